#!/usr/bin/python3
"""Side by side with LAMMPS (issue 13): the same drained triaxial test on the
same packing, run by Debian's LAMMPS (`lmp`) and by triax_run, interleaved.

usage: bench/lammps_side_by_side.sh [--sample config/samples/dense_1000.h5]
       [--tile KxKyKz] [--strain 0.05] [--rate 1e-5] [--threads "1 2"] [--rounds 3]
       [--lammps-ct 1.6] [--ours "ct0.3 contacts"] [--out DIR]

--tile: both codes run KxKyKz periodic copies of the sample instead
(triax_import --tile: the same packing, stored in slab order as OUT/tiled.h5;
e.g. 3x2x2 of dense_1000.h5 gives 12 000 spheres).

What runs (units SI, compression positive):
  LAMMPS: the sample as a data file (triax_import --to-lammps; atom_style
    sphere, no contact history), pair_style granular with hertz/material
    (E, nu; no contact damping) and tangential mindlin (k_t from E and nu,
    no tangential damping, mu): the same Hertz-Mindlin law as ours (eq. 107,
    114-117); fix nve/sphere; fix viscous gamma = 4 xi / T0 x mean mass (our
    OD mass damping, eq. 101, on translation only); fix deform z trate
    (axial log strain rate eps'/T0, remap x) and fix press/berendsen on x
    and y holding 100 kPa (the lateral servo: Pdamp 100 dt, modulus 3 MPa,
    the stiffest setting found stable; it holds the lateral stress within
    ~10 %, printed as sigma_lat); dt = lammps-ct x T0. One MPI
    rank per thread (mpirun -np T).
  ours: triax_run on a protocol with one drained_shear stage (same rate,
    lateral PID servo at 100 kPa, OD damping xi of the sample) to the same
    axial strain, at c_t 0.3 ("ct0.3", dt = 0.3 T0) and with the time step
    from the contacts ("contacts", dem/contact_time_step.h: the default of
    a protocol that sets neither); OMP threads T.
Prints per case the medians over rounds of: dt/T0, steps, wall time to the
strain (LAMMPS: its "Loop time", without its setup; ours: the run's wall
time, with the stage's setup and first results flush), the whole process's
wall time (proc_s: start-up, reading the sample, the run, writing the
results; what a user waits for), cost per particle-step (from the first), q/p averaged over eps_a in [0.8, 1.0] x strain, eps_v at the
end; the load average beside each round; then, per code, the median over
rounds of each round's wall time on the fewest threads over that on each
other thread count (the speed-up; runs of one round are interleaved). Then
per case with more than one thread, by round: the round trip of a cache line
between CPUs 0 and 1 before and after the run (host_scaling --pingpong, ns;
about 95-145 or 465-535 on this VM, the host's two placements of the
vCPUs: session 35) and, for ours, the steps the thread governor ran on one
thread; and the median wall time over the rounds whose two round trips were
both below RT_SLOW ns (environment, default 250, as bench/round_trip.sh;
"near"). Data in OUT/side_by_side.json.
"""
import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("VT_BIN", os.path.join(ROOT, "build/devel/lib/virtual_triaxial"))


def load() -> str:
    with open("/proc/loadavg") as f:
        return f.read().split()[0]


def rt_slow_ns():
    """RT_SLOW [ns] (default 250): a round trip at or above it means the vCPUs
    placed far apart (session 35)."""
    v = os.environ.get("RT_SLOW", "250")
    try:
        x = float(v)
    except ValueError:
        x = -1.0
    if not (x > 0.0 and math.isfinite(x)):
        sys.exit(f"lammps_side_by_side: RT_SLOW must be a number of ns, not '{v}'")
    return x


def round_trip_ns():
    """The round trip of a cache line between CPUs 0 and 1 now [ns]; None
    without host_scaling or two CPUs."""
    exe = os.path.join(BIN, "host_scaling")
    if not os.access(exe, os.X_OK):
        return None
    p = subprocess.run([exe, "--pingpong", "--rounds", "1"], capture_output=True, text=True)
    m = re.search(r"^1\s+pingpong\s+([0-9.]+)", p.stdout, re.M)
    return float(m.group(1)) if p.returncode == 0 and m else None


def timed_run(cmd, **kw):
    """subprocess.run(cmd, capture_output, text) and its wall time [s]."""
    t = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    return p, time.perf_counter() - t


def between_readings(threads, run):
    """run() and the round trips (before, after) around it when it runs more
    than one thread, else (None, None)."""
    if threads == "1":
        return run(), (None, None)
    before = round_trip_ns()
    result = run()
    return result, (before, round_trip_ns())


def governor_steps_one(stderr):
    """Steps triax_run's thread governor ran on one thread (None: no governor line)."""
    m = re.search(r"threads chosen at run time: (\d+) steps on 1, (\d+) on (\d+)", stderr)
    return int(m.group(1)) if m else None


def sample_facts(path):
    with h5py.File(path, "r") as f:
        r = f["particles/radius"][()]
        rho = float(f["material/density"][()])
        young = float(f["material/young_modulus"][()])
        return {"n": len(r), "r_min": float(r.min()), "rho": rho, "young": young,
                "nu": float(f["material/poisson_ratio"][()]), "mu": float(f["material/friction"][()]),
                "xi": float(f["settings/damping_ratio"][()]), "mass_mean": float(f["particles/mass"][()].mean()),
                "t0": 2 * float(r.min()) * math.sqrt(rho / young)}


def lammps_deck(s, data, dt, rate, strain, thermo_every):
    steps = int(math.ceil(strain / (rate * dt)))
    gamma = 4 * s["xi"] / s["t0"] * s["mass_mean"]
    return steps, f"""# drained triaxial test, written by bench/lammps_side_by_side.py
units si
atom_style sphere
atom_modify map array
boundary p p p
newton off
comm_modify vel yes
read_data {data}
pair_style granular
pair_coeff * * hertz/material {s['young']!r} 0.0 {s['nu']!r} tangential mindlin NULL 0.0 {s['mu']!r}
neighbor {0.15 * 2 * s['r_min']!r} bin
neigh_modify delay 0 every 1 check yes
timestep {dt!r}
fix integ all nve/sphere
fix damp all viscous {gamma!r}
fix axial all deform 1 z trate {-rate!r} remap x
fix servo all press/berendsen x 100000.0 100000.0 {100 * dt!r} y 100000.0 100000.0 {100 * dt!r} couple none modulus 3.0e6 dilate all
thermo_style custom step time pxx pyy pzz vol lz
thermo_modify norm no format float %.10g
thermo {thermo_every}
run {steps}
"""


def parse_lammps(log, n):
    rows, loop = [], None
    head = None
    for line in log.splitlines():
        w = line.split()
        if w[:2] == ["Step", "Time"]:
            head = w
            continue
        if head and len(w) == len(head):
            try:
                rows.append([float(x) for x in w])
                continue
            except ValueError:
                head = None
        m = re.match(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps", line)
        if m:
            loop = (float(m.group(1)), int(m.group(3)))
            head = None
    a = np.array(rows)
    pxx, pyy, pzz, vol, lz = a[:, 2], a[:, 3], a[:, 4], a[:, 5], a[:, 6]
    eps_a, eps_v = np.log(lz[0] / lz), np.log(vol[0] / vol)
    p, q = (pxx + pyy + pzz) / 3, pzz - (pxx + pyy) / 2
    s1, s3 = pzz, np.minimum(pxx, pyy)
    phi = np.degrees(np.arcsin(np.clip((s1 - s3) / (s1 + s3), -1, 1)))
    return {"wall": loop[0], "steps": loop[1], "us": loop[0] * 1e6 / (n * loop[1]),
            "eps_a": eps_a, "eps_v": eps_v, "qp": q / p, "phi_peak": float(phi.max()), "lat": (pxx + pyy) / 2}


def ours_protocol(sample, s, config, rate, strain):
    basis = "time_step_basis: contacts" if config == "contacts" else "time_step_ratio: " + config[2:]
    return f"""particles: {{sample_file: {os.path.abspath(sample)}}}
material: {{friction: {s['mu']!r}}}
damping: {{model: OD, ratio: {s['xi']!r}}}
{basis}
control:
  interval: 10
  servo: {{strategy: pid, gain: 1.0, ki: 0.6, max_dimensionless_rate: 1.0e-4}}
stages:
  - name: shear
    type: drained_shear
    confining_pressure: 100.0e3
    strain_rate_dimensionless: {rate!r}
    axial_axis: z
    stop: {{axial_strain: {strain!r}}}
output: {{interval: 100, progress_seconds: 3600}}
"""


def parse_ours(summary_line, results, n):
    s = json.loads(summary_line)
    with h5py.File(results, "r") as f:
        g = f[list(f.keys())[0]]["series"]
        eps_a = g["strain"][()][:, 2]
        return {"wall": s["wall_seconds"], "steps": s["steps"], "us": s["wall_seconds"] * 1e6 / (n * s["steps"]),
                "eps_a": eps_a, "eps_v": g["volumetric_strain"][()], "qp": g["q"][()] / g["p"][()],
                "dt_t0": s["dt_s"] / s["t0_s"], "phi_peak": s["phi_peak_deg"],
                "lat": (g["stress"][()][:, 0] + g["stress"][()][:, 4]) / 2}


def window(r, strain):
    sel = (r["eps_a"] >= 0.8 * strain) & (r["eps_a"] <= strain * 1.001)
    return float(np.mean(r["qp"][sel])), float(r["eps_v"][-1]), float(np.mean(r["lat"][sel]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sample", default=os.path.join(ROOT, "config/samples/dense_1000.h5"))
    ap.add_argument("--tile", default=None, help="KxKyKz: periodic copies of the sample (triax_import --tile)")
    ap.add_argument("--strain", type=float, default=0.05)
    ap.add_argument("--rate", type=float, default=1e-5, help="dimensionless axial rate eps' = eps_dot T0")
    ap.add_argument("--threads", default="1 2")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--lammps-ct", type=float, default=1.6)
    ap.add_argument("--ours", default="ct0.3 contacts")
    ap.add_argument("--lmp", default="lmp")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    rt_slow = rt_slow_ns()
    if not shutil.which(a.lmp):
        sys.exit(f"lammps_side_by_side: '{a.lmp}' not found: install Debian's LAMMPS (apt-get install lammps "
                 "openmpi-bin) or give --lmp")
    # absolute: LAMMPS runs in it and reads the data file by this path
    out = os.path.abspath(a.out or tempfile.mkdtemp(prefix="vt_lammps_"))
    os.makedirs(out, exist_ok=True)
    source = a.sample
    if a.tile:
        tiled = os.path.join(out, "tiled.h5")
        p = subprocess.run([os.path.join(BIN, "triax_import"), "--tile", a.sample, "--factors", a.tile, "--out", tiled],
                           capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"lammps_side_by_side: --tile {a.tile}: {p.stderr.strip()}")
        print("# tiled: " + ", ".join(p.stdout.split("\n")[:-1]), flush=True)
        a.sample = tiled
    s = sample_facts(a.sample)
    data = os.path.join(out, "sample.data")
    subprocess.run([os.path.join(BIN, "triax_import"), "--to-lammps", a.sample, "--out", data], check=True,
                   stdout=subprocess.DEVNULL)
    dt_l = a.lammps_ct * s["t0"]
    rate_si = a.rate / s["t0"]
    steps_l, deck = lammps_deck(s, data, dt_l, rate_si, a.strain, max(1, int(0.0005 / (rate_si * dt_l))))
    with open(os.path.join(out, "in.triax"), "w") as f:
        f.write(deck)
    for c in a.ours.split():
        with open(os.path.join(out, f"ours_{c}.yaml"), "w") as f:
            f.write(ours_protocol(a.sample, s, c, a.rate, a.strain))
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {s['n']} particles ({a.sample}), "
          f"strain {a.strain}, eps' {a.rate}, T0 {s['t0']:.4g} s; LAMMPS dt = {a.lammps_ct} T0, {steps_l} steps",
          flush=True)
    cases = {}
    for rnd in range(a.rounds):
        for t in a.threads.split():
            env = dict(os.environ, OMP_NUM_THREADS="1")
            cmd = ([a.lmp] if t == "1" else ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", t, a.lmp])
            ld = load()
            (p, t_proc), rt = between_readings(t, lambda: timed_run(
                cmd + ["-in", "in.triax", "-log", "none", "-screen", "lammps.out"], cwd=out, env=env))
            with open(os.path.join(out, "lammps.out")) as f:
                log = f.read()
            if p.returncode != 0 or "Loop time" not in log:
                sys.exit(f"lammps_side_by_side: lmp failed (see {out}/lammps.out): {p.stderr[-500:]}")
            r = parse_lammps(log, s["n"])
            r["dt_t0"], r["load"], r["proc"] = a.lammps_ct, ld, t_proc
            r["rt"], r["steps_one"] = rt, None
            cases.setdefault(("LAMMPS", t), []).append(r)
            for c in a.ours.split():
                env = dict(os.environ, OMP_NUM_THREADS=t)
                res = os.path.join(out, f"ours_{c}.h5")
                ld = load()
                (p, t_proc), rt = between_readings(t, lambda: timed_run(
                    [os.path.join(BIN, "triax_run"), os.path.join(out, f"ours_{c}.yaml"), "--out", res, "--quiet"],
                    env=env))
                if p.returncode != 0:
                    sys.exit(f"lammps_side_by_side: triax_run failed: {p.stderr[-500:]}")
                r = parse_ours(p.stdout.strip().splitlines()[-1], res, s["n"])
                r["load"], r["proc"] = ld, t_proc
                r["rt"], r["steps_one"] = rt, governor_steps_one(p.stderr)
                cases.setdefault((f"ours {c}", t), []).append(r)
        print(f"# round {rnd + 1}/{a.rounds} done, load {load()}", flush=True)
    print(f"{'code':<16} {'T':>2} {'dt/T0':>7} {'steps':>7} {'wall_s':>8} {'proc_s':>7} {'us/p-step':>10} "
          f"{'q/p@0.8-1.0':>11} {'eps_v_end':>10} {'phi_pk':>6} {'sig_lat':>7} {'loads'}")
    table = []
    for (code, t), rs in cases.items():
        med = lambda k: statistics.median(r[k] for r in rs)
        qp, ev, lat = window(rs[0], a.strain)
        row = {"code": code, "threads": int(t), "dt_t0": med("dt_t0"), "steps": med("steps"), "wall_s": med("wall"), "process_s": med("proc"),
               "us_per_particle_step": med("us"), "qp_window": qp, "eps_v_end": ev, "sigma_lat_window_pa": lat, "phi_peak_deg": rs[0]["phi_peak"],
               "loads": [r["load"] for r in rs], "walls": [r["wall"] for r in rs],
               "round_trips_ns": [list(r["rt"]) for r in rs], "governor_steps_one": [r["steps_one"] for r in rs]}
        table.append(row)
        print(f"{code:<16} {t:>2} {row['dt_t0']:7.3f} {row['steps']:7.0f} {row['wall_s']:8.2f} {row['process_s']:7.2f} "
              f"{row['us_per_particle_step']:10.4f} {qp:11.4f} {ev:10.5f} {rs[0]['phi_peak']:6.2f} {lat / 1e3:7.1f} {' '.join(row['loads'])}")
    for (code, t), rs in cases.items():
        if t == "1" or any(x is None for r in rs for x in r["rt"]):
            continue
        near = [r["wall"] for r in rs if max(r["rt"]) < rt_slow]
        rts = " ".join(f"{r['rt'][0]:.0f}/{r['rt'][1]:.0f}" for r in rs)
        gov = "" if rs[0]["steps_one"] is None else "; steps on one thread " + " ".join(str(r["steps_one"]) for r in rs)
        near_s = f"{statistics.median(near):.2f} s over {len(near)} rounds" if near else "no such round"
        print(f"{code:<16} {t:>2} round trips before/after [ns] {rts}{gov}; wall near: {near_s}")
    speedups = []
    fewest = min(a.threads.split(), key=int)
    for (code, t), rs in cases.items():
        if t == fewest:
            continue
        ratios = [b["wall"] / r["wall"] for b, r in zip(cases[(code, fewest)], rs)]
        speedups.append({"code": code, "threads": int(t), "over_threads": int(fewest),
                         "median": statistics.median(ratios), "rounds": ratios})
        print(f"speed-up {code:<16} {t} over {fewest} threads: median {statistics.median(ratios):.3f} "
              f"(rounds {' '.join(f'{x:.3f}' for x in ratios)})")
    with open(os.path.join(out, "side_by_side.json"), "w") as f:
        json.dump({"sample": a.sample, "source_sample": source, "tile": a.tile, "strain": a.strain, "rate": a.rate, "lammps_ct": a.lammps_ct,
                   "date": time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime()), "cases": table,
                   "speedups": speedups}, f, indent=1)
    print(f"# data: {out}/side_by_side.json")


if __name__ == "__main__":
    main()
