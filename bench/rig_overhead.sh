#!/usr/bin/env bash
# Rig overhead benchmark: the same protocol through the ROS rig
# (launch_equiv_scripts/run_triaxial.sh, with and without the bag recorder) and headless
# (triax_run); compares the test wall times each reports (set-up, plots and
# master start excluded) and checks both took the same decisions.
#   bench/rig_overhead.sh [PROTOCOL.yaml] [REPEATS]
# Run it on a quiet machine: timings under load mean little.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
protocol="${1:-config/protocols/drained_100kPa.yaml}"
repeats="${2:-2}"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
source launch_equiv_scripts/lib/ensure_built.sh
vt_ensure_built all >/dev/null
tmp="$(mktemp -d)"
best() { sort -g | head -1; }
field() { /usr/bin/python3 -c "import json,sys; d=json.loads(open(sys.argv[1]).read().splitlines()[-1]); print(d.get(sys.argv[2]))" "$@"; }
for ((r = 0; r < repeats; ++r)); do
  build/devel/lib/virtual_triaxial/triax_run "${protocol}" --out "${tmp}/headless.h5" --quiet > "${tmp}/headless_${r}.json"
  field "${tmp}/headless_${r}.json" wall_seconds >> "${tmp}/headless.t"
  OUT="${tmp}/rig_${r}" launch_equiv_scripts/run_triaxial.sh "${protocol}" > "${tmp}/rig_${r}.log" 2>&1
  field "${tmp}/rig_${r}/summary.json" wall_seconds >> "${tmp}/rig.t"
  RECORD=0 OUT="${tmp}/rignobag_${r}" launch_equiv_scripts/run_triaxial.sh "${protocol}" > "${tmp}/rignobag_${r}.log" 2>&1
  field "${tmp}/rignobag_${r}/summary.json" wall_seconds >> "${tmp}/rignobag.t"
done
h="$(best < "${tmp}/headless.t")"; g="$(best < "${tmp}/rig.t")"; n="$(best < "${tmp}/rignobag.t")"
echo "protocol: ${protocol} (best of ${repeats})"
echo "headless triax_run: ${h} s   phi_peak_deg $(field "${tmp}/headless_0.json" phi_peak_deg)"
echo "ROS rig, no bag:    ${n} s   phi_peak_deg $(field "${tmp}/rignobag_0/summary.json" phi_peak_deg)"
echo "ROS rig + bag:      ${g} s   phi_peak_deg $(field "${tmp}/rig_0/summary.json" phi_peak_deg)"
awk -v h="${h}" -v n="${n}" 'BEGIN { printf "rig_overhead_without_bag_percent: %.1f\n", 100 * (n - h) / h }'
awk -v h="${h}" -v g="${g}" 'BEGIN { printf "rig_overhead_percent: %.1f\n", 100 * (g - h) / h }'
rm -rf "${tmp}"
