#!/usr/bin/env bash
# bench/two_thread_ceiling.sh against closed forms, with a fake triax_bench
# (BIN) and a fake host_scaling (HOST) whose numbers depend on the round
# (r = 1..8):
#   one thread     0.080 every round
#   two threads    0.040 0.050 0.044 0.064 0.042 0.055 0.045 0.0625
#   ours = one / two, to 3 decimals:
#                  2.000 1.600 1.818 1.250 1.905 1.455 1.778 1.280
#   round trip before / after the two-thread run [ns]:
#                  120/125 500/510 110/115 490/495 130/128 125/505 500/120 250/250
# With RT_SLOW = 250: near (both below) rounds 1, 3, 5, median 1.905; far
# (both at or above; 250 is far) rounds 2, 4, 8, median 1.280; rounds 6
# and 7 changed during the run and count in neither. All rounds: median
# (1.600 + 1.778) / 2 = 1.689. Classing by the reading before the run
# alone, by the one after alone, or near as "at or below", would each put
# a fourth round among the near ones. The steal column is the kernels'
# mean (0.10), not counting the pingpong line. RT_SLOW=600 makes every
# round near (median 1.689, 8 rounds, far none); RT_SLOW=x is refused (exit
# 2). The round trip is read exactly twice a round, around the two-thread
# run.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "${tmp}"' EXIT
cat >"${tmp}/triax_bench" <<FAKE
#!/usr/bin/env bash
threads=""
while ((\$#)); do case "\$1" in --threads) threads=\$2; shift 2;; *) shift;; esac; done
echo "run \${threads}" >>"${tmp}/calls"
if [[ \${threads} == 1 ]]; then echo x >>"${tmp}/rounds"; fi
r=\$(wc -l <"${tmp}/rounds")
pick() { shift "\${r}"; echo "\$1"; }  # the r-th of the arguments after the first
if [[ \${threads} == 1 ]]; then echo "us_per_particle_step: 0.080"
else echo "us_per_particle_step: \$(pick - 0.040 0.050 0.044 0.064 0.042 0.055 0.045 0.0625)"; fi
FAKE
cat >"${tmp}/host_scaling" <<FAKE
#!/usr/bin/env bash
if [[ "\$1" == --pingpong ]]; then
  echo "pingpong" >>"${tmp}/calls"
  echo x >>"${tmp}/readings"
  n=\$(wc -l <"${tmp}/readings")
  pick() { shift "\${n}"; echo "\$1"; }
  printf '1      pingpong %8.1f ns round trip of a cache line between CPUs 0 and 1\n' \
    "\$(pick - 120 125 500 510 110 115 490 495 130 128 125 505 500 120 250 250)"
  exit 0
fi
for k in compute fma sync syncnp syncblk cache memory; do
  echo "1      \${k}   0.1000   0.1000   0.1000   0.1000 1.00/1.00  2.000    0.10"
done
echo "1      pingpong    120.0 ns round trip of a cache line between CPUs 0 and 1"
FAKE
chmod +x "${tmp}/triax_bench" "${tmp}/host_scaling"
fail=0
run() { BIN="${tmp}/triax_bench" HOST="${tmp}/host_scaling" "${ROOT}/bench/two_thread_ceiling.sh" 8 3x2x2 10 2>&1; }
out="$(run)"
echo "${out}"
grep -qE "^1 .* 0\.10 +120/125 +0\.080 +0\.040 +2\.000 " <<<"${out}" ||
  { echo "FAIL: round 1's line (steal 0.10 of the kernels alone, 120/125, 2.000)"; fail=1; }
grep -q "^median .* 1.689 " <<<"${out}" || { echo "FAIL: the median over all rounds is not 1.689"; fail=1; }
grep -q "below 250 ns: median 1.905 (3 rounds)" <<<"${out}" || { echo "FAIL: near rounds (1, 3, 5): 1.905"; fail=1; }
grep -q "at or above 250 ns: median 1.280 (3 rounds)" <<<"${out}" || { echo "FAIL: far rounds (2, 4, 8): 1.280"; fail=1; }
# two readings a round, one right before and one right after the two-thread run
expect="$(for r in 1 2 3 4 5 6 7 8; do printf 'run 1\npingpong\nrun 2\npingpong\n'; done)"
[[ "$(cat "${tmp}/calls")" == "${expect}" ]] || { echo "FAIL: the readings are not around the two-thread runs"; fail=1; }
rm -f "${tmp}/rounds" "${tmp}/readings" "${tmp}/calls"
out="$(RT_SLOW=600 run)"
grep -q "below 600 ns: median 1.689 (8 rounds)" <<<"${out}" || { echo "FAIL: RT_SLOW=600 did not make every round near"; fail=1; }
grep -q "at or above 600 ns: median - (0 rounds)" <<<"${out}" || { echo "FAIL: RT_SLOW=600 left a far round"; fail=1; }
rm -f "${tmp}/rounds" "${tmp}/readings" "${tmp}/calls"
set +e
err="$(RT_SLOW=x run)"; rc=$?
set -e
[[ ${rc} == 2 ]] && grep -q "RT_SLOW must be a number" <<<"${err}" || { echo "FAIL: RT_SLOW=x: exit ${rc}, '${err}'"; fail=1; }
((fail == 0)) && echo "PASS"
exit "${fail}"
