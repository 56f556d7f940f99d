#!/usr/bin/env bash
# per round: rt, 2T runs of each DIR (order rotating), rt; costs
cd /work/main
R=$1; shift; D=("$@"); K=${#D[@]}; S=${STEPS:-1000}
H=/root/s40/base/host_scaling
rt() { $H --pingpong --rounds 1 | awk '/^median_round_trip_ns/ {printf "%.0f", $2}'; }
run() { LD_LIBRARY_PATH=$1 $1/triax_bench --sample ${SAMPLE:-config/samples/dense_1000.h5} --tile ${TILE:-3x2x2} --sort-sample --threads ${THREADS:-2} --steps $S 2>/dev/null | awk '/^us_per_particle_step:/{print $2}'; }
echo "round rt_b rt_a ${D[*]}"
for ((r=1;r<=R;++r)); do
  a=$(rt); line=()
  for ((k=0;k<K;++k)); do idx=$(((k + r) % K)); line[idx]=$(run ${D[idx]}); done
  b=$(rt)
  echo "$r $a $b ${line[*]}"
done
