#!/usr/bin/env bash
# per round: 1T (dir A), rt, 2T A and 2T B (order alternating), rt; integrate phase (mean of threads) and cost
cd /work/main
A=$2; Bd=$3; S=${STEPS:-1500}
H=/root/s40/base/host_scaling
rt() { $H --pingpong --rounds 1 | awk '/^median_round_trip_ns/ {printf "%.0f", $2}'; }
run() { LD_LIBRARY_PATH=$1 $1/triax_bench --sample config/samples/dense_1000.h5 --tile ${TILE:-3x2x2} --sort-sample --threads $2 --steps $S 2>/dev/null; }
cost() { awk '/^us_per_particle_step:/{print $2}'; }
integ() { awk -v steps=$S '$1 ~ /^phase_seconds_thread_/ { for(i=2;i<NF;i+=2) if ($i=="integrate") {s+=$(i+1); n++} } END {printf "%.1f", 1e6*s/n/steps}'; }
echo "round rt_b rt_a one_A two_A two_B B/A integ_A integ_B"
for ((r=1;r<=$1;++r)); do
  one=$(run $A 1 | cost)
  a=$(rt)
  if (( r % 2 )); then oa=$(run $A 2); ob=$(run $Bd 2); else ob=$(run $Bd 2); oa=$(run $A 2); fi
  b=$(rt)
  ca=$(cost <<<"$oa"); cb=$(cost <<<"$ob")
  echo "$r $a $b $one $ca $cb $(awk -v a=$ca -v b=$cb 'BEGIN{printf "%.3f", b/a}') $(integ <<<"$oa") $(integ <<<"$ob")"
done
