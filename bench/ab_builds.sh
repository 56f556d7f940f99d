#!/usr/bin/env bash
# Interleaved A/B (or A/B/C...) of whole builds of triax_bench: each DIR holds
# a triax_bench binary and the project's libraries of one build (copy
# build/devel/lib/libvt_*.so and build/devel/lib/virtual_triaxial/triax_bench
# there). Every round runs each build once, in an order that rotates from
# round to round, so a drift of the host's speed hits all alike; prints the
# median and minimum cost per particle-step of each build and the median of
# the rounds' ratios to the first build.
#
#   bench/ab_builds.sh ROUNDS THREADS SAMPLE STEPS DIR_A DIR_B [DIR_C ...]
#   TILE=5x5x4 bench/ab_builds.sh 10 2 config/samples/dense_1000.h5 300 /tmp/base /tmp/new
#
# TILE (default 3x2x2) is passed to --tile; EXTRA holds more triax_bench args.
set -euo pipefail
[[ $# -ge 6 ]] || { sed -n '2,13p' "$0" >&2; exit 2; }
R=$1; T=$2; S=$3; ST=$4; shift 4; DIRS=("$@"); K=${#DIRS[@]}
[[ "${R}" =~ ^[1-9][0-9]*$ ]] || { echo "ab_builds: ROUNDS must be a whole number >= 1" >&2; exit 2; }
for d in "${DIRS[@]}"; do [[ -x "${d}/triax_bench" ]] || { echo "ab_builds: ${d}/triax_bench missing" >&2; exit 2; }; done
# run DIR -> the run's cost (us_per_particle_step; not the median-step cost
# printed beside it, tests/scripts/test_ab_builds.sh)
run() {
  local v
  # shellcheck disable=SC2086
  v="$(LD_LIBRARY_PATH="$1" "$1/triax_bench" --sample "${S}" --tile "${TILE:-3x2x2}" --threads "${T}" --steps "${ST}" ${EXTRA:-} 2>&1 |
    awk -F': ' '$1 == "us_per_particle_step" { print $2 }')"
  [[ -n "${v}" ]] || { echo "ab_builds: $1/triax_bench printed no us_per_particle_step" >&2; exit 1; }
  echo "${v}"
}
for r in $(seq "${R}"); do
  line=()
  for k in $(seq 0 $((K - 1))); do idx=$(((k + r) % K)); line[idx]=$(run "${DIRS[idx]}"); done
  echo "${line[*]}" >&2
  echo "${line[*]}"
done | python3 -c '
import sys, statistics as st
names = sys.argv[1:]
rows = [list(map(float, l.split())) for l in sys.stdin if len(l.split()) == len(names)]
if not rows:
    sys.exit("ab_builds: no complete round")
for k, n in enumerate(names):
    col = [r[k] for r in rows]; q = [r[k] / r[0] for r in rows]
    print("%-24s median %.4f min %.4f  ratio to the first, median %.3f  rounds %d" % (n, st.median(col), min(col), st.median(q), len(rows)))
' "${DIRS[@]}"
