#!/usr/bin/env bash
# bench/cut_cost.sh against closed forms, with a fake triax_bench (BIN) of
# 12 000 particles whose costs and cuts depend on the round (r = 1..6):
#   one thread          0.080 0.082 0.078 0.160 0.080 0.081 (round 4 a noisy
#                       one-thread run: median of all 0.0805)
#   TILE, two threads   0.040 0.060 0.041 0.058 0.046 0.070, cut 1000 1100
#                       1010 1100 990 1100
#   12x1x1, two         0.0400 0.0425 0.0400 0.0425 0.0430 0.0500, cut 250
#                       300 250 300 260 300
# Classed by median one / two < 1.7: rounds 2, 4, 6 slow (round 4 too,
# although its own one / two is 2.76), 1, 3, 5 normal. Medians: TILE two
# 0.041 normal, 0.060 slow; column 0.0400 and 0.0425; normal cuts 1000 and
# 250. Extra per cut particle: (0.060 - 0.041) x 12 000 / 1000 x 1000 =
# 228 ns and (0.0425 - 0.0400) x 12 000 / 250 x 1000 = 120 ns. Means
# instead of medians (244), the slow rounds' cut (207) or a round's own
# one-thread cost as the yardstick (257) give other numbers.
# SLOW_BELOW=1.2 leaves one slow round (6: 1.15). A run that prints no cost
# and a tile without three factors are refused.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "${tmp}"' EXIT
cat >"${tmp}/triax_bench" <<FAKE
#!/usr/bin/env bash
tile=""; threads=""
while ((\$#)); do case "\$1" in --tile) tile=\$2; shift 2;; --threads) threads=\$2; shift 2;; *) shift;; esac; done
echo "\${tile} \${threads}" >>"${tmp}/calls"
if [[ \${threads} == 1 ]]; then echo x >>"${tmp}/rounds"; fi
r=\$(wc -l <"${tmp}/rounds")
pick() { shift "\${r}"; echo "\$1"; }  # the r-th of the arguments after the first
echo "particles: 12000"
if [[ \${threads} == 1 ]]; then
  cost=\$(pick - 0.080 0.082 0.078 0.160 0.080 0.081)
elif [[ \${tile} == 12x1x1 ]]; then
  echo "cut_particles: \$(pick - 250 300 250 300 260 300)"
  cost=\$(pick - 0.0400 0.0425 0.0400 0.0425 0.0430 0.0500)
else
  echo "cut_particles: \$(pick - 1000 1100 1010 1100 990 1100)"
  cost=\$(pick - 0.040 0.060 0.041 0.058 0.046 0.070)
fi
[[ -e "${tmp}/no_cost" ]] || echo "us_per_particle_step: \${cost}"
FAKE
chmod +x "${tmp}/triax_bench"
fail=0
out="$(BIN="${tmp}/triax_bench" "${ROOT}/bench/cut_cost.sh" 6 3x2x2 10 2>&1)"
echo "${out}"
grep -q "tiled 3x2x2 and 12x1x1" <<<"${out}" || { echo "FAIL: the column is not 12x1x1"; fail=1; }
[[ "$(grep -c '^12x1x1 2$' "${tmp}/calls")" == 6 ]] || { echo "FAIL: the column did not run on two threads each round"; fail=1; }
grep -q "^normal .* 0.041 .* 0.0400 .* 1000 .* 250 .*(3 rounds)" <<<"${out}" ||
  { echo "FAIL: normal rounds' medians (two 0.041, column 0.0400, cuts 1000 / 250, 3 rounds)"; fail=1; }
grep -q "^slow .* 0.060 .* 0.0425 .* 1100 .* 300 .*(3 rounds)" <<<"${out}" ||
  { echo "FAIL: slow rounds' medians (two 0.060, column 0.0425, cuts 1100 / 300, 3 rounds)"; fail=1; }
grep -q "extra per cut particle and step \[ns\]: 3x2x2 228, 12x1x1 120$" <<<"${out}" ||
  { echo "FAIL: the extra per cut particle is not 228 / 120 ns"; fail=1; }
rm -f "${tmp}/rounds" "${tmp}/calls"
out="$(SLOW_BELOW=1.2 BIN="${tmp}/triax_bench" "${ROOT}/bench/cut_cost.sh" 6 3x2x2 10 2>&1)"
grep -q "^slow .*(1 rounds)" <<<"${out}" || { echo "FAIL: SLOW_BELOW=1.2 did not leave one slow round"; fail=1; }
rm -f "${tmp}/rounds"; touch "${tmp}/no_cost"
if err="$(BIN="${tmp}/triax_bench" "${ROOT}/bench/cut_cost.sh" 2 3x2x2 10 2>&1)"; then
  echo "FAIL: a run without a cost was accepted"; fail=1
elif ! grep -q "printed no 'us_per_particle_step'" <<<"${err}"; then
  echo "FAIL: the missing cost is not named: ${err}"; fail=1
fi
rm -f "${tmp}/no_cost" "${tmp}/rounds"
set +e
err="$(BIN="${tmp}/triax_bench" "${ROOT}/bench/cut_cost.sh" 2 3x2 10 2>&1)"; rc=$?
set -e
[[ ${rc} == 2 ]] && grep -q "three factors" <<<"${err}" ||
  { echo "FAIL: a tile without three factors: exit ${rc}, '${err}'"; fail=1; }
((fail == 0)) && echo "PASS"
exit "${fail}"
