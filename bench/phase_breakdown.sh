#!/usr/bin/env bash
# Where the time of a step goes on one thread and on two (triax_bench's
# phase timers, dem/phase_times.h), in interleaved rounds: each round times
# one thread, then two, on the same tiled sample. Prints, per thread count,
# the medians over the rounds of each thread's microseconds per step in
# each phase (prepare, pairs, integrate) and outside its own
# work inside the parallel regions (waits: forming the team, barriers,
# the other thread's lead), the two-thread waits split into imbalance (and
# its steady part) and overhead, and the median of the rounds' speed-ups.
#
#   bench/phase_breakdown.sh ROUNDS TILE STEPS [SAMPLE]
#   bench/phase_breakdown.sh 6 3x2x2 3000            # 12 000 dense spheres
#   bench/phase_breakdown.sh 4 5x5x4 400             # 100 000
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=tile_rounds.sh
source bench/tile_rounds.sh
tile_rounds phase_breakdown "$@"
# shellcheck source=median.sh
source bench/median.sh
work="$(mktemp -d)"; trap 'rm -rf "${work}"' EXIT
echo "# $(date -u '+%F %H:%M UTC'), ${SAMPLE} tiled ${TILE}, slab-sorted, ${STEPS} steps, ${R} rounds, load average $(cut -d' ' -f1-3 /proc/loadavg)"
for ((r = 1; r <= R; ++r)); do
  for t in 1 2; do
    "${BIN}" --sample "${SAMPLE}" --tile "${TILE}" --sort-sample --threads "${t}" --steps "${STEPS}" >"${work}/${t}_${r}" 2>/dev/null ||
      { echo "phase_breakdown: triax_bench failed" >&2; exit 1; }
  done
done
# per round: column COL (1-based) of the file of T threads, or phase PHASE of thread TH in us per step
col() { for ((r = 1; r <= R; ++r)); do awk -F': ' -v k="$2" '$1 == k { print $2 }' "${work}/$1_${r}"; done; }
phase_us() {
  for ((r = 1; r <= R; ++r)); do
    awk -v k="phase_seconds_thread_$2:" -v ph="$3" -v steps="${STEPS}" \
      '$1 == k { for (i = 2; i < NF; i += 2) if ($i == ph) printf "%.1f\n", 1e6 * $(i + 1) / steps }' "${work}/$1_${r}"
  done
}
phases=(prepare pairs integrate waits)
echo "particles $(col 1 particles | head -1); microseconds per step, medians of ${R} rounds"
printf '%-10s' threads; printf ' %9s' "${phases[@]}" us/p-step; echo
for t in 1 2; do
  for ((th = 0; th < t; ++th)); do
    printf '%-10s' "${t} (t${th})"
    for ph in "${phases[@]}"; do printf ' %9s' "$(phase_us "${t}" "${th}" "${ph}" | median)"; done
    ((th == 0)) && printf ' %9s' "$(col "${t}" us_per_particle_step | median)"
    echo
  done
done
# the team's mean waits split step by step (phase_times.h): imbalance, its
# steady part (what a better fixed cut would recover) and overhead
waits_us() {
  for ((r = 1; r <= R; ++r)); do
    awk -v k="region_waits_$2:" -v f="$3" -v steps="${STEPS}" \
      '$1 == k { for (i = 2; i < NF; i += 2) if ($i == f) printf "%.1f\n", 1e6 * $(i + 1) / steps }' "${work}/$1_${r}"
  done
}
for region in forces integration; do
  printf 'two threads, %-11s waits: imbalance %s (steady %s), overhead %s us per step\n' "${region}" \
    "$(waits_us 2 "${region}" imbalance | median)" "$(waits_us 2 "${region}" steady | median)" \
    "$(waits_us 2 "${region}" overhead | median)"
done
echo "two threads / one: speed-up, median of the rounds' $(paste <(col 1 us_per_particle_step) <(col 2 us_per_particle_step) |
  awk '{ printf "%.4f\n", $1 / $2 }' | median)x"
