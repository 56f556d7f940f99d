#!/usr/bin/env bash
# triax_sweep on a real one-node Slurm cluster (run by ctest; needs root and
# Debian's slurm-wlm + munge, installed here if missing):
# - starts munged, slurmctld and slurmd with every file in a temp folder
#   (tests/sweep/slurm_cluster.sh), stops them by their PIDs on any exit;
# - submits a 6-run sweep (tests/sweep/sweep_mini.yaml) as one job array
#   with at most 2 tasks at once and waits: every run completed, each by its
#   own array task;
# - runs the same sweep with the local backend: sweep.csv and sweep.h5 equal
#   the Slurm ones byte for byte;
# - a run killed by Slurm (scancel of its task) is redone by the next submit
#   and the table is again the local one.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "${HERE}/../.." && pwd)"
SWEEP="${HERE}/sweep_mini.yaml"
fail() { echo "[test_sweep_slurm] FAIL: $*" >&2; exit 1; }

if [[ "$(id -u)" -ne 0 ]]; then
  fail "needs root (the test cluster runs with SlurmUser=root)"
fi
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  apt-get install -y -o DPkg::Lock::Timeout=900 slurm-wlm munge >/dev/null
fi

T="$(mktemp -d /tmp/vt_sweep_slurm.XXXXXX)"
# shellcheck source=tests/sweep/slurm_cluster.sh
source "${HERE}/slurm_cluster.sh"
cleanup() {
  local rc=$?
  vt_slurm_stop
  if ((rc == 0)); then rm -rf "${T}"; else echo "[test_sweep_slurm] files kept in ${T}" >&2; fi
  exit "${rc}"
}
trap cleanup EXIT
trap 'exit 1' INT TERM

vt_slurm_start "${T}/cluster"

echo "[test_sweep_slurm] slurm backend"
"${ROOT}/scripts/triax_sweep" "${SWEEP}" --backend slurm --out "${T}/slurm" --max-parallel 2 --wait --poll 0.5 \
  || fail "the slurm sweep did not complete"
echo "[test_sweep_slurm] local backend"
"${ROOT}/scripts/triax_sweep" "${SWEEP}" --out "${T}/local" -j 2 || fail "the local sweep did not complete"

n_runs=6
[[ "$(tail -n +2 "${T}/slurm/sweep.csv" | wc -l)" == "${n_runs}" ]] || fail "expected ${n_runs} rows"
[[ "$(/usr/bin/python3 -c "import csv,sys; print(sum(r['status']=='completed' for r in csv.DictReader(open(sys.argv[1]))))" "${T}/slurm/sweep.csv")" == "${n_runs}" ]] \
  || fail "not every run completed: $(cut -d, -f1-8 "${T}/slurm/sweep.csv")"
# each run by its own array task, and on the slurm backend
[[ "$(ls "${T}/slurm/slurm/"*_*.out | wc -l)" == "${n_runs}" ]] || fail "expected ${n_runs} task logs"
[[ "$(grep -c ',slurm,' "${T}/slurm/sweep_timing.csv")" == "${n_runs}" ]] || fail "runs not recorded as slurm runs"
cmp "${T}/slurm/sweep.csv" "${T}/local/sweep.csv" || fail "sweep.csv differs between the slurm and local backends"
cmp "${T}/slurm/sweep.h5" "${T}/local/sweep.h5" || fail "sweep.h5 differs between the slurm and local backends"
echo "[test_sweep_slurm] slurm table = local table (byte for byte, ${n_runs} runs)"

echo "[test_sweep_slurm] a task killed by Slurm is redone by the next submit"
killed_run="$(ls "${T}/slurm/runs" | sed -n 4p)"
rm -rf "${T}/slurm/runs/${killed_run}"   # as if it had never run ...
# ... and its new task is slow (a program that waits before triax_run), so it
# is cancelled while it runs
cat > "${T}/slow_triax_run" <<SLOW
#!/usr/bin/python3
import os, sys, time
real = "${ROOT}/build/devel/lib/virtual_triaxial/triax_run"
if "--check" not in sys.argv:
    time.sleep(60)
os.execv(real, [real] + sys.argv[1:])
SLOW
chmod +x "${T}/slow_triax_run"
"${ROOT}/scripts/triax_sweep" "${SWEEP}" --backend slurm --out "${T}/slurm" --program "${T}/slow_triax_run" \
  >/dev/null 2>&1 || fail "second submit failed"
job="$(tail -n 1 "${T}/slurm/slurm/jobs.txt" | cut -d' ' -f1)"
[[ "$(tail -n 1 "${T}/slurm/slurm/jobs.txt" | cut -d' ' -f2)" == 1 ]] || fail "the second submit should hold 1 run"
for _ in $(seq 300); do compgen -G "${T}/slurm/runs/.partial-${killed_run}-*" >/dev/null && break; sleep 0.1; done
compgen -G "${T}/slurm/runs/.partial-${killed_run}-*" >/dev/null || fail "the slow task did not start"
[[ "$(squeue -h -r -j "${job}" -o %T)" == RUNNING ]] || fail "the slow task is not running"
scancel "${job}"
for _ in $(seq 100); do [[ -z "$(squeue -h -j "${job}" 2>/dev/null)" ]] && break; sleep 0.1; done
pgrep -f "${T}/slow_triax_run" >/dev/null && fail "the cancelled task left its program running"
[[ ! -e "${T}/slurm/runs/${killed_run}" ]] || fail "a cancelled task published its run"
"${ROOT}/scripts/triax_sweep" collect "${SWEEP}" --out "${T}/slurm" >/dev/null 2>&1 && fail "collect should report the missing run"
grep -q ',pending,' "${T}/slurm/sweep.csv" || fail "the cancelled run is not pending in the table"
"${ROOT}/scripts/triax_sweep" "${SWEEP}" --backend slurm --out "${T}/slurm" --wait --poll 0.5 || fail "third submit failed"
[[ "$(tail -n 1 "${T}/slurm/slurm/jobs.txt" | cut -d' ' -f2)" == 1 ]] || fail "the third submit should run 1 run"
cmp "${T}/slurm/sweep.csv" "${T}/local/sweep.csv" || fail "after the redo, sweep.csv differs from the local one"
echo "[test_sweep_slurm] PASS"
