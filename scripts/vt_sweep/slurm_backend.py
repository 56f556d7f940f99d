"""Slurm backend: the runs not yet finished as one job array (`sbatch
--array=0-(n-1)%K`), one task per run, each task `run-one` on the shared
output folder (the same code as the local workers, so the same files).

OUT/slurm/ holds the submissions: `todo_N.txt` (array task -> run index),
`job_N.sh`, `jobs.txt` (job ids) and the task logs `JOBID_TASK.out`.
A task killed by Slurm (time limit, scancel, node failure) publishes
nothing, so the next submit runs it again; a sweep with a job still queued
or running is not submitted twice.
"""
import os
import shlex
import subprocess
import sys
import time

from .errors import SweepError
from .local_backend import SCRIPTS, forget_failed
from .plan import prepare
from .progress import Progress
from .run_one import is_published
from .table import counts, write_tables


def _slurm(cmd):
    try:
        return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    except OSError as e:
        raise SweepError("slurm", f"cannot run {cmd[0]}: {e.strerror} (is the Slurm client installed?)") from None


def job_tasks(job_id):
    """[(task, state)] of a job that squeue still lists (pending arrays as one
    line), [] when it has left the queue."""
    p = _slurm(["squeue", "-h", "-r", "-j", job_id, "-o", "%i %T"])
    if p.returncode != 0:
        return []
    return [tuple(line.split()[:2]) for line in p.stdout.splitlines() if line.strip()]


def active_jobs(out):
    path = os.path.join(out, "slurm", "jobs.txt")
    if not os.path.isfile(path):
        return []
    with open(path) as f:
        ids = [line.split()[0] for line in f if line.strip()]
    return [j for j in ids if job_tasks(j)]


def _job_script(out, todo_file):
    py = shlex.quote(sys.executable)
    return (
        "#!/bin/bash\n"
        "# one array task = one run of the sweep (vt_sweep/run_one.py)\n"
        "set -eu\n"
        f"index=$(sed -n \"$((SLURM_ARRAY_TASK_ID + 1))p\" {shlex.quote(todo_file)})\n"
        f"export PYTHONPATH={shlex.quote(SCRIPTS)}${{PYTHONPATH:+:$PYTHONPATH}}\n"
        f"exec {py} -m vt_sweep run-one {shlex.quote(out)} \"$index\" --backend slurm\n")


def sbatch_command(spec, n_tasks, script, options):
    """The sbatch command line: array, concurrency cap, resources, partition."""
    o = dict(spec.slurm)
    o.update({k: v for k, v in options.items() if v not in (None, [], "")})
    array = f"0-{n_tasks - 1}" + (f"%{o['max_parallel']}" if o.get("max_parallel") else "")
    cmd = ["sbatch", "--parsable", f"--array={array}", f"--job-name=vt_{spec.name}",
           f"--output={os.path.join(spec.output, 'slurm', '%A_%a.out')}", f"--cpus-per-task={spec.threads}",
           "--ntasks=1", f"--chdir={spec.output}"]
    for key in ("partition", "time", "mem"):
        if o.get(key):
            cmd.append(f"--{key}={o[key]}")
    cmd += list(o.get("extra_args") or [])
    return cmd + [script]


def submit(spec, options, wait=False, retry_failed=False, poll_seconds=2.0, stream=None, program_path=None):
    """Submits the unfinished runs; with `wait`, follows them to the end and
    writes the tables. Returns 0 (submitted; or all completed when waiting),
    1 some runs failed or are still missing after the job ended."""
    stream = stream or sys.stderr
    out = spec.output
    os.makedirs(os.path.join(out, "slurm"), exist_ok=True)
    busy = active_jobs(out)
    if busy:
        raise SweepError("slurm", f"job {', '.join(busy)} of this sweep is still queued or running "
                                  "(wait for it, or scancel it and submit again)")
    stream.write(f"triax_sweep: {spec.name}: checking the inputs\n")
    plan = prepare(spec, program_path)
    if retry_failed:
        forget_failed(out, plan)
    todo = [run["index"] for run in plan["runs"] if not is_published(out, run["id"])]
    if not todo:
        stream.write(f"triax_sweep: {spec.name}: every run has finished; nothing to submit\n")
        write_tables(out)
        c = counts(out, plan)
        return 0 if c["failed"] == 0 else 1
    sdir = os.path.join(out, "slurm")
    n = 1 + sum(1 for f in os.listdir(sdir) if f.startswith("todo_"))
    todo_file = os.path.join(sdir, f"todo_{n}.txt")
    script = os.path.join(sdir, f"job_{n}.sh")
    with open(todo_file, "w") as f:
        f.write("".join(f"{i}\n" for i in todo))
    with open(script, "w") as f:
        f.write(_job_script(out, todo_file))
    os.chmod(script, 0o755)
    cmd = sbatch_command(spec, len(todo), script, options)
    p = _slurm(cmd)
    if p.returncode != 0:
        raise SweepError("slurm", f"sbatch refused the job: {p.stderr.strip() or p.stdout.strip()}")
    job = p.stdout.strip().split(";")[0]
    with open(os.path.join(sdir, "jobs.txt"), "a") as f:
        f.write(f"{job} {len(todo)} {time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())}\n")
    stream.write(f"triax_sweep: {spec.name}: submitted job {job}: {len(todo)} of {len(plan['runs'])} runs "
                 f"({' '.join(shlex.quote(c) for c in cmd)})\n")
    if not wait:
        stream.write(f"triax_sweep: follow with `squeue -j {job}`; gather the results with "
                     f"`triax_sweep collect {spec.path or out}`\n")
        return 0
    prog = Progress(spec.name, len(plan["runs"]), 1, stream)
    before = counts(out, plan)
    while True:
        tasks = job_tasks(job)
        c = counts(out, plan)
        prog.finished_here = c["completed"] + c["failed"] - before["completed"] - before["failed"]
        prog.show(c["completed"], sum(1 for _, s in tasks if s == "RUNNING"), c["failed"])
        if not tasks:
            break
        time.sleep(poll_seconds)
    prog.close()
    write_tables(out)
    c = counts(out, plan)
    stream.write(f"triax_sweep: {spec.name}: job {job} ended: {c['completed']} completed, {c['failed']} failed, "
                 f"{c['pending']} missing (submit again to run those); wrote {os.path.join(out, 'sweep.csv')}\n")
    return 0 if c["failed"] == 0 and c["pending"] == 0 else 1
