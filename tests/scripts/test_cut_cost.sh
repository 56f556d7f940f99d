#!/usr/bin/env bash
# bench/cut_cost.sh: the column it compares is the same particles as
# K x 1 x 1 (K the product of TILE's factors), rounds are classed normal
# or slow by TILE's two / one against SLOW_BELOW, and the slow phases'
# extra per cut particle is (two_slow - two_normal) N / cut. A fake
# triax_bench (BIN) prints 12 000 particles and costs by round: one thread
# 0.0800; TILE two threads 0.0400 in odd rounds (2.0x: normal) and 0.0600
# in even ones (1.33x: slow), cut 1000 (edge 600 + tail 400); the column
# 0.0400 and 0.0425, cut 250. Closed forms: 0.02 x 12 000 / 1000 = 240 ns
# and 0.0025 x 12 000 / 250 = 120 ns; two rounds of each kind in four.
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
slow=\$((r % 2 == 0))
echo "particles: 12000"
if [[ \${tile} == 12x1x1 ]]; then
  echo "edge_particles: 150"; echo "tail_particles: 100"
  cost=\$([[ \${slow} == 1 ]] && echo 0.0425 || echo 0.0400)
else
  echo "edge_particles: 600"; echo "tail_particles: 400"
  if [[ \${threads} == 1 ]]; then cost=0.0800; else cost=\$([[ \${slow} == 1 ]] && echo 0.0600 || echo 0.0400); fi
fi
echo "us_per_particle_step: \${cost}"
FAKE
chmod +x "${tmp}/triax_bench"
out="$(BIN="${tmp}/triax_bench" "${ROOT}/bench/cut_cost.sh" 4 3x2x2 10 2>&1)"
echo "${out}"
fail=0
grep -q "tiled 3x2x2 and 12x1x1" <<<"${out}" || { echo "FAIL: the column is not 12x1x1"; fail=1; }
[[ "$(grep -c '^12x1x1 2$' "${tmp}/calls")" == 4 ]] || { echo "FAIL: the column did not run on two threads each round"; fail=1; }
grep -q "^normal .* 0.04 .* 0.04 .*(2 rounds)" <<<"${out}" || { echo "FAIL: normal rounds' medians"; fail=1; }
grep -q "^slow .* 0.06 .* 0.0425 .*(2 rounds)" <<<"${out}" || { echo "FAIL: slow rounds' medians"; fail=1; }
grep -q "extra per cut particle and step \[ns\]: 3x2x2 240, 12x1x1 120$" <<<"${out}" ||
  { echo "FAIL: the extra per cut particle is not 240 / 120 ns"; fail=1; }
if BIN="${tmp}/triax_bench" "${ROOT}/bench/cut_cost.sh" 2 3x2 10 >/dev/null 2>&1; then
  echo "FAIL: a tile without three factors was accepted"; fail=1
fi
((fail == 0)) && echo "PASS"
exit "${fail}"
