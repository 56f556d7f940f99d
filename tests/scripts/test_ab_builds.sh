#!/usr/bin/env bash
# bench/ab_builds.sh takes each build's run cost (us_per_particle_step), not
# the median-step cost triax_bench prints beside it: two fake builds print
# both (A: mean 0.2000, median step 0.1000; B: 0.1000, 0.0500), so the
# ratio B / A must be 0.500 and A's median 0.2000. Taking the first line
# that matches "us_per_particle_step" (the bug of 07c68e9 to this test)
# gave rows of A's mean against B's median step, ratio 0.250.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "${tmp}"' EXIT
fake() {  # fake DIR MEAN MEDIAN_STEP
  mkdir -p "$1"
  printf '#!/bin/sh\necho "state_fingerprint: 0"\necho "us_per_particle_step_median_step: %s"\necho "us_per_particle_step: %s"\n' "$3" "$2" >"$1/triax_bench"
  chmod +x "$1/triax_bench"
}
fake "${tmp}/a" 0.2000 0.1000
fake "${tmp}/b" 0.1000 0.0500
out="$("${ROOT}/bench/ab_builds.sh" 3 1 none.h5 10 "${tmp}/a" "${tmp}/b" 2>/dev/null)"
echo "${out}"
fail=0
grep -q "^${tmp}/a .*median 0.2000 .*rounds 3$" <<<"${out}" || { echo "FAIL: A's median is not its run cost 0.2000 over 3 rounds"; fail=1; }
grep -q "^${tmp}/b .*median 0.1000 .*ratio to the first, median 0.500 .*rounds 3$" <<<"${out}" ||
  { echo "FAIL: B / A is not 0.500 (run costs)"; fail=1; }
# a build that prints no cost is refused, not averaged
printf '#!/bin/sh\necho nothing\n' >"${tmp}/b/triax_bench"
if "${ROOT}/bench/ab_builds.sh" 2 1 none.h5 10 "${tmp}/a" "${tmp}/b" >/dev/null 2>&1; then
  echo "FAIL: a build without a cost was accepted"; fail=1
fi
((fail == 0)) && echo "PASS"
exit "${fail}"
