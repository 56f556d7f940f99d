#!/usr/bin/env bash
# Where the time of a step goes on one thread and on two (triax_bench's
# phase timers, dem/phase_times.h), in interleaved rounds: each round times
# one thread, then two, on the same tiled sample. Prints, per thread count,
# the medians over the rounds of each thread's microseconds per step in
# each phase (prepare, pairs, ghosts, sums, integrate) and outside its own
# work inside the parallel regions (waits: forming the team, barriers,
# the other thread's lead), and the median of the rounds' speed-ups.
#
#   bench/phase_breakdown.sh ROUNDS TILE STEPS [SAMPLE]
#   bench/phase_breakdown.sh 6 3x2x2 3000            # 12 000 dense spheres
#   bench/phase_breakdown.sh 4 5x5x4 400             # 100 000
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
[[ $# -ge 3 ]] || { sed -n '2,12p' "$0" >&2; exit 2; }
R=$1; TILE=$2; STEPS=$3; SAMPLE=${4:-config/samples/dense_1000.h5}
BIN="${BIN:-build/devel/lib/virtual_triaxial/triax_bench}"
[[ "${R}" =~ ^[1-9][0-9]*$ ]] || { echo "phase_breakdown: ROUNDS must be a whole number >= 1" >&2; exit 2; }
[[ "${STEPS}" =~ ^[1-9][0-9]*$ ]] || { echo "phase_breakdown: STEPS must be a whole number >= 1" >&2; exit 2; }
[[ -x "${BIN}" ]] || { echo "phase_breakdown: ${BIN} not built" >&2; exit 2; }
work="$(mktemp -d)"; trap 'rm -rf "${work}"' EXIT
echo "# $(date -u '+%F %H:%M UTC'), ${SAMPLE} tiled ${TILE}, Morton-sorted, ${STEPS} steps, ${R} rounds, load average $(cut -d' ' -f1-3 /proc/loadavg)"
for ((r = 1; r <= R; ++r)); do
  for t in 1 2; do
    "${BIN}" --sample "${SAMPLE}" --tile "${TILE}" --sort-sample --threads "${t}" --steps "${STEPS}" >"${work}/${t}_${r}" 2>/dev/null ||
      { echo "phase_breakdown: triax_bench failed" >&2; exit 1; }
  done
done
python3 - "${work}" "${R}" "${STEPS}" <<'PY'
import statistics as st, sys
work, rounds, steps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
names = ["prepare", "pairs", "ghosts", "sums", "integrate", "waits"]
def parse(path):
    out = {"threads": {}}
    for line in open(path):
        key, _, val = line.partition(":")
        if key == "us_per_particle_step": out["us"] = float(val)
        elif key == "particles": out["n"] = int(val)
        elif key.startswith("phase_seconds_thread_"):
            w = val.split()
            out["threads"][int(key.rsplit("_", 1)[1])] = {w[k]: float(w[k + 1]) for k in range(0, len(w), 2)}
    return out
runs = {t: [parse("%s/%d_%d" % (work, t, r)) for r in range(1, rounds + 1)] for t in (1, 2)}
print("particles %d; microseconds per step, medians of %d rounds" % (runs[1][0]["n"], rounds))
print("%-10s %s %9s" % ("threads", " ".join("%9s" % n for n in names), "us/p-step"))
for t in (1, 2):
    for th in range(t):
        row = [st.median(1e6 * x["threads"][th][n] / steps for x in runs[t]) for n in names]
        label = "%d (t%d)" % (t, th)
        us = st.median(x["us"] for x in runs[t]) if th == 0 else float("nan")
        print("%-10s %s %9s" % (label, " ".join("%9.1f" % v for v in row), "%.4f" % us if th == 0 else ""))
print("two threads / one: speed-up, median of the rounds' %.3fx" % st.median(a["us"] / b["us"] for a, b in zip(runs[1], runs[2])))
PY
