#!/usr/bin/env bash
# rounds of: rt, each dir once (order rotates), rt ; prints r rt_before rt_after cost...
R=$1; T=$2; TILE=$3; STEPS=$4; shift 4; DIRS=("$@"); K=${#DIRS[@]}
HS=/work/main/build/devel/lib/virtual_triaxial/host_scaling
rt() { $HS --pingpong --rounds 1 | awk '/median_round_trip_ns/ {print $2}'; }
run() { local d=$1; LD_LIBRARY_PATH="$d" "$d/triax_bench" --sample ${SAMPLE:-/work/main/config/samples/dense_1000.h5} --sort-sample --tile "$TILE" --threads "$T" --steps "$STEPS" ${EXTRA:-} 2>&1 | awk -F': ' '$1=="us_per_particle_step"{print $2}'; }
for r in $(seq $R); do
  x=$(rt); line=()
  for k in $(seq 0 $((K - 1))); do idx=$(((k + r) % K)); line[idx]=$(run "${DIRS[idx]}"); done
  y=$(rt)
  echo "$r $x $y ${line[*]}"
done
