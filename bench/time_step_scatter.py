#!/usr/bin/python3
"""Does the time step from the contacts change the answer by more than the
sample's scatter? (issue 13: the contact step as the default)

usage: bench/time_step_scatter.sh [--seeds "1 2 3 4 5 6 7 8"] [--strain 0.05]
       [--rate 1e-5] [--out DIR]

Prepares one dense 1000-sphere sample per seed exactly as the shipped
dense_1000.h5 (triax_prepare, config/samples/README.md; seed 1 is that file,
the others are written to OUT once and reused), then runs on each the drained
test of bench/lammps_side_by_side.py (one drained_shear stage to the strain
at eps', lateral PID servo at 100 kPa, one thread) twice: at c_t = 0.3
("ct0.3", dt = 0.3 T0, eq. 132) and with the time step from the contacts
("contacts", dem/contact_time_step.h). Per sample: q/p averaged over
eps_a in [0.8, 1.0] x strain, eps_v at the end, phi_peak, steps, wall time.
Summary: the sample-to-sample scatter (standard deviation over the seeds)
of each measure at c_t 0.3, and the mean and standard deviation of the
paired difference contacts - ct0.3 with its paired t (mean / standard
error: |t| above about 2.4 at 8 samples marks a systematic shift); the
contact step is "within the sample's scatter" when |mean difference| is
below the scatter at c_t 0.3.
Data in OUT/time_step_scatter.json. Units SI, compression positive.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lammps_side_by_side import BIN, ROOT, load, ours_protocol, parse_ours, sample_facts, window  # noqa: E402

SHIPPED = os.path.join(ROOT, "config/samples/dense_1000.h5")
PSD = os.path.join(ROOT, "config/samples/psd_uniform4_0.8-1.2mm.yaml")
MEASURES = ("qp_window", "eps_v_end", "phi_peak_deg")


def sample_for(seed, out):
    """The dense 1000-sphere sample of a seed (seed 1: the shipped file)."""
    if seed == 1:
        return SHIPPED
    path = os.path.join(out, f"dense_1000_s{seed}.h5")
    if not os.path.exists(path):
        print(f"# preparing seed {seed} (about a minute)", flush=True)
        part = path + ".part"  # renamed when complete: an interrupted preparation is not reused
        subprocess.run([os.path.join(BIN, "triax_prepare"), "--psd", PSD, "--pressure", "100000", "--mu1", "0.0",
                        "--seed", str(seed), "--particles", "1000", "--out", part],
                       env=dict(os.environ, OMP_NUM_THREADS="1"), check=True, stdout=subprocess.DEVNULL)
        os.replace(part, path)
    return path


def run(sample, config, a, out):
    s = sample_facts(sample)
    proto = os.path.join(out, f"ours_{config}.yaml")
    with open(proto, "w") as f:
        f.write(ours_protocol(sample, s, config, a.rate, a.strain))
    res = os.path.join(out, f"ours_{config}.h5")
    if os.path.exists(res):
        os.remove(res)
    ld = load()  # before the run, as bench/lammps_side_by_side.py
    p = subprocess.run([os.path.join(BIN, "triax_run"), proto, "--out", res, "--quiet"],
                       env=dict(os.environ, OMP_NUM_THREADS="1"), capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"time_step_scatter: triax_run failed on {sample} ({config}): {p.stderr[-500:]}")
    r = parse_ours(p.stdout.strip().splitlines()[-1], res, s["n"])
    qp, ev, _ = window(r, a.strain)
    return {"qp_window": qp, "eps_v_end": ev, "phi_peak_deg": r["phi_peak"], "dt_t0": r["dt_t0"],
            "steps": r["steps"], "wall_s": r["wall"], "load": ld}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", default="1 2 3 4 5 6 7 8")
    ap.add_argument("--strain", type=float, default=0.05)
    ap.add_argument("--rate", type=float, default=1e-5, help="dimensionless axial rate eps' = eps_dot T0")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    seeds = [int(x) for x in a.seeds.split()]
    if len(seeds) < 3:
        sys.exit("time_step_scatter: --seeds: give at least 3 seeds (a scatter needs them)")
    out = a.out or tempfile.mkdtemp(prefix="vt_dt_scatter_")
    os.makedirs(out, exist_ok=True)
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, dense 1000-sphere samples, seeds {seeds}, "
          f"strain {a.strain}, eps' {a.rate}, one thread", flush=True)
    print(f"{'seed':>4} {'case':<9} {'dt/T0':>6} {'steps':>6} {'wall_s':>7} {'q/p@0.8-1.0':>11} {'eps_v_end':>10} "
          f"{'phi_pk':>6} {'load':>5}", flush=True)
    rows = []
    for seed in seeds:
        sample = sample_for(seed, out)
        for config in ("ct0.3", "contacts"):
            r = run(sample, config, a, out)
            r.update(seed=seed, case=config, sample=sample)
            rows.append(r)
            print(f"{seed:>4} {config:<9} {r['dt_t0']:6.3f} {r['steps']:6.0f} {r['wall_s']:7.3f} "
                  f"{r['qp_window']:11.4f} {r['eps_v_end']:10.5f} {r['phi_peak_deg']:6.2f} {r['load']:>5}", flush=True)
    summary = {}
    print(f"{'measure':<13} {'mean ct0.3':>11} {'scatter(sd)':>11} {'mean contacts':>13} "
          f"{'mean diff':>10} {'sd diff':>9} {'paired t':>8} {'|diff|<scatter':>14}")
    for m in MEASURES:
        base = [r[m] for r in rows if r["case"] == "ct0.3"]
        fast = [r[m] for r in rows if r["case"] == "contacts"]
        diff = [f - b for f, b in zip(fast, base)]
        s = {"mean_ct0.3": statistics.mean(base), "scatter_ct0.3": statistics.stdev(base),
             "mean_contacts": statistics.mean(fast), "mean_diff": statistics.mean(diff),
             "sd_diff": statistics.stdev(diff)}
        # paired t = mean / (sd / sqrt(n)): whether the shift is systematic, however small
        s["paired_t"] = s["mean_diff"] / (s["sd_diff"] / len(diff) ** 0.5) if s["sd_diff"] > 0 else float("inf")
        s["within_scatter"] = abs(s["mean_diff"]) < s["scatter_ct0.3"]
        summary[m] = s
        print(f"{m:<13} {s['mean_ct0.3']:11.4f} {s['scatter_ct0.3']:11.4f} {s['mean_contacts']:13.4f} "
              f"{s['mean_diff']:10.4f} {s['sd_diff']:9.4f} {s['paired_t']:8.2f} {'yes' if s['within_scatter'] else 'NO':>14}")
    speed = [b["wall_s"] / f["wall_s"] for b, f in zip(rows[0::2], rows[1::2])]
    print(f"# wall time ct0.3 / contacts per sample: median {statistics.median(speed):.2f}x "
          f"(single runs, {min(speed):.2f}-{max(speed):.2f}x)")
    with open(os.path.join(out, "time_step_scatter.json"), "w") as f:
        json.dump({"seeds": seeds, "strain": a.strain, "rate": a.rate,
                   "date": time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime()), "runs": rows, "summary": summary},
                  f, indent=1)
    print(f"# data: {out}/time_step_scatter.json")


if __name__ == "__main__":
    main()
