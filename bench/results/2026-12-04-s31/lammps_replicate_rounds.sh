#!/bin/bash
# LAMMPS 1 / 2 ranks and ours 1 / 2 threads on dense_1000.h5 tiled 3x2x2 (12 000 spheres), interleaved
B=/work/main/build/devel/lib/virtual_triaxial/triax_bench
S=/work/main/config/samples/dense_1000.h5
for r in $(seq $1); do
  l1=$(lmp -in in.12k -log /tmp/l12/a.log -screen none >/dev/null; awk '/Loop time/ {print $4}' /tmp/l12/a.log)
  l2=$(mpirun --allow-run-as-root --oversubscribe -np 2 lmp -in in.12k -log /tmp/l12/b.log -screen none >/dev/null; awk '/Loop time/ {print $4}' /tmp/l12/b.log)
  o1=$($B --sample $S --tile 3x2x2 --sort-sample --threads 1 --steps 1500 2>&1 | awk -F': ' '$1=="us_per_particle_step"{print $2}')
  o2=$($B --sample $S --tile 3x2x2 --sort-sample --threads 2 --steps 1500 2>&1 | awk -F': ' '$1=="us_per_particle_step"{print $2}')
  echo "$r lammps_1 $l1 lammps_2 $l2 ratio_l $(echo "$l1/$l2" | bc -l | cut -c1-5) ours_1 $o1 ours_2 $o2 ratio_o $(echo "$o1/$o2" | bc -l | cut -c1-5) load $(cut -d' ' -f1 /proc/loadavg)"
done
