"""vt_sweep: parameter sweeps of triax_run / triax_prepare, locally or on Slurm.

Python API (put the repository's scripts/ folder on sys.path):

    from vt_sweep import load_spec, spec_from_dict, run_sweep, results
    spec = spec_from_dict({"name": "rates", "output": "out/rates",
                           "base": "config/protocols/drained_100kPa.yaml",
                           "parameters": {"stages[1].strain_rate_dimensionless": [1e-5, 1e-6]}},
                          folder=".")
    code = run_sweep(spec, backend="local", jobs=2)     # or backend="slurm", wait=True
    columns, rows = results(spec.output)                 # one dict per run, plan order
    for folder, status, summary in finished_runs(spec.output): ...   # by run id

The command line `scripts/triax_sweep` is the same code.
"""
from .errors import SweepError
from .run_one import finished_runs
from .spec import load_spec, spec_from_dict


def run_sweep(spec, backend="local", jobs=None, retry_failed=False, stream=None, program_path=None,
              wait=True, **slurm_options):
    """Runs (local) or submits (slurm) `spec`; the return code of triax_sweep."""
    if backend == "local":
        from .local_backend import run_local
        return run_local(spec, jobs, retry_failed, stream, program_path)
    if backend == "slurm":
        from .slurm_backend import submit
        return submit(spec, slurm_options, wait, retry_failed, stream=stream, program_path=program_path)
    raise SweepError("backend", f"must be local or slurm, got {backend!r}")


def results(out):
    """(columns, rows) of the sweep in folder `out` (finished runs have their
    summary; the others status 'pending'), the same as sweep.csv holds."""
    from .table import collect
    columns, rows, _ = collect(out)
    return columns, rows


__all__ = ["SweepError", "load_spec", "spec_from_dict", "run_sweep", "results", "finished_runs"]
