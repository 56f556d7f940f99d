#!/usr/bin/env bash
# Run the default triaxial scene without ROS (standalone triax_run tool).
#   OUT=output/mine launch_equiv_scripts/run_headless.sh [extra triax_run args]
# Results: ${OUT:-output/default}/results.h5 (relative to the repository root).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

# shellcheck source=SCRIPTDIR/lib/ensure_built.sh
source launch_equiv_scripts/lib/ensure_built.sh
vt_ensure_built all

exe="build/devel/lib/virtual_triaxial/triax_run"
if [[ ! -x "${exe}" ]]; then
  echo "[run] ERROR: ${exe} was not built (is src/tools/triax_run.cpp there?)" >&2
  exit 1
fi

out_dir="${OUT:-output/default}"
mkdir -p "${out_dir}"
out="${out_dir}/results.h5"

echo "[run] ${exe} config/scenes/default.yaml --out ${out} $*"
rc=0
"${exe}" config/scenes/default.yaml --out "${out}" "$@" || rc=$?
if [[ -f "${out}" ]]; then
  /usr/bin/python3 scripts/plot_results.py "${out}" || echo "[run] warning: plotting failed" >&2
fi
echo "[run] results written to $(cd "${out_dir}" && pwd)/results.h5 (exit code ${rc})"
exit "${rc}"
