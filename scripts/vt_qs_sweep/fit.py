"""The fits of a sweep, by triax_qs itself (`fit-rates`: eqs. 73-75;
`fit-damping`: the optimum xi, eq. 86), on the completed runs' summaries.
The fitting lives in the C++ quasi_static library; this module only builds
the --run arguments and reads the JSON line back."""
import json
import os
import subprocess

from vt_sweep.errors import SweepError
from vt_sweep.plan import program_dir


def triax_qs():
    return os.environ.get("VT_TRIAX_QS") or os.path.join(program_dir(), "triax_qs")


def _call(args):
    p = subprocess.run([triax_qs()] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    errors = [ln for ln in p.stderr.splitlines() if "error:" in ln]
    if p.returncode != 0:
        raise SweepError("", errors[-1].split("error: ", 1)[1] if errors else
                         f"triax_qs {args[0]}: exit code {p.returncode}")
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith("{")]
    if not lines:
        raise SweepError("", f"triax_qs {args[0]}: no result line")
    notes = [ln for ln in p.stderr.splitlines() if ln.strip()]
    return json.loads(lines[-1]), notes


def fit_rates(runs, threshold):
    """runs: [(eps', summary.json path)] -> (fit dict, triax_qs's messages)."""
    args = ["fit-rates", "--threshold", repr(threshold)]
    for eps, path in runs:
        args += ["--run", f"{eps!r},{path}"]
    return _call(args)


def fit_damping(runs, threshold):
    """runs: [(xi, eps', summary.json path)] -> (fit dict, triax_qs's messages)."""
    args = ["fit-damping", "--threshold", repr(threshold)]
    for xi, eps, path in runs:
        args += ["--run", f"{xi!r},{eps!r},{path}"]
    return _call(args)
