#!/usr/bin/env bash
# Two threads beside one busy process (issue 13, "graceful under load"):
# one `yes > /dev/null` runs for the whole measurement while triax_bench times
# the same dense tiled sample on one thread and with the thread governor
# (`--threads auto`, two threads allowed), interleaved, the order rotating
# from round to round (round 1: auto, 1; round 2: 1, auto; with BENCH_B the
# three rotate, so use a multiple of 3 rounds). Prints each round, the medians
# and the median of the rounds' ratios auto / one.
#
# Usage: bench/beside_busy.sh [ROUNDS [STEPS [TILE]]]   (defaults 8 12000 3x2x2)
# env BENCH: the triax_bench binary (default: the catkin build's); its
#   directory is the LD_LIBRARY_PATH of its runs (triax_bench has a RUNPATH,
#   which LD_LIBRARY_PATH overrides), so a directory holding a copied
#   triax_bench and libvt_*.so times that build. Relative paths are taken
#   from the repository's root.
# env BENCH_B: a second build's triax_bench, timed `auto` in the same rounds
#   (an A/B of two governors; the order rotates over one, auto, auto B).
# env BUSY_CPU: pin the busy process to that CPU (taskset): the timed runs'
#   one thread then runs on the other CPU in every run, so the vCPUs' speed
#   difference (up to 37 % on this host) does not fall at random on one or
#   auto.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=median.sh
source bench/median.sh
ROUNDS=${1:-8}
STEPS=${2:-12000}
TILE=${3:-3x2x2}
BENCH=${BENCH:-build/devel/lib/virtual_triaxial/triax_bench}
[[ "$ROUNDS" =~ ^[1-9][0-9]*$ ]] || { echo "beside_busy: ROUNDS must be a whole number >= 1, got '$ROUNDS'" >&2; exit 2; }
[[ "$STEPS" =~ ^[1-9][0-9]*$ ]] || { echo "beside_busy: STEPS must be a whole number >= 1, got '$STEPS'" >&2; exit 2; }
[[ -x "$BENCH" ]] || { echo "beside_busy: no triax_bench at $BENCH (build first: tests/run_tests.sh)" >&2; exit 2; }

if [[ -n "${BUSY_CPU:-}" ]]; then
  [[ "$BUSY_CPU" =~ ^[0-9]+$ && "$BUSY_CPU" -lt $(nproc) ]] || { echo "beside_busy: BUSY_CPU must be a CPU number below $(nproc), got '$BUSY_CPU'" >&2; exit 2; }
  taskset -c "$BUSY_CPU" yes > /dev/null &
else
  yes > /dev/null &
fi
BUSY=$!
trap 'kill $BUSY 2>/dev/null || true' EXIT

run() {  # $1 = binary, $2 = 1 | auto; prints "us threads-line"
  local out
  out=$(LD_LIBRARY_PATH="$(dirname "$1")" "$1" --sample config/samples/dense_1000.h5 --tile "$TILE" --sort-sample --steps "$STEPS" --threads "$2" 2>&1) ||
    { echo "beside_busy: $1 --threads $2 failed:" >&2; tail -5 <<<"$out" >&2; return 1; }
  grep -q '^us_per_particle_step: [0-9]' <<<"$out" || { echo "beside_busy: $1 printed no us_per_particle_step" >&2; return 1; }
  echo "$(sed -n 's/^us_per_particle_step: //p' <<<"$out") $(sed -n 's/^threads: //p' <<<"$out")"
}

echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), one \`yes > /dev/null\` beside${BUSY_CPU:+ (pinned to CPU $BUSY_CPU)}; load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# $BENCH --sample config/samples/dense_1000.h5 --tile $TILE --sort-sample --steps $STEPS --threads 1|auto"
[[ -z "${BENCH_B:-}" || -x "$BENCH_B" ]] || { echo "beside_busy: BENCH_B=$BENCH_B is not executable" >&2; exit 2; }
[[ -n "${BENCH_B:-}" ]] && echo "# auto B: $BENCH_B"
echo "round  one      auto     auto/one  ${BENCH_B:+auto-B   B/one     }auto's threads${BENCH_B:+ | B threads}"
ones=() autos=() ratios=() bs=() bratios=()
for ((r = 1; r <= ROUNDS; ++r)); do
  jobs=("1" "auto")
  [[ -n "${BENCH_B:-}" ]] && jobs+=("B")
  declare -A got=()
  for ((k = 0; k < ${#jobs[@]}; ++k)); do
    j=${jobs[$(((k + r) % ${#jobs[@]}))]}
    case $j in
      1) got[1]=$(run "$BENCH" 1) || exit 1 ;;
      auto) got[auto]=$(run "$BENCH" auto) || exit 1 ;;
      B) got[B]=$(run "$BENCH_B" auto) || exit 1 ;;
    esac
  done
  o=${got[1]%% *} a=${got[auto]%% *}
  ratio=$(awk -v a="$a" -v o="$o" 'BEGIN { printf "%.3f", a / o }')
  ones+=("$o") autos+=("$a") ratios+=("$ratio")
  extra="" btail=""
  if [[ -n "${BENCH_B:-}" ]]; then
    b=${got[B]%% *}
    bratio=$(awk -v b="$b" -v o="$o" 'BEGIN { printf "%.3f", b / o }')
    bs+=("$b") bratios+=("$bratio")
    extra=$(printf '%-8s %-9s ' "$b" "$bratio") btail=" | ${got[B]#* }"
  fi
  printf '%-6s %-8s %-8s %-9s %s%s%s\n' "$r" "$o" "$a" "$ratio" "$extra" "${got[auto]#* }" "$btail"
  unset got
done
slower() { printf '%s\n' "$@" | awk '$1 > 1 { n++ } END { print n + 0 }'; }
echo "median one $(median_of "${ones[@]}"), auto $(median_of "${autos[@]}") us per particle-step; auto/one $(median_of "${ratios[@]}") (median of the rounds' ratios), slower than one in $(slower "${ratios[@]}") of $ROUNDS rounds"
if [[ -n "${BENCH_B:-}" ]]; then
  echo "median auto B $(median_of "${bs[@]}") us; B/one $(median_of "${bratios[@]}"), slower than one in $(slower "${bratios[@]}") of $ROUNDS rounds"
fi
