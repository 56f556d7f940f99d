#!/usr/bin/env bash
# How fast each CPU runs the DEM step, in interleaved rounds: each round runs
# triax_bench on one thread pinned (taskset) to each CPU this process may use,
# in turn, on the tiled sample. Prints per round every CPU's cost (us per
# particle-step), slow / fast (the dearest CPU's cost over the cheapest's)
# and the ceiling of a team on all of them against one thread on the
# fastest, S = sum_c (1 / cost_c) / max_c (1 / cost_c) (2 when they are
# alike; a two-thread run cannot beat it, whatever the code); then, in the
# same round, a run on all of them (unpinned), its cost, ours = the fastest
# CPU's one-thread cost over it, and ours / S; then the medians. On this
# project's 2-vCPU VM the two have differed by 1.35x at times and been alike
# at others (bench/results/2026-12-04-s30/, E17).
#
#   bench/core_speeds.sh ROUNDS TILE STEPS [SAMPLE]
#   bench/core_speeds.sh 5 3x2x2 1500               # 12 000 dense spheres
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=tile_rounds.sh
source bench/tile_rounds.sh
tile_rounds core_speeds "$@"
# shellcheck source=median.sh
source bench/median.sh
command -v taskset >/dev/null || { echo "core_speeds: taskset (util-linux) not found" >&2; exit 2; }
# the CPUs of this process's affinity list, e.g. "0-1,4" -> 0 1 4
mapfile -t cpus < <(taskset -cp $$ | sed 's/.*: //' | tr ',' '\n' |
  awk -F- '{ if (NF == 2) for (c = $1; c <= $2; ++c) print c; else print $1 }')
# cost CPU: one thread pinned to CPU; cost all: a team on every CPU, unpinned
cost() {
  local pin=(taskset -c "$1") threads=1
  [[ "$1" == all ]] && pin=() && threads=${#cpus[@]}
  "${pin[@]}" "${BIN}" --sample "${SAMPLE}" --tile "${TILE}" --sort-sample --threads "${threads}" --steps "${STEPS}" 2>/dev/null |
    awk '/^us_per_particle_step:/ { print $2 }'
}
echo "# $(date -u '+%F %H:%M UTC'), ${SAMPLE} tiled ${TILE}, slab-sorted, ${STEPS} steps, ${R} rounds, CPUs ${cpus[*]}, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-6s' round; for c in "${cpus[@]}"; do printf ' %9s' "cpu${c}_us"; done
printf ' %9s %9s %9s %9s %9s\n' slow/fast S_cores team_us ours ours/S
work="$(mktemp -d)"; trap 'rm -rf "${work}"' EXIT
for ((r = 1; r <= R; ++r)); do
  line=()
  for c in "${cpus[@]}"; do
    v="$(cost "${c}")"
    [[ -n "${v}" ]] || { echo "core_speeds: triax_bench on cpu ${c} printed no cost" >&2; exit 1; }
    line+=("${v}")
    echo "${v}" >>"${work}/cpu${c}"
  done
  team="$(cost all)"
  [[ -n "${team}" ]] || { echo "core_speeds: triax_bench on ${#cpus[@]} threads printed no cost" >&2; exit 1; }
  # lo: the fastest CPU's cost; S = lo * sum 1/cost; ours = lo / team
  read -r ratio ceiling ours share < <(printf '%s\n' "${line[@]}" |
    awk -v t="${team}" '{ c[NR] = $1 } END { lo = c[1]; hi = c[1]; s = 0
          for (i = 1; i <= NR; ++i) { if (c[i] < lo) lo = c[i]; if (c[i] > hi) hi = c[i]; s += 1 / c[i] }
          printf "%.3f %.3f %.3f %.3f\n", hi / lo, s * lo, lo / t, lo / t / (s * lo) }')
  for k in ratio ceiling team ours share; do echo "${!k}" >>"${work}/${k}"; done
  printf '%-6s' "${r}"; printf ' %9s' "${line[@]}"; printf ' %9s %9s %9s %9s %9s\n' "${ratio}" "${ceiling}" "${team}" "${ours}" "${share}"
done
printf '%-6s' median; for c in "${cpus[@]}"; do printf ' %9s' "$(median <"${work}/cpu${c}")"; done
for k in ratio ceiling team ours share; do printf ' %9s' "$(median <"${work}/${k}")"; done; echo
