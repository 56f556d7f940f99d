#!/usr/bin/env bash
# Session 36's interleaved A/B of whole builds with the host's placement read around each round
# (not part of the project's tools; kept as the record of how the ab_*.txt and alternate_*.txt files
# were made). Each DIR holds a build's triax_bench and libvt_*.so. Per round: the round trip of a
# cache line between CPUs 0 and 1 (host_scaling --pingpong), each build once (order rotating), the
# round trip again; prints "round rt_before rt_after value..." with value the run's KEY.
#   ab_rt_rounds.sh ROUNDS DIR...
#   RUN_ARGS="--threads 2" TILE=3x2x2 STEPS=1000 ab_rt_rounds.sh 40 /tmp/ab/cur /tmp/ab/ghost   (ab_*.txt)
#   RUN_ARGS="--alternate 1,2 --block 200" KEY=alternate_speedup ab_rt_rounds.sh 16 A B  (alternate_*.txt)
#   SAMPLE=config/samples/dense_1000_spheroid.h5 ...                                    (spheroids)
# ab_rt_summary.py FILE NAME... gives the medians near (both readings < 250 ns) and far (>= 250).
R=$1; shift; DIRS=("$@"); K=${#DIRS[@]}
HS=/work/main/build/devel/lib/virtual_triaxial/host_scaling
rt() { $HS --pingpong --rounds 1 | awk '/median_round_trip_ns/ {print $2}'; }
run() {
  # shellcheck disable=SC2086
  LD_LIBRARY_PATH="$1" "$1/triax_bench" --sample "${SAMPLE:-/work/main/config/samples/dense_1000.h5}" --sort-sample \
    --tile "${TILE:-3x2x2}" ${RUN_ARGS:---threads 2} --steps "${STEPS:-1000}" 2>&1 |
    awk -v k="${KEY:-us_per_particle_step}" -F': ' '$1 == k { split($2, a, " "); print a[1] }'
}
for r in $(seq "$R"); do
  x=$(rt); line=()
  for k in $(seq 0 $((K - 1))); do idx=$(((k + r) % K)); line[idx]=$(run "${DIRS[idx]}"); done
  y=$(rt)
  echo "$r $x $y ${line[*]}"
done
