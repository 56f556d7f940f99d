#!/usr/bin/python3
"""triax_sweep, local backend and sweep files (run by ctest, needs the built triax_run).

- sweep files: each bad file is refused with exit code 2 and one line naming
  the dotted path; the runs of a grid / zip come in the documented order and
  each generated protocol carries exactly its values (read back as yaml-cpp
  would, sample_file made absolute);
- kill -9 of the driver and its workers mid-way, then a restart: the runs
  published before the kill are not redone (same inode and mtime of their
  files), nothing is missing, and the table equals that of an uninterrupted
  sweep byte for byte (runs are deterministic);
- a run with a corrupt sample file fails with triax_run's message while the
  other runs complete, and the sweep reports it.
"""
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
TRIAX_SWEEP = os.path.join(REPO, "scripts", "triax_sweep")
BASE = os.path.join(REPO, "tests", "data", "protocols", "sweep_mini.yaml")
SAMPLE = os.path.join(REPO, "tests", "data", "sample_200_100kPa.h5")
sys.path.insert(0, os.path.join(REPO, "scripts"))

import yaml  # noqa: E402

from vt_sweep.spec import load_spec  # noqa: E402
from vt_sweep.strict_yaml import StrictLoader  # noqa: E402


def sweep(args, **kw):
    return subprocess.run([TRIAX_SWEEP] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def descendants(pid):
    """Every live descendant of `pid` (from /proc)."""
    children = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as f:
                    ppid = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            children.setdefault(ppid, []).append(int(d))
    out, todo = [], [pid]
    while todo:
        for c in children.get(todo.pop(), []):
            out.append(c)
            todo.append(c)
    return out


def alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


class SweepFiles(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="vt_sweep_spec_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def write(self, doc, name="s.yaml"):
        path = os.path.join(self.tmp, name)
        with open(path, "w") as f:
            f.write(doc if isinstance(doc, str) else yaml.safe_dump(doc, sort_keys=False))
        return path

    def base_doc(self, **kw):
        d = {"name": "t", "output": os.path.join(self.tmp, "out"), "base": BASE,
             "parameters": {"damping.ratio": [0.003, 0.01]}}
        d.update(kw)
        return d

    def test_bad_files_name_the_dotted_path(self):
        cases = [
            (self.base_doc(colour=1), "colour: unknown key"),
            (self.base_doc(parameters={"stages[3].strain_rate_dimensionless": [1e-5]}),
             "parameters.stages[3].strain_rate_dimensionless: 'stages[3]' does not exist in the base file"),
            (self.base_doc(parameters={"damping.ratio": 0.1}), "parameters.damping.ratio: must be a non-empty list"),
            (self.base_doc(parameters={"damping.ratio": [0.01, "x"]}), "parameters.damping.ratio[1]:"),
            (self.base_doc(parameters={"damping.ratio": [0.01, -1.0]}), "parameters.damping.ratio[1]:"),
            (self.base_doc(parameters={"damping.colour": [1, 2]}), "parameters.damping.colour"),
            (self.base_doc(parameters={"stages[0].stop.axial_strain": [0.01, -0.1]}),
             "parameters.stages[0].stop.axial_strain[1]:"),
            (self.base_doc(parameters={"particles.sample_file": ["nope.h5"]}),
             "parameters.particles.sample_file[0]: no such file"),
            (self.base_doc(combine="zip", parameters={"damping.ratio": [0.01, 0.02], "material.friction": [0.3]}),
             "parameters.material.friction: 1 values, but parameters.damping.ratio has 2"),
            (self.base_doc(combine="mesh"), "combine: must be grid or zip"),
            (self.base_doc(threads=0), "threads: must be an integer >= 1"),
            (self.base_doc(base="missing.yaml"), "base: no such file"),
            (self.base_doc(slurm={"partitions": "x"}), "slurm.partitions: unknown key"),
            ("name: a\nname: b\n", "duplicated key 'name'"),
        ]
        for doc, expect in cases:
            r = sweep(["check", self.write(doc)])
            self.assertEqual(r.returncode, 2, f"{expect}: {r.stderr}")
            self.assertIn(expect, r.stderr)
            self.assertEqual(r.stderr.count("\n"), 1, r.stderr)
        # the refusal of a value comes with triax_run's own reason
        r = sweep(["check", self.write(self.base_doc(parameters={"damping.ratio": [0.01, -1.0]}))])
        self.assertIn("damping.ratio: must be a finite damping ratio >= 0, got -1", r.stderr)

    def test_grid_and_zip_order_and_generated_inputs(self):
        params = {"stages[0].strain_rate_dimensionless": [1e-4, 5e-5], "damping.ratio": [0.003, 0.01, 0.1]}
        spec = load_spec(self.write(self.base_doc(parameters=params)))
        combos = spec.combinations()
        self.assertEqual(len(combos), 6)
        self.assertEqual([(c["stages[0].strain_rate_dimensionless"], c["damping.ratio"]) for c in combos],
                         [(a, b) for a in params["stages[0].strain_rate_dimensionless"]
                          for b in params["damping.ratio"]])
        zspec = load_spec(self.write(self.base_doc(combine="zip", parameters={
            "damping.ratio": [0.003, 0.01], "material.friction": [0.3, 0.4]})))
        self.assertEqual(zspec.combinations(), [{"damping.ratio": 0.003, "material.friction": 0.3},
                                                {"damping.ratio": 0.01, "material.friction": 0.4}])
        out = os.path.join(self.tmp, "out")
        r = sweep(["check", self.write(self.base_doc(parameters=params))])
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "sweep.json")) as f:
            plan = json.load(f)
        with open(BASE) as f:
            base = yaml.load(f, Loader=StrictLoader)
        for run, combo in zip(plan["runs"], combos):
            with open(os.path.join(out, run["input"])) as f:
                gen = yaml.load(f, Loader=StrictLoader)
            self.assertEqual(gen["stages"][0]["strain_rate_dimensionless"], combo["stages[0].strain_rate_dimensionless"])
            self.assertEqual(gen["damping"]["ratio"], combo["damping.ratio"])
            self.assertEqual(gen["particles"]["sample_file"], SAMPLE)
            # everything else is the base file's
            gen["stages"][0]["strain_rate_dimensionless"] = base["stages"][0]["strain_rate_dimensionless"]
            gen["damping"]["ratio"] = base["damping"]["ratio"]
            gen["particles"]["sample_file"] = base["particles"]["sample_file"]
            self.assertEqual(gen, base)
        self.assertEqual(len({r["id"] for r in plan["runs"]}), 6)


class LocalBackend(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="vt_sweep_local_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def sweep_file(self, parameters, name="kill"):
        path = os.path.join(self.tmp, f"{name}.yaml")
        with open(path, "w") as f:
            yaml.safe_dump({"name": name, "output": os.path.join(self.tmp, name), "base": BASE,
                            "parameters": parameters}, f, sort_keys=False)
        return path

    def test_kill_nine_then_restart_redoes_nothing_finished(self):
        # 8 runs of ~1500 DEM steps each, 2 workers
        path = self.sweep_file({"stages[0].stop.axial_strain": [0.015, 0.0151, 0.0152, 0.0153],
                                "damping.ratio": [0.003, 0.01]})
        out = os.path.join(self.tmp, "kill")
        runs = os.path.join(out, "runs")
        driver = subprocess.Popen([TRIAX_SWEEP, path, "-j", "2"], stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL, start_new_session=True)
        deadline = time.monotonic() + 120
        published = []
        while time.monotonic() < deadline:
            published = [d for d in os.listdir(runs) if not d.startswith(".")] if os.path.isdir(runs) else []
            if len(published) >= 3:
                break
            time.sleep(0.05)
        self.assertGreaterEqual(len(published), 3, "the sweep did not get going")
        # The driver starts the next worker right after one ends: poll over
        # that gap (a look at the instant a run ends may find none alive).
        victims, workers = [driver.pid], []
        while time.monotonic() < deadline and driver.poll() is None:
            victims = [driver.pid] + descendants(driver.pid)
            workers = [p for p in victims[1:] if alive(p)]
            if workers:
                break
            time.sleep(0.005)
        self.assertGreaterEqual(len(workers), 1, "expected running workers to kill")
        for p in victims:
            try:
                os.kill(p, signal.SIGKILL)
            except ProcessLookupError:
                pass
        driver.wait()
        for _ in range(100):  # a killed process may take a moment to be reaped on a busy machine
            if not [p for p in victims if alive(p)]:
                break
            time.sleep(0.05)
        self.assertFalse([p for p in victims if alive(p)], "a process of the killed sweep survived")
        done = sorted(d for d in os.listdir(runs) if not d.startswith("."))
        self.assertLess(len(done), 8, "the sweep finished before the kill: nothing tested")
        stamps = {}
        for d in done:
            for fname in os.listdir(os.path.join(runs, d)):
                st = os.stat(os.path.join(runs, d, fname))
                stamps[(d, fname)] = (st.st_ino, st.st_mtime_ns, st.st_size)
        r = sweep([path, "-j", "2"])
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(f"{len(done)} already finished (0 failed), {8 - len(done)} to run", r.stderr)
        for (d, fname), before in stamps.items():
            st = os.stat(os.path.join(runs, d, fname))
            self.assertEqual((st.st_ino, st.st_mtime_ns, st.st_size), before, f"{d}/{fname} was redone")
        self.assertEqual(sorted(os.listdir(runs)), sorted(r["run"] for r in read_csv(os.path.join(out, "sweep.csv"))),
                         "leftover partial folders or missing runs")
        rows = read_csv(os.path.join(out, "sweep.csv"))
        self.assertEqual([r["status"] for r in rows], ["completed"] * 8)
        for row in rows:
            self.assertEqual(row["verdict"], "completed")
            self.assertGreater(float(row["steps"]), 1000)
        # nothing corrupt: the same sweep without a kill gives the same table, byte for byte
        ref = sweep([path, "-j", "2", "--out", os.path.join(self.tmp, "ref")])
        self.assertEqual(ref.returncode, 0, ref.stderr)
        with open(os.path.join(out, "sweep.csv"), "rb") as a, open(os.path.join(self.tmp, "ref", "sweep.csv"), "rb") as b:
            self.assertEqual(a.read(), b.read())
        # a restart with everything finished runs nothing
        again = sweep([path, "-j", "2"])
        self.assertIn("8 already finished (0 failed), 0 to run", again.stderr)

    def test_bad_run_is_reported_and_the_others_finish(self):
        corrupt = os.path.join(self.tmp, "corrupt.h5")
        with open(corrupt, "wb") as f:
            f.write(b"this is not an HDF5 file\n" * 10)
        path = self.sweep_file({"particles.sample_file": [SAMPLE, corrupt], "damping.ratio": [0.003, 0.01]}, "bad")
        r = sweep([path, "-j", "2"])
        self.assertEqual(r.returncode, 1, r.stderr)
        rows = read_csv(os.path.join(self.tmp, "bad", "sweep.csv"))
        self.assertEqual([r["status"] for r in rows], ["completed", "completed", "failed", "failed"])
        for row in rows[2:]:
            self.assertEqual(row["exit_code"], "2")
            self.assertIn("corrupt.h5", row["message"])
            self.assertIn(row["message"], r.stderr)  # the driver printed it
        for row in rows[:2]:
            self.assertEqual(row["exit_code"], "0")
            self.assertEqual(row["message"], "")
            self.assertEqual(row["verdict"], "completed")
        self.assertIn("2 completed, 2 failed", r.stderr)
        # units in the parameter columns
        self.assertIn("damping.ratio [-]", rows[0])
        self.assertIn("particles.sample_file [text]", rows[0])


if __name__ == "__main__":
    unittest.main()
