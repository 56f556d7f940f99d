#!/usr/bin/env bash
# What the cut between the two threads' runs costs, in the host's normal
# phases and in its slow ones (session 34, bench/results/2026-12-04-s34/
# experiments.txt E7): each round runs the tiled sample on one thread and
# on two, then the same number of particles tiled as a column (Kx1x1, K
# the product of TILE's factors) on two threads, whose runs meet at planes
# of a smaller cross-section (triax_bench's edge_particles + tail_particles:
# the particles with a pair crossing the runs). Prints per round the costs
# (us per particle-step), the cut particles and the two speed-ups (the
# column's over TILE's one-thread cost), then the medians over the rounds
# where TILE's two threads gain at least SLOW_BELOW (default 1.7: "normal")
# and over the others ("slow"), and the slow phases' extra cost per cut
# particle and step, (two_slow - two_normal) N / cut [ns], for both tilings.
#
#   bench/cut_cost.sh ROUNDS TILE STEPS [SAMPLE]
#   bench/cut_cost.sh 20 3x2x2 2000        # 12 000 dense spheres against 12x1x1
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=tile_rounds.sh
source bench/tile_rounds.sh
tile_rounds cut_cost "$@"
# shellcheck source=median.sh
source bench/median.sh
[[ "${TILE}" =~ ^([1-9][0-9]*)x([1-9][0-9]*)x([1-9][0-9]*)$ ]] ||
  { echo "cut_cost: TILE must be KxKyKz (three factors), not '${TILE}'" >&2; exit 2; }
COLUMN="$((BASH_REMATCH[1] * BASH_REMATCH[2] * BASH_REMATCH[3]))x1x1"
SLOW_BELOW="${SLOW_BELOW:-1.7}"
work="$(mktemp -d)"; trap 'rm -rf "${work}"' EXIT
run() {  # TILE THREADS OUT
  "${BIN}" --sample "${SAMPLE}" --tile "$1" --sort-sample --threads "$2" --steps "${STEPS}" >"$3" 2>/dev/null ||
    { echo "cut_cost: triax_bench failed (--tile $1 --threads $2)" >&2; exit 1; }
}
key() { awk -F': ' -v k="$1" '$1 == k { print $2 }' "$2"; }
cut() { echo $(($(key edge_particles "$1") + $(key tail_particles "$1"))); }
echo "# $(date -u '+%F %H:%M UTC'), ${SAMPLE} tiled ${TILE} and ${COLUMN}, slab-sorted, ${STEPS} steps, ${R} rounds, slow: two / one below ${SLOW_BELOW}"
printf '%-6s %9s %9s %9s %7s %7s %9s %9s\n' round one_us two_us col_two cut col_cut two/one col/one
for ((r = 1; r <= R; ++r)); do
  run "${TILE}" 1 "${work}/one"; run "${TILE}" 2 "${work}/two"; run "${COLUMN}" 2 "${work}/col"
  one="$(key us_per_particle_step "${work}/one")"; two="$(key us_per_particle_step "${work}/two")"
  col="$(key us_per_particle_step "${work}/col")"
  printf '%-6s %9s %9s %9s %7s %7s %9s %9s\n' "${r}" "${one}" "${two}" "${col}" "$(cut "${work}/two")" \
    "$(cut "${work}/col")" "$(awk -v a="${one}" -v b="${two}" 'BEGIN { printf "%.3f", a / b }')" \
    "$(awk -v a="${one}" -v b="${col}" 'BEGIN { printf "%.3f", a / b }')"
  echo "${r} ${one} ${two} ${col} $(cut "${work}/two") $(cut "${work}/col") $(key particles "${work}/two")" >>"${work}/rows"
done
# medians of column C over the normal (N) or slow (S) rounds
med() { awk -v c="$1" -v want="$2" -v s="${SLOW_BELOW}" '{ slow = ($2 / $3 < s) ? "S" : "N"; if (slow == want) print $c }' "${work}/rows" | median; }
for phase in N S; do
  name=$([[ ${phase} == N ]] && echo normal || echo slow)
  count="$(awk -v want="${phase}" -v s="${SLOW_BELOW}" '{ if ((($2 / $3 < s) ? "S" : "N") == want) n++ } END { print n + 0 }' "${work}/rows")"
  printf '%-6s %9s %9s %9s %7s %7s   (%s rounds)\n' "${name}" "$(med 2 "${phase}")" "$(med 3 "${phase}")" "$(med 4 "${phase}")" \
    "$(med 5 "${phase}")" "$(med 6 "${phase}")" "${count}"
done
n="$(awk 'NR == 1 { print $7 }' "${work}/rows")"
extra() {  # COST_COLUMN CUT_COLUMN -> ns per cut particle and step
  local a b c
  a="$(med "$1" N)"; b="$(med "$1" S)"; c="$(med "$2" N)"
  [[ "${a}" != - && "${b}" != - ]] || { echo -; return; }
  awk -v a="${a}" -v b="${b}" -v c="${c}" -v n="${n}" 'BEGIN { printf "%.0f", (b - a) * n / c * 1000 }'
}
echo "slow phases' extra per cut particle and step [ns]: ${TILE} $(extra 3 5), ${COLUMN} $(extra 4 6)"
