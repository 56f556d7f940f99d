"""From a sweep file to its runs: one input per run, validated, and the plan.

Each run gets an id `rNNNN-HASH`: its place in the sweep and the first 10 hex
digits of the SHA-256 of its input (the generated protocol text, or the
triax_prepare command line). Editing the base file or a value changes the
hash, so a changed run is never mistaken for a finished one.

The plan, `OUTPUT/sweep.json`, is all a run needs (absolute paths): the
local workers and the Slurm array tasks read it from the shared folder.
"""
import copy
import hashlib
import json
import os
import subprocess

from . import dotted
from .errors import SweepError
from .fsutil import write_atomic
from .strict_yaml import dump
from .units import SCENE_PATH_KEYS

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PLAN_FILE = "sweep.json"


def program_dir():
    """Where triax_run and triax_prepare are: $VT_PROGRAM_DIR or the build tree."""
    return os.environ.get("VT_PROGRAM_DIR") or os.path.join(REPO, "build", "devel", "lib", "virtual_triaxial")


def _run_input(spec, values):
    """(input text or None, argv tail) of one run."""
    if spec.program == "triax_run":
        tree = copy.deepcopy(spec.base_tree)
        for p in spec.parameters:
            v = values[p.key]
            if p.tokens[-1] in SCENE_PATH_KEYS:
                v = os.path.normpath(os.path.join(spec.folder, v))
            dotted.assign(tree, p.tokens, v, f"parameters.{p.key}")
        return dump(tree), []
    opts = dict(spec.prepare)
    opts.update({p.tokens[0]: values[p.key] for p in spec.parameters})
    argv = []
    for k in sorted(opts):
        v = opts[k]
        if k == "psd":
            v = os.path.normpath(os.path.join(spec.folder, v))
        argv += ["--" + k.replace("_", "-"), repr(v) if isinstance(v, float) else str(v)]
    return None, argv + ["--out", "sample.h5"]


def build_plan(spec, program_path=None):
    """The plan dict of `spec`: program, parameters and runs (inputs in memory)."""
    program = program_path or os.path.join(program_dir(), spec.program)
    runs = []
    for i, values in enumerate(spec.combinations()):
        text, argv = _run_input(spec, values)
        digest = hashlib.sha256((text if text is not None else "\0".join(argv)).encode()).hexdigest()[:10]
        run_id = f"r{i:04d}-{digest}"
        run = {"index": i, "id": run_id, "values": values}
        if text is not None:
            run["input"] = f"inputs/{run_id}.yaml"
            run["input_text"] = text
        else:
            run["argv"] = argv
        runs.append(run)
    return {
        "format": 1, "name": spec.name, "sweep_file": spec.path, "program": spec.program,
        "program_path": program, "threads": spec.threads, "combine": spec.combine,
        "parameters": [{"key": p.key, "unit": p.unit, "column": p.column, "values": p.values}
                       for p in spec.parameters],
        "runs": runs,
    }


def check_inputs(plan, out, progress=None):
    """triax_run --check on every generated input; the first bad one raises
    SweepError naming the parameter value (parameters.KEY[i]) when the error
    is about a varied key, else the run and its values."""
    if plan["program"] != "triax_run":
        return
    if not os.access(plan["program_path"], os.X_OK):
        raise SweepError("program", f"{plan['program_path']}: not found or not executable (build the project first)")
    for k, run in enumerate(plan["runs"]):
        path = os.path.join(out, run["input"])
        proc = subprocess.run([plan["program_path"], path, "--check"], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True)
        if progress:
            progress(k + 1, len(plan["runs"]))
        if proc.returncode == 0:
            continue
        msg = proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else f"exit {proc.returncode}"
        msg = msg.replace("triax_run: error: ", "")
        for p in plan["parameters"]:
            if msg.startswith(p["key"] + ":") or msg.startswith(p["key"] + "."):
                idx = p["values"].index(run["values"][p["key"]])
                raise SweepError(f"parameters.{p['key']}[{idx}]", f"{run['values'][p['key']]!r} is refused: {msg}")
        raise SweepError(f"runs[{run['index']}]", f"{_describe(run['values'])}: input refused: {msg}")


def _describe(values):
    return ", ".join(f"{k} = {v!r}" for k, v in values.items())


def write_plan(plan, out):
    """Writes the inputs and sweep.json (atomically) into `out`; returns the plan
    without the in-memory input texts."""
    os.makedirs(os.path.join(out, "inputs"), exist_ok=True)
    os.makedirs(os.path.join(out, "runs"), exist_ok=True)
    stored = dict(plan, runs=[])
    for run in plan["runs"]:
        run = dict(run)
        text = run.pop("input_text", None)
        if text is not None:
            path = os.path.join(out, run["input"])
            if not os.path.isfile(path) or open(path, encoding="utf-8").read() != text:
                write_atomic(path, text)
        stored["runs"].append(run)
    write_atomic(os.path.join(out, PLAN_FILE), json.dumps(stored, indent=1, sort_keys=True) + "\n")
    return stored


def read_plan(out):
    path = os.path.join(out, PLAN_FILE)
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except OSError:
        raise SweepError("output", f"no sweep plan '{path}' (run the sweep first)") from None


def prepare(spec, program_path=None, progress=None):
    """build + write + check: the stored plan of `spec` in spec.output."""
    plan = build_plan(spec, program_path)
    os.makedirs(spec.output, exist_ok=True)
    stored = write_plan(plan, spec.output)
    check_inputs(stored, spec.output, progress)
    return stored
