#!/usr/bin/env bash
# rounds: rt, each dir's two/one (--alternate 1,2) in rotating order, rt
R=$1; shift; DIRS=("$@"); K=${#DIRS[@]}
HS=/work/main/build/devel/lib/virtual_triaxial/host_scaling
rt() { $HS --pingpong --rounds 1 | awk '/median_round_trip_ns/ {print $2}'; }
run() { LD_LIBRARY_PATH="$1" "$1/triax_bench" --sample ${SAMPLE:-/work/main/config/samples/dense_1000.h5} --sort-sample --tile ${TILE:-3x2x2} --alternate 1,2 --block 200 --steps ${STEPS:-1000} 2>&1 | awk '/alternate_speedup/ {print $2}'; }
for r in $(seq $R); do
  x=$(rt); line=()
  for k in $(seq 0 $((K - 1))); do idx=$(((k + r) % K)); line[idx]=$(run "${DIRS[idx]}"); done
  y=$(rt)
  echo "$r $x $y ${line[*]}"
done
