#!/usr/bin/env bash
# Do two one-thread runs slow each other down? Each round times triax_bench on
# one thread pinned to CPU 0 alone, pinned to CPU 1 alone, then both at once
# (one per CPU), and prints the per-round costs and the medians of
# together / alone per CPU. The two runs share nothing but the machine
# (caches, memory bandwidth, the host), so a ratio above 1 is what two
# threads of one run lose to that sharing before any cost of their own
# (barriers, completions, imbalance). The two runs start together, but their
# untimed set-ups (loading and tiling the sample) may end apart, so the
# timed windows can overlap by less than the whole.
#
#   bench/side_by_side_contention.sh ROUNDS TILE STEPS [SAMPLE]
#   bench/side_by_side_contention.sh 6 3x2x2 3000
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=tile_rounds.sh
source bench/tile_rounds.sh
tile_rounds side_by_side_contention "$@"
command -v taskset >/dev/null || { echo "side_by_side_contention: taskset missing (util-linux)" >&2; exit 2; }
(($(nproc) >= 2)) || { echo "side_by_side_contention: needs 2 CPUs" >&2; exit 2; }
run() { taskset -c "$1" "${BIN}" --sample "${SAMPLE}" --tile "${TILE}" --sort-sample --threads 1 --steps "${STEPS}" 2>/dev/null | awk -F': ' '$1 == "us_per_particle_step" { print $2 }'; }
# shellcheck source=median.sh
source bench/median.sh
work="$(mktemp -d)"; trap 'rm -rf "${work}"' EXIT
echo "# $(date -u '+%F %H:%M UTC'), ${SAMPLE} tiled ${TILE}, ${STEPS} steps, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# round alone_cpu0 alone_cpu1 together_cpu0 together_cpu1 (us per particle-step)"
for ((r = 1; r <= R; ++r)); do
  a0=$(run 0); a1=$(run 1)
  run 0 >"${work}/t0" & p0=$!
  run 1 >"${work}/t1" & p1=$!
  wait "${p0}"; wait "${p1}"
  b0=$(cat "${work}/t0"); b1=$(cat "${work}/t1")
  [[ -n "${a0}" && -n "${a1}" && -n "${b0}" && -n "${b1}" ]] ||
    { echo "side_by_side_contention: triax_bench failed in round ${r}" >&2; exit 1; }
  echo "${r} ${a0} ${a1} ${b0} ${b1}"
done | tee "${work}/rows"
# column K of the rounds' rows (2, 3: alone on CPU 0, 1; 4, 5: together)
column() { awk -v k="$1" '{ print $k }' "${work}/rows"; }
for c in 0 1; do
  echo "cpu${c}: alone median $(column $((c + 2)) | median), together median $(column $((c + 4)) | median)," \
    "together / alone median of rounds $(awk -v a=$((c + 2)) -v b=$((c + 4)) '{ printf "%.4f\n", $b / $a }' "${work}/rows" | median)"
done
