#!/usr/bin/env bash
# bench/sweep_bench.sh [ROUNDS] -- what triax_sweep buys and costs.
#   A  the 12-run sweep bench/sweep_bench.yaml on 2 local workers (triax_sweep -j 2)
#   B  the same 12 inputs run one after another by triax_run (a shell loop,
#      each run in its own session like a sweep's worker: `setsid -w`)
#   C  the same sweep on a one-node Slurm cluster started here (2 CPUs,
#      --max-parallel 2; tests/sweep/slurm_cluster.sh; needs root), skipped
#      with SLURM=0
# in interleaved rounds (A B C, A B C, ...), each from an empty output
# folder, OMP_NUM_THREADS=1 per run. Then the cost of a run itself: the
# 12 near-empty runs of bench/sweep_overhead.yaml (20 DEM steps each) on 2
# local workers (D) and on the cluster (E), interleaved. Prints every
# round's wall times, the medians, the speed-up B/A and the overhead per
# run: D x 2 / 12 (local), E x 2 / 12 (Slurm), and the load average
# before and after. On a machine shared with other jobs, compare the
# medians only (Linux autogroup: each session is one CPU share).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ROUNDS="${1:-3}"
SWEEP="${ROOT}/bench/sweep_bench.yaml"
RUN="${ROOT}/build/devel/lib/virtual_triaxial/triax_run"
T="$(mktemp -d /tmp/vt_sweep_bench.XXXXXX)"
export OMP_NUM_THREADS=1
now() { date +%s.%N; }
# shellcheck source=tests/sweep/slurm_cluster.sh
source "${ROOT}/tests/sweep/slurm_cluster.sh"
trap 'vt_slurm_stop; rm -rf "${T}"' EXIT
if [[ "${SLURM:-1}" == 1 ]]; then vt_slurm_start "${T}/cluster"; fi
# the inputs, once (triax_sweep check writes them)
"${ROOT}/scripts/triax_sweep" check "${SWEEP}" --out "${T}/inputs" >/dev/null
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
A=() B=() C=()
for ((r = 1; r <= ROUNDS; r++)); do
  rm -rf "${T}/a" "${T}/c" "${T}/b"; mkdir -p "${T}/b"
  t0=$(now); "${ROOT}/scripts/triax_sweep" "${SWEEP}" --out "${T}/a" -j 2 2>/dev/null; t1=$(now)
  A+=("$(echo "${t1} - ${t0}" | bc)")
  t0=$(now)
  for f in "${T}/inputs/inputs/"*.yaml; do setsid -w "${RUN}" "${f}" --out "${T}/b/$(basename "${f}" .yaml).h5" --quiet >/dev/null 2>&1; done
  t1=$(now); B+=("$(echo "${t1} - ${t0}" | bc)")
  if [[ "${SLURM:-1}" == 1 ]]; then
    t0=$(now)
    "${ROOT}/scripts/triax_sweep" "${SWEEP}" --out "${T}/c" --backend slurm --max-parallel 2 --wait --poll 0.2 2>/dev/null
    t1=$(now); C+=("$(echo "${t1} - ${t0}" | bc)")
    cmp -s "${T}/a/sweep.csv" "${T}/c/sweep.csv" || echo "warning: slurm and local tables differ"
  fi
  echo "round ${r}: 2 workers ${A[-1]} s, one after another ${B[-1]} s${C:+, slurm ${C[-1]} s}"
done
# shellcheck source=median.sh
source "${ROOT}/bench/median.sh"
ma=$(median_of "${A[@]}"); mb=$(median_of "${B[@]}")
echo "median: 2 workers ${ma} s, one after another ${mb} s, speed-up $(echo "scale=3; ${mb} / ${ma}" | bc)"
if ((${#C[@]})); then
  mc=$(median_of "${C[@]}")
  echo "median: slurm ${mc} s; overhead per run $(echo "scale=3; (${mc} - ${ma}) * 2 / 12" | bc) s"
fi
if [[ "${SLURM:-1}" == 1 ]]; then
  TINY="${ROOT}/bench/sweep_overhead.yaml"
  D=() E=()
  for ((r = 1; r <= ROUNDS; r++)); do
    rm -rf "${T}/d" "${T}/e"
    t0=$(now); "${ROOT}/scripts/triax_sweep" "${TINY}" --out "${T}/d" -j 2 2>/dev/null; t1=$(now)
    D+=("$(echo "${t1} - ${t0}" | bc)")
    t0=$(now)
    "${ROOT}/scripts/triax_sweep" "${TINY}" --out "${T}/e" --backend slurm --max-parallel 2 --wait --poll 0.2 2>/dev/null
    t1=$(now); E+=("$(echo "${t1} - ${t0}" | bc)")
    echo "near-empty runs, round ${r}: 2 local workers ${D[-1]} s, slurm ${E[-1]} s"
  done
  md=$(median_of "${D[@]}"); me=$(median_of "${E[@]}")
  echo "median near-empty: local ${md} s ($(echo "scale=3; ${md} * 2 / 12" | bc) s per run), slurm ${me} s ($(echo "scale=3; ${me} * 2 / 12" | bc) s per run)"
fi
/usr/bin/python3 - "${T}/a/sweep.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("runs: %d, e0 %s, steps %s-%s, p_end %s-%s Pa" % (len(rows), rows[0]["e0"], min(int(r["steps"]) for r in rows),
      max(int(r["steps"]) for r in rows), min(float(r["p_end_pa"]) for r in rows), max(float(r["p_end_pa"]) for r in rows)))
PY
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
