#!/usr/bin/env bash
# What the cut between the two threads' runs costs, in the host's normal
# phases and in its slow ones (session 34, bench/results/2026-12-04-s34/
# experiments.txt E7, E10): each round runs the tiled sample on one thread
# and on two, then the same number of particles tiled as a column (Kx1x1,
# K the product of TILE's factors) on two threads, whose runs meet at
# planes of a smaller cross-section when TILE's is larger than one tile
# (the cut: triax_bench's cut_particles, the particles with a pair
# crossing the runs). Prints per round the costs (us per
# particle-step), the cut particles and the two speed-ups over TILE's
# one-thread cost, then the medians over the normal and the slow rounds and
# the slow phases' extra cost per cut particle and step for both tilings,
#   extra = (two_slow - two_normal) [us] x N / cut_normal x 1000  [ns]
# (medians of each class; cut_normal: the normal rounds' median cut).
# A round is slow when the median one-thread cost over all rounds over
# the round's own two-thread cost of TILE is below SLOW_BELOW (default
# 1.7): the slow phases leave one thread alone (E5), so the median of all
# one-thread runs is the steadier yardstick.
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
[[ "${SLOW_BELOW}" =~ ^[0-9]+(\.[0-9]+)?$ ]] || { echo "cut_cost: SLOW_BELOW must be a number, not '${SLOW_BELOW}'" >&2; exit 2; }
work="$(mktemp -d)"; trap 'rm -rf "${work}"' EXIT
run() {  # TILE THREADS OUT
  "${BIN}" --sample "${SAMPLE}" --tile "$1" --sort-sample --threads "$2" --steps "${STEPS}" >"$3" 2>"$3.err" ||
    { echo "cut_cost: triax_bench failed (--tile $1 --threads $2):" >&2; tail -5 "$3.err" >&2; exit 1; }
}
# (called only in plain assignments, so that set -e stops the script when they fail)
key() {  # KEY FILE -> its value; fails when the run printed none
  local v
  v="$(awk -F': ' -v k="$1" '$1 == k { print $2 }' "$2")"
  [[ -n "${v}" ]] || { echo "cut_cost: triax_bench printed no '$1'" >&2; return 1; }
  echo "${v}"
}
cut() {  # FILE -> the particles at the cut; fails when there are none
  local c
  c="$(key cut_particles "$1")"
  ((c > 0)) || { echo "cut_cost: no particle at the cut" >&2; return 1; }
  echo "${c}"
}
echo "# $(date -u '+%F %H:%M UTC'), ${SAMPLE} tiled ${TILE} and ${COLUMN}, slab-sorted, ${STEPS} steps, ${R} rounds, slow: median one / two below ${SLOW_BELOW}"
printf '%-6s %9s %9s %9s %7s %7s %9s %9s\n' round one_us two_us col_two cut col_cut two/one col/one
for ((r = 1; r <= R; ++r)); do
  run "${TILE}" 1 "${work}/one"; run "${TILE}" 2 "${work}/two"; run "${COLUMN}" 2 "${work}/col"
  one="$(key us_per_particle_step "${work}/one")"; two="$(key us_per_particle_step "${work}/two")"
  col="$(key us_per_particle_step "${work}/col")"; c2="$(cut "${work}/two")"; cc="$(cut "${work}/col")"
  np="$(key particles "${work}/two")"
  printf '%-6s %9s %9s %9s %7s %7s %9s %9s\n' "${r}" "${one}" "${two}" "${col}" "${c2}" "${cc}" \
    "$(awk -v a="${one}" -v b="${two}" 'BEGIN { printf "%.3f", a / b }')" \
    "$(awk -v a="${one}" -v b="${col}" 'BEGIN { printf "%.3f", a / b }')"
  echo "${r} ${one} ${two} ${col} ${c2} ${cc} ${np}" >>"${work}/rows"
done
yard="$(awk '{ print $2 }' "${work}/rows" | median)"
# each row with its class, N (normal) or S (slow), appended
awk -v y="${yard}" -v s="${SLOW_BELOW}" '{ print $0, (y / $3 < s) ? "S" : "N" }' "${work}/rows" >"${work}/classed"
med() { awk -v c="$1" -v want="$2" '$8 == want { print $c }' "${work}/classed" | median; }
for phase in N S; do
  name=$([[ ${phase} == N ]] && echo normal || echo slow)
  printf '%-6s %9s %9s %9s %7s %7s   (%s rounds)\n' "${name}" "$(med 2 "${phase}")" "$(med 3 "${phase}")" \
    "$(med 4 "${phase}")" "$(med 5 "${phase}")" "$(med 6 "${phase}")" "$(awk -v w="${phase}" '$8 == w' "${work}/classed" | wc -l)"
done
n="$(awk 'NR == 1 { print $7 }' "${work}/rows")"
extra() {  # COST_COLUMN CUT_COLUMN -> ns per cut particle and step ("-" without both classes)
  local a b c
  a="$(med "$1" N)"; b="$(med "$1" S)"; c="$(med "$2" N)"
  [[ "${a}" != - && "${b}" != - ]] || { echo -; return; }
  awk -v a="${a}" -v b="${b}" -v c="${c}" -v n="${n}" 'BEGIN { printf "%.0f", (b - a) * n / c * 1000 }'
}
echo "slow phases' extra per cut particle and step [ns]: ${TILE} $(extra 3 5), ${COLUMN} $(extra 4 6)"
