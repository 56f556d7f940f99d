#!/usr/bin/python3
"""Test node of specimen_vtk.test: VTK snapshots read back by an independent reader.

Reads the files with Debian's python3-vtk9 (vtkXMLPolyDataReader; the
writer is our own C++ code, io/vtk_snapshot_writer.h) and checks them
against the run's own numbers:
  1. `triax_run tests/data/protocols/snapshot_mini.yaml --specimen DIR`
     (200 spheres, consolidation + drained shear, output.snapshot_interval
     2000 steps): the collections list every snapshot; the last snapshot has
     the particle count, ids, radii and positions (x = H s) of the final
     state saved with --save-sample, bit for bit; on every interval snapshot
     the contact count and the sliding count equal the results file's
     `contacts` and `sliding_contacts` of that step, and the normal forces
     give the run's mean stress: sum_c |F_n| |d_c| / (3 V) = p (Love-Weber,
     eq. 127; tangential forces are normal to the branch of a sphere pair)
     within 2e-5 (the branch vectors are one step newer than the forces);
     the section picture is a PNG.
  2. A saved sample opens the same way: `triax_snapshot` of the shipped
     dense_1000.h5 and dense_1000_spheroid.h5: count, radii, semi-axes and
     positions equal the sample file's; the spheroids' shape tensor has the
     eigenvalues 2a, 2b, 2b along the stored orientation; the contact
     network's mean stress is the preparation pressure (100 kPa) within
     1 % (the preparation stops within 0.5 % on every axis); the total
     normal force read back equals triax_snapshot's own sum to 1e-12.
No ROS master needed.
"""
import json
import os
import shutil
import struct
import subprocess
import tempfile
import unittest
import xml.etree.ElementTree as ET

import h5py
from catkin.find_in_workspaces import find_in_workspaces
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

PKG = "virtual_triaxial"
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
PROTOCOL = os.path.join(ROOT, "tests", "data", "protocols", "snapshot_mini.yaml")
SPHERES = os.path.join(ROOT, "config", "samples", "dense_1000.h5")
SPHEROIDS = os.path.join(ROOT, "config", "samples", "dense_1000_spheroid.h5")


def run(program, *args):
    # rosrun skips the package's build/ folder, where the devel space of this
    # repository-root package lives: ask catkin for the program's location.
    found = find_in_workspaces(search_dirs=["libexec"], project=PKG, path=program)
    if not found:
        raise AssertionError(f"{program}: not built")
    return subprocess.run([found[0], *args], capture_output=True, text=True, timeout=600)


def collection(path):
    root = ET.parse(path).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def read_poly(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    out = r.GetOutput()
    if out is None or r.GetErrorCode() != 0:
        raise AssertionError(f"{path}: VTK cannot read it")
    return out


def arrays(poly):
    d = {"points": vtk_to_numpy(poly.GetPoints().GetData()) if poly.GetPoints() else np.zeros((0, 3))}
    for kind, data in (("point", poly.GetPointData()), ("cell", poly.GetCellData()), ("field", poly.GetFieldData())):
        for k in range(data.GetNumberOfArrays()):
            a = data.GetArray(k)
            d[f"{kind}:{a.GetName()}"] = vtk_to_numpy(a)
    return d


def load(directory, k):
    p = read_poly(os.path.join(directory, f"particles_{k:06d}.vtp"))
    c = read_poly(os.path.join(directory, f"contacts_{k:06d}.vtp"))
    return p, arrays(p), c, arrays(c)


def mean_stress_from_normal_forces(pa, ca):
    h = pa["field:cell_matrix"].reshape(3, 3)
    volume = abs(np.linalg.det(h))
    fn = ca["cell:normal_force"]
    length = np.linalg.norm(ca["cell:branch"], axis=1)
    return float(np.sum(fn * length) / (3.0 * volume))


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n":
        raise AssertionError(f"{path}: not a PNG")
    return struct.unpack(">II", head[16:24])


class SpecimenVtk(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="vt_specimen_vtk_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def check_particles_equal_sample(self, poly, pa, sample):
        with h5py.File(sample, "r") as f:
            ids = f["particles/id"][()]
            radius = f["particles/radius"][()]
            position = f["particles/position"][()]
            semi = f["particles/semi_axes"][()]
            quat = f["particles/orientation"][()]
        n = len(ids)
        self.assertEqual(poly.GetNumberOfPoints(), n)
        self.assertEqual(poly.GetNumberOfVerts(), n)
        order = {int(i): k for k, i in enumerate(ids)}
        idx = np.array([order[int(i)] for i in pa["point:id"]])
        self.assertEqual(sorted(idx.tolist()), list(range(n)))
        np.testing.assert_array_equal(pa["point:radius"], radius[idx])
        np.testing.assert_array_equal(pa["point:semi_axes"], semi[idx])
        np.testing.assert_array_equal(pa["points"], position[idx])
        return semi[idx], quat[idx]

    def test_run_snapshots_match_the_runs_numbers(self):
        out = os.path.join(self.tmp, "run")
        os.makedirs(out)
        results = os.path.join(out, "results.h5")
        final = os.path.join(out, "final.h5")
        spec = os.path.join(out, "specimen")
        r = run("triax_run", PROTOCOL, "--out", results, "--save-sample", final, "--specimen", spec, "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        entries = collection(os.path.join(spec, "particles.pvd"))
        self.assertEqual([e[1] for e in entries], [f"particles_{k:06d}.vtp" for k in range(len(entries))])
        self.assertEqual([e[1] for e in collection(os.path.join(spec, "contacts.pvd"))],
                         [f"contacts_{k:06d}.vtp" for k in range(len(entries))])
        times = [e[0] for e in entries]
        self.assertEqual(times, sorted(set(times)))
        # consolidation start/end, shear start (= consolidation end, written once), 5 interval
        # snapshots of the shear (2000 .. 10000 steps), shear end (= the last interval one)
        with open(os.path.join(spec, "snapshots.csv")) as f:
            labels = [line.split(",")[3] for line in f.read().splitlines()[1:]]
        self.assertEqual(len(labels), len(entries))
        interval = [k for k, lab in enumerate(labels) if " step " in lab]
        self.assertGreaterEqual(len(interval), 4, labels)

        # last snapshot = the saved final state
        p, pa, c, ca = load(spec, len(entries) - 1)
        with h5py.File(final, "r") as f:
            self.assertEqual(int(pa["field:step"][0]), int(f["cell/step"][()]))
            np.testing.assert_array_equal(pa["field:cell_matrix"].reshape(3, 3), f["cell/h"][()])
        self.check_particles_equal_sample(p, pa, final)

        # interval snapshots against the results file's samples of the same step
        with h5py.File(results, "r") as f:
            groups = [g for g in f.values() if isinstance(g, h5py.Group) and "series" in g]
            self.assertEqual(len(groups), 1)
            s = groups[0]["series"]
            step = s["step"][()]
            contacts = s["contacts"][()]
            sliding = s["sliding_contacts"][()]
            stress = s["stress"][()].reshape(-1, 9)
        checked = 0
        for k in interval:
            p, pa, c, ca = load(spec, k)
            rows = np.nonzero(step == int(pa["field:step"][0]) - 1)[0]  # measured step = steps - 1
            self.assertEqual(len(rows), 1, f"snapshot {k}: no sample at its step")
            row = rows[0]
            self.assertEqual(c.GetNumberOfLines(), int(contacts[row]))
            self.assertEqual(int(np.sum(ca["cell:sliding"])), int(sliding[row]))
            self.assertEqual(c.GetNumberOfPoints(), 2 * int(contacts[row]))
            p_run = (stress[row, 0] + stress[row, 4] + stress[row, 8]) / 3.0
            p_snap = mean_stress_from_normal_forces(pa, ca)
            self.assertLess(abs(p_snap / p_run - 1.0), 2e-5, f"snapshot {k}: p {p_snap} vs run {p_run}")
            # normal forces of the lines = |normal_force_vector|; lines join x_i and x_i + branch
            np.testing.assert_allclose(np.linalg.norm(ca["cell:normal_force_vector"], axis=1),
                                       ca["cell:normal_force"], rtol=1e-15)
            pts = ca["points"].reshape(-1, 2, 3)
            np.testing.assert_allclose(pts[:, 1] - pts[:, 0], ca["cell:branch"], atol=1e-15)
            checked += 1
        self.assertGreaterEqual(checked, 4)
        w, h = png_size(os.path.join(spec, "specimen_section.png"))
        self.assertGreater(w, 600)
        self.assertGreater(h, 400)

    def check_sample(self, sample, name):
        out = os.path.join(self.tmp, name)
        r = run("triax_snapshot", sample, "--out", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        summary = json.loads(r.stdout.strip().splitlines()[-1])
        p, pa, c, ca = load(out, 0)
        semi, quat = self.check_particles_equal_sample(p, pa, sample)
        self.assertEqual(c.GetNumberOfLines(), summary["contacts"])
        self.assertGreater(summary["contacts"], 2 * p.GetNumberOfPoints())  # jammed: Z > 4
        fn = ca["cell:normal_force"]
        self.assertLess(abs(np.sum(fn) / summary["total_normal_force"] - 1.0), 1e-12)
        with h5py.File(sample, "r") as f:
            target = float(f["preparation/target_pressure"][()])
        p_snap = float(np.trace(pa["field:stress"].reshape(3, 3)) / 3.0)
        self.assertLess(abs(p_snap / target - 1.0), 0.01, f"{name}: p {p_snap}")
        return semi, quat, pa, ca

    def test_saved_sphere_sample_opens_the_same_way(self):
        semi, quat, pa, ca = self.check_sample(SPHERES, "dense_1000")
        # spheres: sum |F_n| |d| / 3V is the network's p
        p_snap = float(np.trace(pa["field:stress"].reshape(3, 3)) / 3.0)
        self.assertLess(abs(mean_stress_from_normal_forces(pa, ca) / p_snap - 1.0), 1e-9)

    def test_saved_spheroid_sample_opens_the_same_way(self):
        semi, quat, pa, ca = self.check_sample(SPHEROIDS, "dense_1000_spheroid")
        tensors = pa["point:shape_tensor"].reshape(-1, 3, 3)
        for k in range(0, len(tensors), 37):
            w, x, y, z = quat[k]
            e = np.array([1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)])  # R (1,0,0)
            a, b = semi[k, 0], semi[k, 1]
            np.testing.assert_allclose(tensors[k] @ e, 2 * a * e, atol=1e-12 * a)
            np.testing.assert_allclose(sorted(np.linalg.eigvalsh(tensors[k])), sorted([2 * a, 2 * b, 2 * b]),
                                       rtol=1e-12)
        self.assertTrue(np.all(pa["point:shape"] == 1))


if __name__ == "__main__":
    import rostest

    rostest.rosrun(PKG, "specimen_vtk", SpecimenVtk)
