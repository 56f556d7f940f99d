#!/usr/bin/python3
"""Test node of bag_report.test: checks scripts/bag_report.py on synthetic bags.

Writes a recording of a fake rig in the namespace /rig1, split into two bag
files (ticks 1..25 and 26..50, given to the tool in reverse order), with
Stress, Strain, MomentIndex, KineticEnergy, Fabric and ServoState messages
following closed forms of the tick k (q = 2 eps_a 1e5 Pa, ...), plus an
unrelated topic and the protocol node's status as the rig sends it (on
events and every SAMPLE-th tick: idle and a stage start at tick 0, a stage
end and the next stage's start at tick SPLIT, the last stage's end and the
verdict at the last tick, then a refused goal's status, which has no tick,
and a second test's start). Runs the tool as a subprocess and checks that
  - the CSV has one row per tick, ticks strictly rising, and its columns
    reproduce the closed forms to 1e-12 relative;
  - each row carries the protocol status that holds at its tick (a stage
    start from the tick after the one it is sent with, so the last tick of
    a stage or test keeps its own), and the tool warns of nothing (no rows
    of their own for the status messages, no "missing" or "seen twice");
  - a resumed recording (the killed run's files, with a verdict its
    surviving node sent, then the resumed run's files, which run ticks
    again from the checkpoint and send no stage start) gives the
    uninterrupted run's table byte for byte;
  - every PNG exists and is a non-empty PNG;
  - --csv-only writes no PNG;
  - a missing bag, and a bag without rig topics, give exit status 2 and a
    message naming the file.
No ROS master needed (rosbag only).
"""
import csv
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospy
from std_msgs.msg import String
from virtual_triaxial.msg import Fabric, KineticEnergy, MomentIndex, ProtocolStatus, ServoState, Strain, Stress

PKG = "virtual_triaxial"
HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.path.join(HERE, "..", "..", "scripts", "bag_report.py")
NTICKS = 50
SPLIT = 25
SAMPLE = 5  # the status is sent every SAMPLE-th tick
KILLED_AT = 37  # a killed run's last tick; it resumes from a checkpoint after RESUME_FROM - 1
RESUME_FROM = 33
PNGS = ["q_eps_a.png", "eps_v_eps_a.png", "q_p_stress_path.png", "e_log_p.png", "I_mom_eps_a.png",
        "kinetic_energy_eps_a.png"]
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def closed_form(k):
    """Expected values of tick k (SI, compression positive)."""
    eps_a = 1e-4 * k
    s3 = 1e5
    q = 2 * eps_a * 1e5
    s1 = s3 + q
    eps_v = 0.3 * eps_a - 5.0 * eps_a ** 2
    return {
        "time_s": 1e-6 * k + 0.5,
        "control_period_s": 6.2e-8,
        "sigma_xx_Pa": s3, "sigma_yy_Pa": s3, "sigma_zz_Pa": s1,
        "sigma_xy_Pa": 10.0 * k, "sigma_xz_Pa": -3.0 * k, "sigma_yz_Pa": 0.25 * k,
        "s1_Pa": s1, "s2_Pa": s3, "s3_Pa": s3,
        "p_Pa": (s1 + 2 * s3) / 3.0, "q_Pa": q, "phi_rad": math.asin(q / (s1 + s3)),
        "sigma_bar_p": (s1 + 2 * s3) / 3.0 / 7e10,
        "stiffness_x_Pa": 3e8 + k, "stiffness_y_Pa": 3e8 + 2 * k, "stiffness_z_Pa": 4e8 - k,
        "eps_a": eps_a, "eps_v": eps_v, "eps_x": -(eps_a - eps_v) / 2, "eps_y": -(eps_a - eps_v) / 2,
        "eps_z": eps_a,
        "eps_rate_z_per_s": 32.1, "eps_rate_dimensionless_z": 1e-5,
        "I_mom": 1e-4 * (1 + k), "ufr": 2e-4 / k, "I_uf": 3e-5 * k, "I_in": 1e-7 * k * k,
        "ke_trans_J": 1e-9 * k * k, "ke_rot_J": 3e-10 * k, "boundary_work_J": 1e-3 * k,
        "elastic_energy_J": 4e-4 * k, "damping_dissipation_J": 1e-5 * k, "friction_dissipation_J": 2e-4 * k,
        "energy_balance_error_J": 1e-12 * k, "energy_relative_balance_error": 1e-9 * k,
        "e": 0.65 - 1.65 * eps_v, "Z_mech": 4.5 - 1e-3 * k, "Z_raw": 4.1 + 1e-3 * k,
        "idle_mass_fraction": 0.05 + 1e-4 * k, "contacts": 400 + k, "sliding_contacts": k // 3,
        "servo_target_x_Pa": 1e5, "servo_error_x_Pa": 0.5 * k - 7.0, "servo_rate_x_per_s": -1e-3 * k,
        "servo_saturated_x": k % 2, "servo_enabled": 1,
    }


def messages(k):
    v = closed_form(k)
    stamp = rospy.Time.from_sec(v["time_s"])

    def hdr(m):
        m.header.stamp = stamp
        m.tick = k
        return m

    s = hdr(Stress())
    s.time = v["time_s"]
    s.control_period = v["control_period_s"]
    xy, xz, yz = v["sigma_xy_Pa"], v["sigma_xz_Pa"], v["sigma_yz_Pa"]
    s.stress = [v["sigma_xx_Pa"], xy, xz, xy, v["sigma_yy_Pa"], yz, xz, yz, v["sigma_zz_Pa"]]
    s.principal = [v["s1_Pa"], v["s2_Pa"], v["s3_Pa"]]
    s.p, s.q, s.phi, s.sigma_bar_p = v["p_Pa"], v["q_Pa"], v["phi_rad"], v["sigma_bar_p"]
    s.stiffness = [v["stiffness_x_Pa"], v["stiffness_y_Pa"], v["stiffness_z_Pa"]]
    e = hdr(Strain())
    e.time = v["time_s"]
    e.strain = [v["eps_x"], v["eps_y"], v["eps_z"]]
    e.volumetric = v["eps_v"]
    e.strain_rate = [0.0, 0.0, v["eps_rate_z_per_s"]]
    e.strain_rate_dimensionless = [0.0, 0.0, v["eps_rate_dimensionless_z"]]
    m = hdr(MomentIndex())
    m.time = v["time_s"]
    m.moment_index, m.ufr, m.iuf, m.inertia_index = v["I_mom"], v["ufr"], v["I_uf"], v["I_in"]
    ke = hdr(KineticEnergy())
    ke.time = v["time_s"]
    ke.translational, ke.rotational = v["ke_trans_J"], v["ke_rot_J"]
    ke.boundary_work, ke.elastic = v["boundary_work_J"], v["elastic_energy_J"]
    ke.damping, ke.friction = v["damping_dissipation_J"], v["friction_dissipation_J"]
    ke.balance_error, ke.relative_balance_error = v["energy_balance_error_J"], v["energy_relative_balance_error"]
    f = hdr(Fabric())
    f.time = v["time_s"]
    f.void_ratio, f.coordination_number, f.raw_coordination_number = v["e"], v["Z_mech"], v["Z_raw"]
    f.idle_mass_fraction, f.contacts, f.sliding_contacts = v["idle_mass_fraction"], v["contacts"], v["sliding_contacts"]
    sv = hdr(ServoState())
    sv.strategy = "proportional"
    sv.enabled = True
    sv.controlled = [True, True, False]
    sv.targets = [v["servo_target_x_Pa"], 1e5, 0.0]
    sv.errors = [v["servo_error_x_Pa"], 0.0, 0.0]
    sv.saturated = [bool(v["servo_saturated_x"]), False, False]
    sv.strain_rate = [v["servo_rate_x_per_s"], 0.0, 0.0]
    sv.gain, sv.max_strain_rate = 1.0, 321.0
    return stamp, [("/rig1/stress", s), ("/rig1/strain", e), ("/rig1/moment_index", m),
                   ("/rig1/kinetic_energy", ke), ("/rig1/fabric", f), ("/rig1/servo_state", sv),
                   ("/chatter", String(data="not a rig topic %d" % k))]


def status(tick, state, stage, index, eps_a=0.0, message=""):
    s = ProtocolStatus()
    s.tick, s.state, s.protocol, s.stage, s.stage_index, s.stage_count = tick, state, "synthetic", stage, index, 2
    s.eps_a, s.message = eps_a, message
    return s


def status_messages(k, resumed=False):
    """The status messages sent while tick k is recorded (tick 0: before the
    first), as test_protocol_node sends them; a resumed run's node starts
    idle and sends no start of the stage it resumes."""
    out = []
    if k == 0:
        out = [status(0, "idle", "", 0), status(0, "running", "consolidation", 0)]
    elif k == SPLIT:
        out = [status(k, "running", "consolidation", 0, 1e-4 * k, "balanced"),
               status(k, "running", "shear", 1)]  # the next stage starts after tick k
    elif k == NTICKS:
        end = status(k, "running", "shear", 1, 1e-4 * k, "axial strain")
        verdict = status(k, "completed", "shear", 1, 1e-4 * k, "axial strain")  # the last status, final state
        out = [end, verdict, status(0, "failed", "", 0, 0.0, "refused: bad goal"),  # a refused goal: no tick
               status(k, "running", "consolidation", 0)]  # a second test starts after tick k
        out[-1].protocol = "second"
    elif k % SAMPLE == 0:
        out = [status(k, "running", "consolidation" if k < SPLIT else "shear", 0 if k < SPLIT else 1, 1e-4 * k)]
    return [status(0, "idle", "", 0)] + out if resumed and k == RESUME_FROM else out


def expected_status(k):
    """(state, stage, stage_eps_a) a row of tick k carries."""
    if k == NTICKS:
        return "completed", "shear", 1e-4 * k
    if k <= SPLIT:
        return "running", "consolidation", 1e-4 * (k - k % SAMPLE)
    return "running", "shear", 0.0 if k < SPLIT + SAMPLE else 1e-4 * (k - k % SAMPLE)


def write_bag(path, ticks, resumed=False, verdict=None):
    """Ticks of the rig and the statuses sent with them into one file."""
    with rosbag.Bag(path, "w") as bag:
        for k in ticks:
            stamp = rospy.Time.from_sec(1e-6 * k + 0.5)  # closed_form's time_s
            if k > 0:
                for topic, msg in messages(k)[1]:
                    bag.write(topic, msg, t=stamp)
            sent = status_messages(k, resumed) + ([verdict] if verdict is not None and k == ticks[-1] else [])
            for n, msg in enumerate(sent):  # after the tick's state, in order
                # a resumed rig's recorder may take its node's latched idle
                # status before the first /clock, at time 0: that file then
                # starts before the killed run's (session 35's unit_rig_resume)
                t = rospy.Time(0) if resumed and msg.state == "idle" else stamp + rospy.Duration(0, 1000 * (n + 1))
                bag.write("/rig1/protocol_status", msg, t=t)


def run_tool(*args):
    return subprocess.run(["/usr/bin/python3", TOOL] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, timeout=300)


class BagReportTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="vt_bag_report_")
        cls.bags = [os.path.join(cls.tmp, "rig_%d.bag" % i) for i in range(2)]
        write_bag(cls.bags[0], list(range(0, SPLIT + 1)))
        write_bag(cls.bags[1], list(range(SPLIT + 1, NTICKS + 1)))
        # the same test killed after tick KILLED_AT (its node, still alive, sends
        # a verdict), then resumed: ticks RESUME_FROM.. run again in new files
        cls.resumed_bags = [cls.bags[0], os.path.join(cls.tmp, "rig_killed.bag"), os.path.join(cls.tmp, "rig_r1_0.bag")]
        write_bag(cls.resumed_bags[1], list(range(SPLIT + 1, KILLED_AT + 1)),
                  verdict=status(KILLED_AT, "failed", "shear", 1, 1e-4 * KILLED_AT, "servo died"))
        write_bag(cls.resumed_bags[2], list(range(RESUME_FROM, NTICKS + 1)), resumed=True)
        cls.out = os.path.join(cls.tmp, "report")
        # split files given in reverse order: the tool must read them in time order
        cls.result = run_tool(cls.bags[1], cls.bags[0], "--out", cls.out)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def rows(self):
        with open(os.path.join(self.out, "rig_series.csv"), newline="") as f:
            return list(csv.DictReader(f))

    def test_tool_succeeds_and_says_what_it_wrote(self):
        r = self.result
        self.assertEqual(r.returncode, 0, "stdout:\n%s\nstderr:\n%s" % (r.stdout, r.stderr))
        self.assertIn(os.path.join(self.out, "rig_series.csv"), r.stdout)
        for png in PNGS:
            self.assertIn(os.path.join(self.out, png), r.stdout)

    def test_rows_carry_the_status_that_holds_and_nothing_is_warned(self):
        self.assertNotIn("warning", self.result.stderr)
        rows = self.rows()
        self.assertEqual(len(rows), NTICKS)
        for r in rows:
            k = int(r["tick"])
            state, stage, eps = expected_status(k)
            self.assertEqual((r["protocol_state"], r["protocol_stage"]), (state, stage), "tick %d" % k)
            self.assertAlmostEqual(float(r["stage_eps_a"]), eps, delta=1e-15, msg="tick %d" % k)

    def test_a_resumed_recording_gives_the_uninterrupted_table(self):
        out = os.path.join(self.tmp, "resumed")
        # given in reverse: the resumed file, whose first message (its idle
        # status, time 0) is the earliest of all, must still be read last
        r = run_tool(*reversed(self.resumed_bags), "--out", out, "--csv-only")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("seen twice", r.stderr)  # the ticks run again are said (their later message is used)
        with open(os.path.join(out, "rig_series.csv")) as f, open(os.path.join(self.out, "rig_series.csv")) as g:
            self.assertEqual(f.read(), g.read())

    def test_resumed_files_are_known_by_name_beside_the_run_they_resume(self):
        sys.path.insert(0, os.path.dirname(TOOL))
        import bag_report
        def numbers(*names):
            stems = {bag_report.split_stem(n) for n in names}
            return [bag_report.resume_number(n, stems) for n in names]
        self.assertEqual(numbers("rig_0.bag", "rig_1.bag", "rig_r1_0.bag", "rig_r2_3.bag"), [0, 0, 1, 2])
        # a prefix that itself ends in _rN: only a resume of a given run counts
        self.assertEqual(numbers("x_r2_0.bag", "x_r2_r1_0.bag"), [0, 1])
        self.assertEqual(numbers("rig_r1_0.bag", "rig_r1_1.bag"), [0, 0])  # the run resumed is not given
        self.assertEqual(numbers("a.bag", "a_r1.bag", "rig_killed.bag"), [0, 0, 0])

    def test_one_row_per_tick_strictly_rising(self):
        rows = self.rows()
        self.assertEqual(len(rows), NTICKS)
        ticks = [int(r["tick"]) for r in rows]
        self.assertEqual(ticks, list(range(1, NTICKS + 1)))
        self.assertTrue(all(b > a for a, b in zip(ticks, ticks[1:])))

    def test_columns_reproduce_the_closed_form(self):
        rows = self.rows()
        self.assertEqual(len(rows), NTICKS)
        for key in ("time_s", "eps_a", "eps_v", "p_Pa", "q_Pa", "phi_rad", "e", "I_mom", "ufr", "ke_trans_J"):
            self.assertIn(key, rows[0], "column %s missing; have %s" % (key, sorted(rows[0])))
        for r in rows:
            k = int(r["tick"])
            want = closed_form(k)
            for key, v in want.items():
                self.assertIn(key, r, "column %s missing" % key)
                got = float(r[key])
                self.assertLessEqual(abs(got - v), 1e-12 * abs(v), "tick %d %s: %r != %r" % (k, key, got, v))
            # the closed form of the brief, checked directly as well
            self.assertLessEqual(abs(float(r["q_Pa"]) - 2 * float(r["eps_a"]) * 1e5), 1e-12 * float(r["q_Pa"]))
            self.assertAlmostEqual(float(r["phi_deg"]), math.degrees(want["phi_rad"]), delta=1e-12 * 90)

    def test_every_png_is_a_non_empty_png(self):
        for png in PNGS:
            path = os.path.join(self.out, png)
            self.assertTrue(os.path.isfile(path), path)
            self.assertGreater(os.path.getsize(path), 1000, path)
            with open(path, "rb") as f:
                self.assertEqual(f.read(8), PNG_MAGIC, path)

    def test_csv_only_writes_no_png(self):
        out = os.path.join(self.tmp, "csv_only")
        r = run_tool(self.bags[0], "--out", out, "--csv-only")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(sorted(os.listdir(out)), ["rig_series.csv"])
        with open(os.path.join(out, "rig_series.csv"), newline="") as f:
            self.assertEqual(len(list(csv.DictReader(f))), SPLIT)

    def test_missing_bag_exits_2_naming_the_path(self):
        missing = os.path.join(self.tmp, "no_such_recording.bag")
        r = run_tool(self.bags[0], missing, "--out", os.path.join(self.tmp, "x"))
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn(missing, r.stderr)
        self.assertNotIn("Traceback", r.stderr)

    def test_bag_without_rig_topics_exits_2_naming_the_file(self):
        path = os.path.join(self.tmp, "chatter.bag")
        with rosbag.Bag(path, "w") as bag:
            bag.write("/chatter", String(data="hello"), t=rospy.Time(1, 0))
        r = run_tool(path, "--out", os.path.join(self.tmp, "y"))
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn(path, r.stderr)
        self.assertIn("no rig topics", r.stderr)
        self.assertNotIn("Traceback", r.stderr)

    def test_not_a_bag_exits_2_naming_the_file(self):
        path = os.path.join(self.tmp, "garbage.bag")
        with open(path, "w") as f:
            f.write("this is not a bag\n")
        r = run_tool(path, "--out", os.path.join(self.tmp, "z"))
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn(path, r.stderr)
        self.assertNotIn("Traceback", r.stderr)


if __name__ == "__main__":
    import rostest
    rostest.rosrun(PKG, "bag_report_check", BagReportTest, sys.argv)
