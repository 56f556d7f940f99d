"""Command line of triax_sweep (see `triax_sweep --help`)."""
import argparse
import os
import sys

from .errors import SweepError
from .spec import load_spec

USAGE = """triax_sweep SWEEP.yaml [--backend local|slurm] [options]   run (or submit) a sweep
triax_sweep collect SWEEP.yaml [--out DIR]                    gather finished runs into sweep.csv / sweep.h5
triax_sweep check SWEEP.yaml                                  validate the file and every run's input
triax_sweep run-one OUT INDEX [--backend NAME]                one run (what workers and Slurm tasks call)"""

EXIT_HELP = """exit codes: 0 every run completed (or, slurm without --wait, submitted);
1 some runs failed or did not finish; 2 bad sweep file or options (one line naming the field)."""


def _run_parser():
    ap = argparse.ArgumentParser(prog="triax_sweep", usage=USAGE, epilog=EXIT_HELP,
                                 description="Runs a parameter sweep of triax_run / triax_prepare runs.")
    ap.add_argument("sweep", help="sweep file (YAML)")
    ap.add_argument("--backend", choices=["local", "slurm"], default="local")
    ap.add_argument("--out", help="output folder (default: the file's output)")
    ap.add_argument("-j", "--jobs", type=int, help="local: worker processes (default: the core count)")
    ap.add_argument("--retry-failed", action="store_true", help="run the failed runs again")
    ap.add_argument("--program", help="the triax_run / triax_prepare executable (default: the build tree)")
    g = ap.add_argument_group("slurm backend")
    g.add_argument("--partition")
    g.add_argument("--time", help="time limit per run (sbatch --time, e.g. 00:30:00)")
    g.add_argument("--mem", help="memory per run (sbatch --mem, e.g. 2G)")
    g.add_argument("--max-parallel", type=int, help="at most K runs at once (--array=...%%K)")
    g.add_argument("--sbatch-arg", action="append", default=[], help="another sbatch option (repeatable)")
    g.add_argument("--wait", action="store_true", help="wait for the job, then collect")
    g.add_argument("--poll", type=float, default=2.0, help="seconds between queue polls with --wait")
    return ap


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    try:
        if argv and argv[0] == "run-one":
            ap = argparse.ArgumentParser(prog="triax_sweep run-one")
            ap.add_argument("out")
            ap.add_argument("index", type=int)
            ap.add_argument("--backend", default="local")
            a = ap.parse_args(argv[1:])
            from .run_one import run_one
            return run_one(a.out, a.index, a.backend)
        if argv and argv[0] in ("collect", "check"):
            ap = argparse.ArgumentParser(prog=f"triax_sweep {argv[0]}")
            ap.add_argument("sweep", help="sweep file, or (collect) its output folder")
            ap.add_argument("--out")
            ap.add_argument("--program")
            a = ap.parse_args(argv[1:])
            if argv[0] == "collect":
                return _collect(a)
            from .plan import prepare
            spec = load_spec(a.sweep, a.out)
            plan = prepare(spec, a.program)
            print(f"triax_sweep: {spec.name}: valid, {len(plan['runs'])} runs of {spec.program}, output {spec.output}")
            return 0
        a = _run_parser().parse_args(argv)
        if a.jobs is not None and a.jobs < 1:
            raise SweepError("--jobs", f"must be >= 1, got {a.jobs}")
        if a.max_parallel is not None and a.max_parallel < 1:
            raise SweepError("--max-parallel", f"must be >= 1, got {a.max_parallel}")
        spec = load_spec(a.sweep, a.out)
        if a.backend == "local":
            from .local_backend import run_local
            return run_local(spec, a.jobs, a.retry_failed, program_path=a.program)
        from .slurm_backend import submit
        opts = {"partition": a.partition, "time": a.time, "mem": a.mem, "max_parallel": a.max_parallel,
                "extra_args": a.sbatch_arg}
        return submit(spec, opts, a.wait, a.retry_failed, a.poll, program_path=a.program)
    except SweepError as e:
        print(f"triax_sweep: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("\ntriax_sweep: interrupted; finished runs are kept, start again to run the rest", file=sys.stderr)
        return 130


def _collect(a):
    from .table import counts, write_tables
    out = a.out or (a.sweep if os.path.isdir(a.sweep) else load_spec(a.sweep).output)
    columns, rows = write_tables(out)
    c = counts(out)
    print(f"triax_sweep: collected {out}: {c['completed']} completed, {c['failed']} failed, "
          f"{c['pending']} not finished; wrote sweep.csv, sweep.h5 ({len(rows)} rows, {len(columns)} columns)")
    return 0 if c["failed"] == 0 and c["pending"] == 0 else 1
