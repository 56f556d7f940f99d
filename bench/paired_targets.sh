#!/usr/bin/env bash
# Issue 13's ratio targets measured in turns inside one process
# (triax_bench --alternate / --pair-tile, bench/block_turns.h), so that the
# host's drift over seconds hits both sides of each ratio alike; whole runs
# interleaved in rounds (bench/run_matrix.sh) leave the ratio to the drift
# between runs, which on this VM moves one thread's cost by +-25 %.
# Each round runs six cases and prints each one's median over its pairs of
# blocks (quartiles in brackets):
#   two / one thread     12 000 spheres (3x2x2) and 10^5 (5x5x4)
#   x_N1                 10^5 against 12 000 spheres, one thread and two
#   spheroid / sphere    12 000 (3x2x2) each, one thread and two
# then the medians over the rounds. Samples: config/samples/dense_1000.h5
# and dense_1000_spheroid.h5, slab-sorted, the state at the start that
# of bench/run_matrix.sh (same samples and shear rate; with --alternate
# the one simulation shears through 2 x STEPS steps, the pairs through
# STEPS each).
#
#   bench/paired_targets.sh ROUNDS
#   STEPS=1000 BLOCK=200 STEPS_1E5=600 BLOCK_1E5=100 bench/paired_targets.sh 5
#   PIN_ONE="0 1" bench/paired_targets.sh 6
# PIN_ONE: CPUs to pin the one-thread cases to (taskset), each in turn and
# reported apart and pooled ("x_N1 one" and "spheroid/sphere one" then
# median all the CPUs' rounds); unset: unpinned, where the kernel may move
# the thread between vCPUs that at times differ by 1.3-1.5x in speed
# (bench/core_speeds.sh).
# The cases on two threads (two / one, x_N1 two, spheroid / sphere two) run
# between two readings of the round trip of a cache line between the two
# CPUs (bench/round_trip.sh, printed as [before/after] ns; skipped when
# host_scaling is not built): about 95-145 ns with the host's vCPUs near
# each other, 465-535 ns far apart, where two threads lose (session 35).
# After the medians over all rounds, each such case's median over the
# rounds with both readings below RT_SLOW ns (default 250), "near".
# STEPS: steps of each side at 12 000 and of x_N1 (default 1000, as the
# matrix), in turns of BLOCK steps (default 200); STEPS_1E5: of two / one
# thread at 10^5 (default 600), in turns of BLOCK_1E5 (default 100). Short
# turns bias the ratios: a switch to two threads costs about 1.6 ms (the
# threads' runs re-cut, thread_runs.h), and a 12 000-particle turn after a
# 10^5 one starts with its data out of the caches (20-step turns gave two /
# one 1.21 and x_N1 on two threads 0.85).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=median.sh
source bench/median.sh
# shellcheck source=tile_rounds.sh
source bench/tile_rounds.sh
if ! (($# == 1)) || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then usage_from_header; fi
R=$1
BIN="${BIN:-build/devel/lib/virtual_triaxial/triax_bench}"
STEPS="${STEPS:-1000}"; STEPS_1E5="${STEPS_1E5:-600}"; BLOCK="${BLOCK:-200}"; BLOCK_1E5="${BLOCK_1E5:-100}"
for v in STEPS STEPS_1E5 BLOCK BLOCK_1E5; do
  [[ "${!v}" =~ ^[1-9][0-9]*$ ]] || { echo "paired_targets: ${v} must be a whole number >= 1, not '${!v}'" >&2; exit 2; }
done
[[ -x "${BIN}" ]] || { echo "paired_targets: ${BIN} not built" >&2; exit 2; }
# shellcheck source=round_trip.sh
source bench/round_trip.sh
round_trip_setup paired_targets
SPH=config/samples/dense_1000.h5
SPD=config/samples/dense_1000_spheroid.h5
PIN_ONE="${PIN_ONE:-}"
for c in ${PIN_ONE}; do
  [[ "${c}" =~ ^[0-9]+$ ]] || { echo "paired_targets: PIN_ONE must list CPU numbers, not '${c}'" >&2; exit 2; }
done
cases=() args=() pins=() pooled=() twos=()
# add_case NAME ARGS ONE_THREAD: a case, or with PIN_ONE one per CPU for a
# one-thread case; every other case runs two threads (twos: 1)
add_case() {
  if [[ "$3" == 1 && -n "${PIN_ONE}" ]]; then
    for c in ${PIN_ONE}; do cases+=("$1 cpu${c}"); args+=("$2"); pins+=("${c}"); pooled+=("$1"); twos+=(0); done
  else
    cases+=("$1"); args+=("$2"); pins+=(""); pooled+=(""); twos+=("$((1 - $3))")
  fi
}
add_case "two/one 12000" "--tile 3x2x2 --alternate 1,2 --steps ${STEPS}" 0
add_case "two/one 1e5" "--tile 5x5x4 --alternate 1,2 --steps ${STEPS_1E5} --block ${BLOCK_1E5}" 0
add_case "x_N1 one" "--tile 3x2x2 --threads 1 --pair-tile 5x5x4 --steps ${STEPS}" 1
add_case "x_N1 two" "--tile 3x2x2 --threads 2 --pair-tile 5x5x4 --steps ${STEPS}" 0
add_case "spheroid/sphere one" "--tile 3x2x2 --threads 1 --pair-tile 3x2x2 --pair-sample ${SPD} --steps ${STEPS}" 1
add_case "spheroid/sphere two" "--tile 3x2x2 --threads 2 --pair-tile 3x2x2 --pair-sample ${SPD} --steps ${STEPS}" 0
pinning="unpinned"
[[ -n "${PIN_ONE}" ]] && pinning="pinned to CPUs ${PIN_ONE}"
echo "# $(date -u '+%F %H:%M UTC'), ${R} rounds, turns of ${BLOCK} steps (two / one at 10^5: ${BLOCK_1E5}), one-thread cases ${pinning}, load average $(cut -d' ' -f1-3 /proc/loadavg)"
declare -A med pool near
for ((r = 1; r <= R; ++r)); do
  line="round ${r}:"
  for k in "${!cases[@]}"; do
    run=("${BIN}")
    [[ -n "${pins[k]}" ]] && run=(taskset -c "${pins[k]}" "${BIN}")
    two=${twos[k]}
    rb=""; ra=""
    ((two)) && rb="$(round_trip || true)"
    # shellcheck disable=SC2086
    out="$("${run[@]}" --sample "${SPH}" --sort-sample --block "${BLOCK}" ${args[k]} 2>/dev/null)" ||
      { echo "paired_targets: triax_bench failed on '${cases[k]}'" >&2; exit 1; }
    ((two)) && ra="$(round_trip || true)"
    v="$(awk '/^(alternate_speedup|pair_cost_ratio):/ { printf "%s %s %s", $2, $10, $11 }' <<<"${out}" | tr -d ')')"
    read -r m q1 q3 <<<"${v}"
    [[ -n "${m}" ]] || { echo "paired_targets: no ratio from '${cases[k]}'" >&2; exit 1; }
    med[${k}]+="${m} "
    [[ -n "${pooled[k]}" ]] && pool[${pooled[k]}]+="${m} "
    line+="  ${cases[k]} ${m} (${q1}-${q3})"
    if [[ -n "${rb}" && -n "${ra}" ]]; then
      line+=" [${rb%.*}/${ra%.*}]"
      near_rt "${rb}" "${ra}" && near[${k}]+="${m} "
    elif ((two)) && [[ -x "${HOST}" ]]; then
      echo "paired_targets: warning: ${HOST} --pingpong gave no round trip around '${cases[k]}'" >&2
    fi
  done
  echo "${line}"
done
echo "medians over ${R} rounds:"
for k in "${!cases[@]}"; do
  # shellcheck disable=SC2086
  printf '  %-32s %s\n' "${cases[k]}" "$(median_of ${med[${k}]})"
done
# the pooled one-thread cases, in the order of the cases (each once)
declare -A shown
for k in "${!cases[@]}"; do
  name="${pooled[k]}"
  if [[ -n "${name}" && -z "${shown[${name}]:-}" ]]; then
    shown[${name}]=1
    # shellcheck disable=SC2086
    printf '  %-32s %s\n' "${name}, every CPU" "$(median_of ${pool[${name}]})"
  fi
done
# the two-thread cases over the rounds with the vCPUs near
if [[ -x "${HOST}" ]]; then
  echo "medians over the rounds with both round trips below ${RT_SLOW} ns:"
  for k in "${!cases[@]}"; do
    ((twos[k])) || continue
    # shellcheck disable=SC2086
    printf '  %-32s %s (%s rounds)\n' "${cases[k]}" "$(median_of ${near[${k}]:-})" "$(wc -w <<<"${near[${k}]:-}")"
  done
fi
