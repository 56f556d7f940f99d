"""Local backend: J worker processes (`run-one`), each running one triax_run
or triax_prepare at a time; a progress line; failures recorded, not fatal.

One driver per output folder (an flock on OUT/.lock, released by the kernel
when the driver dies, kill -9 included). Workers die with the driver
(PR_SET_PDEATHSIG), their programs with them, so a killed sweep leaves no
process behind and no published half run. Each worker runs in its own
session (setsid), like a Slurm task: Linux's autogroup scheduler gives each
session one share of the CPUs, so J workers get J shares on a busy machine,
not one share split J ways.
"""
import fcntl
import os
import subprocess
import sys
import time

from .errors import SweepError
from .plan import prepare
from .progress import Progress
from .run_one import die_with_parent, is_published, read_status
from .table import write_tables

SCRIPTS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def worker_command(out, index, backend):
    return [sys.executable, "-m", "vt_sweep", "run-one", out, str(index), "--backend", backend]


def worker_env():
    path = os.environ.get("PYTHONPATH", "")
    return dict(os.environ, PYTHONPATH=SCRIPTS + (os.pathsep + path if path else ""))


def lock_output(out):
    """Holds OUT/.lock for this process; SweepError if another driver holds it."""
    os.makedirs(out, exist_ok=True)
    fd = os.open(os.path.join(out, ".lock"), os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        raise SweepError("output", f"'{out}' is in use by another triax_sweep (one driver per output folder)") from None
    return fd


def forget_failed(out, plan):
    """Removes the published failed runs so they run again (--retry-failed)."""
    import shutil
    n = 0
    for run in plan["runs"]:
        if is_published(out, run["id"]) and read_status(out, run["id"])["status"] == "failed":
            gone = os.path.join(out, "runs", f".retry-{run['id']}-{os.getpid()}")
            os.rename(os.path.join(out, "runs", run["id"]), gone)
            shutil.rmtree(gone, ignore_errors=True)
            n += 1
    return n


def run_local(spec, jobs=None, retry_failed=False, stream=None, program_path=None):
    """Runs the sweep; returns 0 if every run completed, 1 if some failed or
    were interrupted. Writes sweep.csv / sweep.h5 at the end."""
    stream = stream or sys.stderr
    jobs = jobs or os.cpu_count() or 1
    out = spec.output
    lock = lock_output(out)
    try:
        stream.write(f"triax_sweep: {spec.name}: checking the inputs\n")
        plan = prepare(spec, program_path)
        if retry_failed:
            stream.write(f"triax_sweep: {spec.name}: {forget_failed(out, plan)} failed runs will run again\n")
        total = len(plan["runs"])
        done = failed = 0
        todo = []
        for run in plan["runs"]:
            if not is_published(out, run["id"]):
                todo.append(run)
            elif read_status(out, run["id"])["status"] == "completed":
                done += 1
            else:
                failed += 1
        stream.write(f"triax_sweep: {spec.name}: {total} runs ({spec.program}), {done + failed} already finished "
                     f"({failed} failed), {len(todo)} to run on {jobs} workers; output {out}\n")
        prog = Progress(spec.name, total, jobs, stream)
        running, lost = {}, 0
        env = worker_env()
        while todo or running:
            while todo and len(running) < jobs:
                run = todo.pop(0)
                # each worker in its own session, as Slurm starts its tasks: with
                # the kernel's autogroup scheduling a session is one CPU share
                p = subprocess.Popen(worker_command(out, run["index"], "local"), env=env,
                                     stdin=subprocess.DEVNULL, preexec_fn=die_with_parent(),
                                     start_new_session=True)
                running[p.pid] = (p, run)
            prog.show(done, len(running), failed)
            pid, _ = os.wait()
            if pid not in running:
                continue
            p, run = running.pop(pid)
            p.returncode = 0
            prog.finished_here += 1
            if not is_published(out, run["id"]):
                lost += 1
                prog.note(f"triax_sweep: run {run['id']} was interrupted; it runs again at the next start")
                continue
            st = read_status(out, run["id"])
            if st["status"] == "completed":
                done += 1
            else:
                failed += 1
                prog.note(f"triax_sweep: run {run['id']} ({_describe(run['values'])}) failed, "
                          f"exit code {st['exit_code']}: {st['message']}")
        prog.show(done, 0, failed, force=True)
        prog.close()
        write_tables(out)
        stream.write(f"triax_sweep: {spec.name}: {done} completed, {failed} failed, {lost} interrupted; "
                     f"wrote {os.path.join(out, 'sweep.csv')} and sweep.h5\n")
        return 0 if failed == 0 and lost == 0 else 1
    finally:
        os.close(lock)


def _describe(values):
    return ", ".join(f"{k} = {v!r}" for k, v in values.items())
