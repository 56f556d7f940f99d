#!/usr/bin/env bash
# bench/paired_targets.sh's placement readings against closed forms, with a
# fake triax_bench (BIN) and a fake host_scaling (HOST). Three rounds; each
# call of the bench prints the next of these ratios (per round, the cases
# in the script's order):
#   two/one 12000  1.90 1.40 1.85     two/one 1e5          1.95 1.70 1.91
#   x_N1 one       1.16 1.17 1.18     x_N1 two             1.10 1.05 1.08
#   s/s one        2.40 2.50 2.45     spheroid/sphere two  2.30 2.35 2.38
# and the round trip [ns] read before / after each two-thread case:
#   two/one 12000  120/125 500/505 110/112   (near: rounds 1, 3)
#   two/one 1e5    120/480 100/100 115/118   (near: 2, 3; round 1 changed)
#   x_N1 two       130/130 130/130 520/120   (near: 1, 2; round 3 changed)
#   s/s two        100/100 250/250 100/100   (near: 1, 3; 250 is not near)
# Medians over the near rounds (RT_SLOW 250): 1.875, (1.70 + 1.91) / 2 =
# 1.805, 1.075, (2.30 + 2.38) / 2 = 2.34; over all rounds 1.85, 1.91, 1.08,
# 2.35. Classing by the reading before the run alone (1e5: 3 rounds), by
# the one after alone (x_N1 two: 3) or near as "at or below" (s/s two: 3)
# changes a count. The one-thread cases read no round trip, and each
# two-thread case is read right before and right after its run (8 readings
# a round, in that order). Without host_scaling the script runs and prints
# no near medians.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "${tmp}"' EXIT
cat >"${tmp}/triax_bench" <<FAKE
#!/usr/bin/env bash
echo x >>"${tmp}/runs"
echo run >>"${tmp}/calls"
n=\$(wc -l <"${tmp}/runs")
pick() { shift "\${n}"; echo "\$1"; }
m=\$(pick - 1.90 1.95 1.16 1.10 2.40 2.30  1.40 1.70 1.17 1.05 2.50 2.35  1.85 1.91 1.18 1.08 2.45 2.38)
key=pair_cost_ratio
[[ " \$* " == *" --alternate "* ]] && key=alternate_speedup
echo "\${key}: \${m} (median of 5 pairs of blocks; quartiles \${m} \${m})"
FAKE
cat >"${tmp}/host_scaling" <<FAKE
#!/usr/bin/env bash
[[ "\$1" == --pingpong ]] || exit 2
echo x >>"${tmp}/readings"
echo rt >>"${tmp}/calls"
n=\$(wc -l <"${tmp}/readings")
pick() { shift "\${n}"; echo "\$1"; }
printf '1      pingpong %8.1f ns round trip of a cache line between CPUs 0 and 1\n' "\$(pick - \
  120 125 120 480 130 130 100 100  500 505 100 100 130 130 250 250  110 112 115 118 520 120 100 100)"
FAKE
chmod +x "${tmp}/triax_bench" "${tmp}/host_scaling"
fail=0
out="$(BIN="${tmp}/triax_bench" HOST="${tmp}/host_scaling" "${ROOT}/bench/paired_targets.sh" 3 2>&1)"
echo "${out}"
grep -q "^round 1: *two/one 12000 1.90 (1.90-1.90) \[120/125\]" <<<"${out}" ||
  { echo "FAIL: round 1's first case with its readings [120/125]"; fail=1; }
grep -q "x_N1 one 1.16 (1.16-1.16)  x_N1 two" <<<"${out}" || { echo "FAIL: a one-thread case got readings"; fail=1; }
[[ "$(wc -l <"${tmp}/readings")" == 24 ]] || { echo "FAIL: not 8 readings a round"; fail=1; }
# per round: 12000 and 1e5 (two threads), x_N1 one, x_N1 two, s/s one, s/s two
expect="$(for r in 1 2 3; do printf 'rt\nrun\nrt\nrt\nrun\nrt\nrun\nrt\nrun\nrt\nrun\nrt\nrun\nrt\n'; done)"
[[ "$(cat "${tmp}/calls")" == "${expect}" ]] || { echo "FAIL: the readings are not right around the two-thread runs"; fail=1; }
near="$(sed -n '/^medians over the rounds with both round trips below 250 ns:/,$p' <<<"${out}")"
for want in "two/one 12000 +1.875 \(2 rounds\)" "two/one 1e5 +1.805 \(2 rounds\)" "x_N1 two +1.075 \(2 rounds\)" \
  "spheroid/sphere two +2.34 \(2 rounds\)"; do
  grep -qE "^  ${want}$" <<<"${near}" || { echo "FAIL: near medians: no '${want}'"; fail=1; }
done
grep -qE "^  two/one 12000 +1.85$" <<<"${out}" || { echo "FAIL: the median over all rounds (1.85)"; fail=1; }
rm -f "${tmp}/runs" "${tmp}/readings" "${tmp}/calls"
out="$(BIN="${tmp}/triax_bench" HOST="${tmp}/none" "${ROOT}/bench/paired_targets.sh" 3 2>&1)" ||
  { echo "FAIL: without host_scaling the script failed: ${out}"; fail=1; }
grep -q "both round trips" <<<"${out}" && { echo "FAIL: near medians without host_scaling"; fail=1; }
grep -qE "^  spheroid/sphere two +2.35$" <<<"${out}" || { echo "FAIL: without host_scaling the medians are missing"; fail=1; }
((fail == 0)) && echo "PASS"
exit "${fail}"
