"""One run of a sweep, the same for every backend: `triax_sweep run-one OUT INDEX`.

The run works in a private folder `OUT/runs/.partial-ID-HOST-PID` and, when
its program has exited, writes `status.json` and renames the folder to
`OUT/runs/ID` in one step, so `runs/ID` is either absent or complete:
  status.json   id, index, values, status (completed | failed), exit_code,
                message (the program's one-line error or failure), wall
                seconds, CPU seconds (user + system of the program), host,
                backend, UTC start and end
  summary.json  the program's JSON summary (its last stdout line)
  run.log       the program's stderr (progress, warnings, errors)
  protocol.yaml the generated input (triax_run), results.h5 (triax_run's
                --out) or sample.h5 (triax_prepare's --out)
A program killed by a signal (kill -9, a Slurm time limit or cancel) leaves
no `runs/ID`: the next start of the sweep runs it again. Leftover partial
folders of a run are removed when the run starts again.
"""
import ctypes
import json
import os
import shutil
import signal
import socket
import subprocess
import time

from .fsutil import fsync_dir, write_atomic
from .plan import read_plan

PR_SET_PDEATHSIG = 1


def die_with_parent():
    """A preexec_fn: the child gets SIGKILL when this process dies (kill -9
    included), so a killed run leaves nothing running. A parent that died
    between fork and prctl is caught by the getppid check."""
    parent = os.getpid()

    def preexec():
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
        if os.getppid() != parent:
            os.kill(os.getpid(), signal.SIGKILL)
    return preexec


def is_published(out, run_id):
    return os.path.isfile(os.path.join(out, "runs", run_id, "status.json"))


def read_status(out, run_id):
    with open(os.path.join(out, "runs", run_id, "status.json"), encoding="utf-8") as f:
        return json.load(f)


def finished_runs(out):
    """(folder, status, summary) of every published run of the sweep in `out`,
    by run id; summary is {} when the program printed none (a failed run)."""
    runs = os.path.join(out, "runs")
    if not os.path.isdir(runs):
        return
    for run_id in sorted(os.listdir(runs)):
        if run_id.startswith(".") or not is_published(out, run_id):
            continue
        folder = os.path.join(runs, run_id)
        summary = {}
        if os.path.exists(os.path.join(folder, "summary.json")):
            with open(os.path.join(folder, "summary.json"), encoding="utf-8") as f:
                summary = json.load(f)
        yield folder, read_status(out, run_id), summary


def _utc():
    return time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())


def _last_json(text):
    for line in reversed(text.strip().splitlines()):
        line = line.strip()
        if line.startswith("{"):
            try:
                return json.loads(line), line
            except json.JSONDecodeError:
                return None, None
    return None, None


def _message(program, code, summary, log):
    if summary and summary.get("failure"):
        return str(summary["failure"])
    lines = [ln.strip() for ln in log.splitlines() if ln.strip()]
    errors = [ln for ln in lines if "error" in ln.lower()]
    line = (errors or lines or [f"exit code {code}"])[-1]
    return line.replace(f"{program}: error: ", "").replace(f"{program}: ", "")


def run_one(out, index, backend="local"):
    """Runs run `index` of the plan in `out`; returns 0 completed, 1 failed
    (both published), 3 not published (killed, or done by someone else)."""
    out = os.path.abspath(out)
    plan = read_plan(out)
    run = plan["runs"][index]
    runs_dir = os.path.join(out, "runs")
    final = os.path.join(runs_dir, run["id"])
    if is_published(out, run["id"]):
        return 0 if read_status(out, run["id"])["status"] == "completed" else 1
    for name in os.listdir(runs_dir):
        if name.startswith(f".partial-{run['id']}-"):
            shutil.rmtree(os.path.join(runs_dir, name), ignore_errors=True)
    host = socket.gethostname()
    work = os.path.join(runs_dir, f".partial-{run['id']}-{host}-{os.getpid()}")
    os.makedirs(work)
    program = plan["program_path"]
    name = os.path.basename(program)
    if plan["program"] == "triax_run":
        shutil.copyfile(os.path.join(out, run["input"]), os.path.join(work, "protocol.yaml"))
        cmd = [program, "protocol.yaml", "--out", "results.h5"]
    else:
        cmd = [program] + run["argv"]
    env = dict(os.environ, OMP_NUM_THREADS=str(plan["threads"]))
    started, t0 = _utc(), time.monotonic()
    with open(os.path.join(work, "stdout.txt"), "w") as so, open(os.path.join(work, "run.log"), "w") as se:
        cpu = 0.0
        try:
            child = subprocess.Popen(cmd, cwd=work, env=env, stdout=so, stderr=se, preexec_fn=die_with_parent())
            _, wstatus, usage = os.wait4(child.pid, 0)  # the program's own CPU time, whatever else runs
            child.returncode = code = os.waitstatus_to_exitcode(wstatus)
            cpu = usage.ru_utime + usage.ru_stime
        except OSError as e:
            se.write(f"{name}: error: cannot start {program}: {e.strerror}\n")
            code = 127
    wall = time.monotonic() - t0
    if code < 0:  # killed by a signal: not a result
        shutil.rmtree(work, ignore_errors=True)
        return 3
    with open(os.path.join(work, "stdout.txt")) as f:
        summary, line = _last_json(f.read())
    os.remove(os.path.join(work, "stdout.txt"))
    with open(os.path.join(work, "run.log")) as f:
        log = f.read()
    ok = code == 0 and summary is not None and summary.get("converged", True) is not False
    status = {
        "id": run["id"], "index": index, "values": run["values"], "status": "completed" if ok else "failed",
        "exit_code": code, "message": "" if ok else _message(name, code, summary, log),
        "wall_seconds": wall, "cpu_seconds": cpu, "host": host, "backend": backend, "started_utc": started, "finished_utc": _utc(),
    }
    if line:
        write_atomic(os.path.join(work, "summary.json"), line + "\n")
    write_atomic(os.path.join(work, "status.json"), json.dumps(status, indent=1, sort_keys=True) + "\n")
    for fname in os.listdir(work):
        fd = os.open(os.path.join(work, fname), os.O_RDONLY)
        os.fsync(fd)
        os.close(fd)
    try:
        os.rename(work, final)
    except OSError:  # published meanwhile by another attempt
        shutil.rmtree(work, ignore_errors=True)
        return 3
    fsync_dir(runs_dir)
    return 0 if ok else 1
