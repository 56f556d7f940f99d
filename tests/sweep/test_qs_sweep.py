#!/usr/bin/python3
"""triax_qs rate-sweep / damping-sweep (run by ctest; needs the built
triax_run and triax_qs). Tiny real runs: the shipped dense_1000 sample,
drained shear to 0.5 % axial strain at eps' = 1e-4 .. 1.25e-5 (about a
second each, tests/data/protocols/qs_sweep_mini.yaml).

- rate sweep: the fit on real runs is triax_qs fit-rates' on the same
  summaries (one home for the fit), the trend is physical (I_mom and
  phi_peak rise with eps', so b > 0, eps'_QS lies below the slowest rate and
  phi_QS below the slowest run's phi_peak), the report folder is complete
  and the last stdout line is the result, keys named with their units;
- resumability: a second call with one more rate runs only that one (the
  finished runs' files keep their inode and mtime);
- a run that fails (unstable, exit 3) is reported with its message, the
  others are fitted, and the command exits with the run's code;
- damping sweep: the optimum xi of four real runs lies between the
  neighbours of the lowest run, as triax_qs fit-damping finds it;
- bad input: exit code 2 and one line naming the option or field.
"""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
BIN = os.environ.get("VT_PROGRAM_DIR") or os.path.join(REPO, "build", "devel", "lib", "virtual_triaxial")
TRIAX_QS = os.path.join(BIN, "triax_qs")
PROTOCOL = os.path.join(REPO, "tests", "data", "protocols", "qs_sweep_mini.yaml")
RATES = [1e-4, 5e-5, 2.5e-5]


def qs(args):
    p = subprocess.run([TRIAX_QS] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith("{")]
    return p.returncode, (json.loads(lines[-1]) if lines else None), p.stderr


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


def stamps(out):
    runs = os.path.join(out, "sweep", "runs")
    return {d: (os.stat(os.path.join(runs, d, "summary.json")).st_ino,
                os.stat(os.path.join(runs, d, "summary.json")).st_mtime_ns) for d in os.listdir(runs)}


class RateSweep(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="vt_qs_rate_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_fit_on_real_runs_report_and_resume(self):
        out = os.path.join(self.tmp, "report")
        code, res, err = qs(["rate-sweep", PROTOCOL, "--rates", ",".join(map(repr, RATES)), "--jobs", "2",
                             "--out", out])
        self.assertEqual(code, 0, err)
        self.assertIn("ETA", err)
        self.assertEqual((res["runs"], res["runs_completed"], res["runs_failed"]), (3, 3, 0))
        self.assertEqual(res["quasi_static_threshold"], 1e-3)   # the protocol's I_QS
        runs = read_csv(os.path.join(out, "runs.csv"))
        self.assertEqual([float(r["eps_prime"]) for r in runs], RATES)
        self.assertTrue(all(r["status"] == "completed" for r in runs))
        imom = [float(r["mean_moment_index_to_peak"]) for r in runs]
        phi = [float(r["phi_peak_deg"]) for r in runs]
        # faster is more dynamic and stronger (figs. 66-69): strictly decreasing down the rates
        self.assertTrue(imom[0] > imom[1] > imom[2], imom)
        self.assertTrue(phi[0] > phi[1] > phi[2], phi)
        self.assertGreater(res["b_i_eq73"], 0.0)
        self.assertLess(res["eps_prime_qs_eq73"], min(RATES))    # every run is above I_QS
        self.assertLess(res["phi_qs_eq74_deg"], min(phi))
        self.assertLess(res["eps_prime_qs_eq73_low_1se"], res["eps_prime_qs_eq73"])
        self.assertGreater(res["eps_prime_qs_eq73_high_1se"], res["eps_prime_qs_eq73"])
        self.assertAlmostEqual(res["strain_rate_qs_eq73_per_s"] / (res["eps_prime_qs_eq73"] / res["t0_s"]), 1, 5)
        # the fit is triax_qs fit-rates' on the runs' own summaries
        direct_args = ["fit-rates"]
        for r in runs:
            direct_args += ["--run", "%s,%s" % (r["eps_prime"], os.path.join(out, "sweep", "runs", r["run"],
                                                                                "summary.json"))]
        c2, direct, err2 = qs(direct_args)
        self.assertEqual(c2, 0, err2)
        for k, v in direct.items():
            if k != "runs":
                self.assertEqual(res[k], v, k)
        with open(os.path.join(out, "fit.json")) as f:
            self.assertEqual(json.load(f), direct)
        with open(os.path.join(out, "result.json")) as f:
            self.assertEqual(json.load(f), res)
        for png in ("i_mom_vs_rate.png", "tan_phi_vs_i_mom.png", "q_eps_a.png"):
            self.assertTrue(is_png(os.path.join(out, png)), png)
        curves = read_csv(os.path.join(out, "q_eps_a.csv"))
        self.assertEqual({r["run"] for r in curves}, {r["run"] for r in runs})
        self.assertTrue(all(0 < float(c["eps_a"]) <= 0.0052 for c in curves))   # shear rows only
        self.assertTrue(all(float(c["q_pa"]) > 0 for c in curves))

        # resume: one more rate; the three finished runs are reused untouched
        before = stamps(out)
        code, res2, err = qs(["rate-sweep", PROTOCOL, "--rates", ",".join(map(repr, RATES + [1.25e-5])),
                              "--out", out])
        self.assertEqual(code, 0, err)
        self.assertIn("3 already finished", err)
        after = stamps(out)
        self.assertEqual(len(after), 4)
        for d, s in before.items():
            self.assertEqual(after[d], s, d)
        self.assertEqual(res2["runs_completed"], 4)
        self.assertEqual(len(read_csv(os.path.join(out, "runs.csv"))), 4)


class FailedRun(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="vt_qs_failed_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_unstable_run_is_reported_and_the_rest_fitted(self):
        # eps' above 1e-3 is refused before any run (io/run_limits.h); at
        # c_t = 3 (within the limit 10, above the critical 1) eps' = 1e-3
        # overlaps the particles beyond the limit (triax_run exits 3) while
        # 2e-5 and 1e-5 complete
        with open(PROTOCOL) as f:
            text = f.read()
        text = text.replace("time_step_ratio: 0.3", "time_step_ratio: 3.0").replace(
            "../../../config/samples/", os.path.join(REPO, "config", "samples") + "/")
        protocol = os.path.join(self.tmp, "qs_sweep_mini_ct3.yaml")
        with open(protocol, "w") as f:
            f.write(text)
        out = os.path.join(self.tmp, "report")
        code, res, err = qs(["rate-sweep", protocol, "--rates", "1e-3,2e-5,1e-5", "--out", out])
        self.assertEqual(code, 3, err)
        self.assertEqual((res["runs"], res["runs_completed"], res["runs_failed"]), (3, 2, 1))
        runs = read_csv(os.path.join(out, "runs.csv"))
        self.assertEqual([r["status"] for r in runs], ["failed", "completed", "completed"])
        self.assertEqual(runs[0]["exit_code"], "3")
        self.assertIn("overlap", runs[0]["message"])
        self.assertIn("eps_prime_qs_eq73", res)          # fitted on the two completed runs
        self.assertNotIn("eps_prime_qs_eq73_low_1se", res)  # two points: no uncertainty to state


class DampingSweep(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="vt_qs_damping_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_optimum_on_real_runs(self):
        out = os.path.join(self.tmp, "report")
        ratios = [0.003, 0.01, 0.03, 0.1]
        code, res, err = qs(["damping-sweep", PROTOCOL, "--ratios", ",".join(map(repr, ratios)), "--model", "OD",
                             "--rate", "2.5e-5", "--out", out])
        self.assertEqual(code, 0, err)
        runs = read_csv(os.path.join(out, "runs.csv"))
        self.assertEqual([float(r["damping_ratio"]) for r in runs], ratios)
        self.assertTrue(all(float(r["eps_prime"]) == 2.5e-5 and r["damping_model"] == "OD" for r in runs))
        imom = [float(r["mean_moment_index_to_peak"]) for r in runs]
        k = imom.index(min(imom))
        self.assertTrue(0 < k < len(ratios) - 1, imom)   # a bracketed minimum (else the test says nothing)
        self.assertGreater(res["optimum_damping_ratio"], ratios[k - 1])
        self.assertLess(res["optimum_damping_ratio"], ratios[k + 1])
        self.assertLessEqual(res["min_mean_moment_index"], min(imom))
        direct_args = ["fit-damping"]
        for r in runs:
            direct_args += ["--run", "%s,%s,%s" % (r["damping_ratio"], r["eps_prime"],
                                                   os.path.join(out, "sweep", "runs", r["run"], "summary.json"))]
        c2, direct, err2 = qs(direct_args)
        self.assertEqual(c2, 0, err2)
        for k_, v in direct.items():
            if k_ != "runs":
                self.assertEqual(res[k_], v, k_)
        for png in ("i_mom_vs_damping.png", "tan_phi_vs_i_mom.png", "q_eps_a.png"):
            self.assertTrue(is_png(os.path.join(out, png)), png)


class BadInput(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="vt_qs_bad_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def protocol(self, edit):
        import yaml
        with open(PROTOCOL) as f:
            doc = yaml.safe_load(f)
        doc["particles"]["sample_file"] = os.path.join(REPO, "config", "samples", "dense_1000.h5")
        edit(doc)
        path = os.path.join(self.tmp, "p.yaml")
        with open(path, "w") as f:
            yaml.safe_dump(doc, f)
        return path

    def refused(self, args, field):
        out = os.path.join(self.tmp, "out")
        code, res, err = qs(args + ["--out", out])
        self.assertEqual(code, 2, err)
        self.assertIsNone(res)
        errors = [ln for ln in err.splitlines() if "error:" in ln]
        self.assertEqual(len(errors), 1, err)
        self.assertTrue(errors[0].startswith("triax_qs: error: " + field + ":"), errors[0])
        return errors[0], out

    def test_options(self):
        r = ["rate-sweep", PROTOCOL, "--rates"]
        d = ["damping-sweep", PROTOCOL]
        for args, field in [
                (r + ["1e-5,abc"], "--rates[1]"),
                (r + ["1e-5"], "--rates"),
                (r + ["1e-5,-2e-6"], "--rates[1]"),
                (r + ["1e-5,1e-5"], "--rates"),
                (r + ["1e-5,2e-6", "--jobs", "0"], "--jobs"),
                (r + ["1e-5,2e-6", "--backend", "cloud"], "--backend"),
                (["rate-sweep", PROTOCOL], "--rates"),
                (d + ["--ratios", "0.01,0.02,0.03", "--model", "XD", "--rate", "1e-5"], "--model"),
                (d + ["--ratios", "0.01,0.02", "--model", "OD", "--rate", "1e-5"], "--ratios"),
                (d + ["--ratios", "0.01,0.02,0.03", "--model", "OD"], "--rate"),
                (d + ["--ratios", "0.01,0.02,0.03", "--model", "ND", "--rate", "fast"], "--rate"),
                (["rate-sweep", os.path.join(self.tmp, "missing.yaml"), "--rates", "1e-5,2e-6"], "PROTOCOL.yaml")]:
            with self.subTest(args=args):
                _, out = self.refused(args, field)
                self.assertFalse(os.path.exists(out))   # refused before anything is written

    def test_protocol_without_shear_stage(self):
        p = self.protocol(lambda d: d["stages"].pop(1))
        self.refused(["rate-sweep", p, "--rates", "1e-5,2e-6"], "stages")

    def test_protocol_triax_run_refuses(self):
        p = self.protocol(lambda d: d["material"].update(friction=-0.5))
        line, _ = self.refused(["rate-sweep", p, "--rates", "1e-5,2e-6"], "runs[0]")
        self.assertIn("material.friction", line)


if __name__ == "__main__":
    unittest.main(verbosity=2)
