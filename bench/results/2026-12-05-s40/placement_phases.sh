#!/usr/bin/env bash
# per round: rt before, 1T and 2T phases (us per step), rt after
cd /work/main
B=build/devel/lib/virtual_triaxial
S=1500
rt() { $B/host_scaling --pingpong --rounds 1 | awk '/^median_round_trip_ns/ {printf "%.0f", $2}'; }
ph() { awk -v steps=$S -v k="$1" '$1==k { for(i=2;i<NF;i+=2) printf "%s=%.1f ", $i, 1e6*$(i+1)/steps }'; }
printf 'round rt_b rt_a one_us two_us ratio | t0 phases | t1 phases | imb steady\n'
for ((r=1;r<=${1:-20};++r)); do
  o1=$($B/triax_bench --sample config/samples/dense_1000.h5 --tile 3x2x2 --sort-sample --threads 1 --steps $S 2>/dev/null)
  a=$(rt)
  o2=$($B/triax_bench --sample config/samples/dense_1000.h5 --tile 3x2x2 --sort-sample --threads 2 --steps $S 2>/dev/null)
  b=$(rt)
  one=$(awk '/^us_per_particle_step:/{print $2}' <<<"$o1"); two=$(awk '/^us_per_particle_step:/{print $2}' <<<"$o2")
  printf '%s %s %s %s %s %.3f | %s| %s| %s\n' $r $a $b $one $two $(awk -v a=$one -v b=$two 'BEGIN{print a/b}') \
   "$(ph phase_seconds_thread_0: <<<"$o2")" "$(ph phase_seconds_thread_1: <<<"$o2")" \
   "$(awk -v steps=$S '$1=="region_waits_forces:"{printf "%.1f %.1f", 1e6*$3/steps, 1e6*$5/steps}' <<<"$o2") p10/50/90 $(awk '$1=="step_us:"{print $5, $3, $7}' <<<"$o2")"
done
