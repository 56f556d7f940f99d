#!/usr/bin/python3
"""Speed against accuracy (issue 16): what each setting costs and what it gets wrong.

    reports/speed_accuracy/run_report.py [--jobs 2] [--samples dense_1000,dense_1000_spheroid]
                                         [--groups fixed_ct03,...] [--report-only]

For each sample, groups of drained tests at 100 kPa (one sweep each, run by
the sweep runner `scripts/vt_sweep` with `--jobs` processes of one OpenMP
thread, resumable: a finished run is not repeated):
  fixed_ct03      fixed eps' 1e-5 ... 1e-7 at c_t = 0.3 (the old way)
  fixed_contacts  the same rates with the time step from the contacts
  predicted       rate.strategy predicted (eq. 85) at target 0.5 and 1
  adaptive        rate.strategy adaptive at targets 0.35 ... 1
  time_step       c_t 0.1 ... 2.4 at eps' 1e-6 (to the stability limit)
  damping_*       every damping model at several strengths, eps' 1e-6, c_t 0.3
  servo           proportional against PID at eps' 1e-6
  threads2        eps' 1e-6 on two OpenMP threads
Each run stops at `FINAL_STRAIN` axial strain (past the peak). Cost is the
run's CPU time (user + system, from the sweep runner's status.json): on a
shared machine it is what the wall time would be on a quiet one (1 thread;
the 2-thread run's CPU time is the sum over its threads, its wall time is
given too). Accuracy is |phi_peak - phi_ref|, phi_ref the phi_peak of the
slowest run at the reference settings (fixed eps' 1e-7, c_t 0.3, OD 0.3 %),
whose mean I_mom to the peak is below I_QS / 1.3; the servo's lateral-stress
error (RMS over the shear, and at the peak) from results.h5.

Writes per sample <sample>/runs/<group>/ (the sweeps: sweep.csv, status and
summary of every run; results.h5 stay local), <sample>/points.csv,
<sample>/pareto.csv, the figures <sample>/cost_vs_error.png and
<sample>/cost_vs_i_mom.png, and summary.json.
"""
import argparse
import copy
import csv
import json
import math
import os
import sys

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from vt_sweep import finished_runs, run_sweep, spec_from_dict  # noqa: E402  (after the path)

SAMPLES = {  # base protocol, final axial strain (past the peak: 2-2.5 % spheres, 0.1-0.2 % spheroids)
    "dense_1000": ("config/protocols/drained_100kPa.yaml", 0.04),
    "dense_1000_spheroid": ("config/protocols/drained_100kPa_spheroid.yaml", 0.01),
}
I_QS = 1e-3
RATE = "stages[1].strain_rate_dimensionless"


def groups(sample):
    """(name, base overrides, parameters, threads) of every group of `sample`."""
    spheroid = sample.endswith("spheroid")
    fixed_rates = [1e-5, 3e-6, 1e-6, 3e-7, 1e-7]
    g = [
        ("fixed_ct03", {}, {RATE: fixed_rates}, 1),
        ("fixed_contacts", {"time_step_basis": "contacts"}, {RATE: [1e-5, 1e-6, 3e-7, 1e-7]}, 1),
        ("predicted", {"time_step_basis": "contacts", "rate": {"strategy": "predicted"}},
         {"stages[1].rate.target": [0.5, 1.0]}, 1),
        ("adaptive", {"time_step_basis": "contacts", "rate": {"strategy": "adaptive"}},
         {"stages[1].rate.target": [0.35, 0.5, 0.7, 1.0]}, 1),
        ("time_step", {RATE: 1e-6}, {"time_step_ratio": [0.1, 0.3, 0.6, 1.0, 1.6, 2.4]}, 1),
        ("damping_OD", {RATE: 1e-6}, {"damping.ratio": [0.0, 0.001, 0.003, 0.01, 0.03]}, 1),
        ("damping_ND", {RATE: 1e-6, "damping": {"model": "ND", "ratio": 0.005}},
         {"damping.ratio": [0.002, 0.005, 0.02]}, 1),
        # e = 0.5 and 0.1: the servo loses control and the cell blows open during the
        # consolidation (reports/stability_map/: viscous stresses depend on the
        # commanded rate); measured here once: e 1.2e6 after 186 000 steps. Not run.
        ("damping_viscous", {RATE: 1e-6, "damping": {"model": "viscous", "restitution": 0.9}},
         {"damping.restitution": [0.9]}, 1),
        ("damping_local", {RATE: 1e-6, "damping": {"model": "local", "coefficient": 0.2}},
         {"damping.coefficient": [0.05, 0.2, 0.7]}, 1),
        ("servo", {RATE: 1e-6}, {"control.servo.strategy": ["proportional", "pid"]}, 1),
        ("threads2", {RATE: 1e-6}, {"damping.ratio": [0.003]}, 2),
    ]
    if spheroid:  # 2.5x the cost per step: the rate and damping groups only
        g = [x for x in g if x[0] in ("fixed_ct03", "fixed_contacts", "predicted", "adaptive", "damping_OD")]
    return g


def log(msg):
    print("[speed_accuracy] " + msg, file=sys.stderr, flush=True)


def write_base(sample, name, overrides, folder):
    """The group's base protocol: the sample's protocol, stop at FINAL_STRAIN, the overrides."""
    protocol, final = SAMPLES[sample]
    with open(os.path.join(ROOT, protocol)) as f:
        doc = yaml.safe_load(f)
    doc["particles"]["sample_file"] = os.path.join(ROOT, os.path.dirname(protocol), doc["particles"]["sample_file"])
    doc["control"]["quasi_static_threshold"] = I_QS
    shear = doc["stages"][1]
    assert shear["type"] == "drained_shear"
    shear["stop"] = {"axial_strain": final}
    for key, value in overrides.items():
        if key == RATE:
            shear["strain_rate_dimensionless"] = value
        elif key == "rate":
            shear.pop("strain_rate_dimensionless", None)
            shear["rate"] = copy.deepcopy(value)
        elif key == "damping":
            doc["damping"] = copy.deepcopy(value)
        elif key == "time_step_basis":
            doc.pop("time_step_ratio", None)
            doc["time_step_basis"] = value
        else:
            doc[key] = value
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, f"base_{name}.yaml")
    with open(path, "w") as f:
        f.write(f"# generated by reports/speed_accuracy/run_report.py: group {name} of {sample}\n")
        yaml.safe_dump(doc, f, sort_keys=False)
    return path


def lateral_errors(results, pressure=100e3):
    """(RMS over the shear, error at the peak of phi) of the lateral stresses / pressure."""
    try:
        import h5py
    except ImportError:
        return None, None
    if not os.path.exists(results):
        return None, None
    with h5py.File(results, "r") as f:
        s = f["test/series"]
        stress, phi, strain = s["stress"][:], s["phi"][:], s["strain"][:]
    # the shear stage: samples after the strain reset (axial strain restarts at ~0)
    start = 0
    for i in range(1, len(strain)):
        if strain[i, 2] < strain[i - 1, 2] - 1e-9:
            start = i
    lat = (stress[start:, [0, 4]] - pressure) / pressure
    if len(lat) == 0:
        return None, None
    rms = math.sqrt(float((lat ** 2).mean()))
    k = start + int(phi[start:].argmax())
    peak = float(abs((stress[k, [0, 4]] - pressure) / pressure).max())
    return rms, peak


def run_groups(sample, jobs, only):
    rows = []
    for name, overrides, params, threads in groups(sample):
        if only and name not in only:
            continue
        folder = os.path.join(HERE, sample)
        base = write_base(sample, name, overrides, os.path.join(folder, "bases"))
        spec = spec_from_dict({"name": f"{sample}_{name}", "output": os.path.join(folder, "runs", name),
                               "base": base, "parameters": params, "threads": threads}, folder=folder)
        log(f"{sample} / {name}: {sum(len(v) for v in params.values())} runs, {jobs} at a time")
        code = run_sweep(spec, backend="local", jobs=jobs)
        if code not in (0, 1):
            raise SystemExit(f"speed_accuracy: sweep {name} of {sample} ended with code {code}")
    return rows


def collect(sample):
    """One point per finished run of every group of `sample`."""
    points = []
    for name, _, params, threads in groups(sample):
        out = os.path.join(HERE, sample, "runs", name)
        key = list(params)[0]
        for d, st, summ in finished_runs(out):
            value = st["values"].get(key, list(st["values"].values())[0] if st["values"] else "")
            rms, at_peak = lateral_errors(os.path.join(d, "results.h5"))
            points.append({
                "group": name, "setting": f"{key.split('.')[-1]}={value}", "threads": threads,
                "status": st["status"], "verdict": summ.get("verdict", "failed"),
                "message": st.get("message", ""),
                "cpu_s": st.get("cpu_seconds") or st["wall_seconds"], "wall_s": st["wall_seconds"],
                "steps": summ.get("steps", ""), "phi_peak_deg": summ.get("phi_peak_deg", ""),
                "eps_peak": summ.get("eps_peak", ""),
                "mean_i_mom": summ.get("mean_moment_index_to_peak", ""),
                "quasi_static": summ.get("quasi_static", ""),
                "eps_prime_min": summ.get("strain_rate_dimensionless_min", ""),
                "eps_prime_max": summ.get("strain_rate_dimensionless_max", ""),
                "energy_error": summ.get("energy_relative_balance_error", ""),
                "lateral_rms": "" if rms is None else rms, "lateral_at_peak": "" if at_peak is None else at_peak,
            })
    return points


def reference(points):
    """phi_ref: the reference settings' slowest run (fixed_ct03 at 1e-7)."""
    ref = [p for p in points if p["group"] == "fixed_ct03" and p["setting"].endswith("=1e-07")
           and p["verdict"] == "completed"]
    if not ref:
        return None
    return ref[0]


def plateau_noise(sample, ref):
    """Standard deviation of phi [deg] of the reference run over its plateau
    (from the peak's strain to the end): the scale on which phi_peak, the
    maximum of a noisy plateau, scatters between trajectories."""
    try:
        import h5py
        import numpy as np
    except ImportError:
        return None
    out = os.path.join(HERE, sample, "runs", "fixed_ct03", "runs")
    for rid in os.listdir(out):
        d = os.path.join(out, rid)
        if not os.path.exists(os.path.join(d, "summary.json")):
            continue
        with open(os.path.join(d, "summary.json")) as f:
            if json.load(f).get("phi_peak_deg") != ref["phi_peak_deg"]:
                continue
        if not os.path.exists(os.path.join(d, "results.h5")):
            return None
        with h5py.File(os.path.join(d, "results.h5"), "r") as f:
            phi, strain = f["test/series/phi"][:], f["test/series/strain"][:]
        start = max(i for i in range(len(strain)) if i == 0 or strain[i, 2] < strain[i - 1, 2] - 1e-12)
        eps, phi = strain[start:, 2], phi[start:] * 180.0 / math.pi
        window = phi[eps >= ref["eps_peak"] - 0.005]
        return float(np.std(window)) if len(window) > 2 else None
    return None


def pareto(points):
    """The runs no other run beats in both cost and error (completed runs only)."""
    ok = sorted((p for p in points if p["verdict"] == "completed" and p["error_deg"] != ""),
                key=lambda p: (p["cpu_s"], p["error_deg"]))
    front, best = [], math.inf
    for p in ok:
        if p["error_deg"] < best:
            front.append(p)
            best = p["error_deg"]
    return front


def write_csv(path, rows, cols):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)


COLORS = {"fixed_ct03": "black", "fixed_contacts": "tab:blue", "predicted": "tab:cyan", "adaptive": "tab:red",
          "time_step": "tab:green", "damping_OD": "tab:orange", "damping_ND": "tab:brown",
          "damping_viscous": "tab:purple", "damping_local": "tab:pink", "servo": "tab:olive",
          "threads2": "tab:gray"}


def plot(sample, points, front, ref, noise):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ok = [p for p in points if p["verdict"] == "completed" and p["error_deg"] != ""]
    for ykey, fname, ylabel in (("error_deg", "cost_vs_error.png", "|phi_peak - phi_ref| [deg]"),
                                ("mean_i_mom", "cost_vs_i_mom.png", "mean I_mom to the peak [-]")):
        fig, ax = plt.subplots(figsize=(9, 6))
        for g in COLORS:
            pts = [p for p in ok if p["group"] == g]
            if pts:
                floor = 1e-3 if ykey == "error_deg" else 0.0  # an error of 0 (the reference) stays visible
                ax.scatter([p["cpu_s"] for p in pts], [max(p[ykey], floor) for p in pts], label=g, color=COLORS[g],
                           s=28, zorder=3)
                for p in pts:
                    ax.annotate(p["setting"].split("=")[1], (p["cpu_s"], max(p[ykey], floor)), fontsize=6,
                                xytext=(3, 2), textcoords="offset points")
        if ykey == "error_deg":
            ax.plot([p["cpu_s"] for p in front], [max(p["error_deg"], 1e-3) for p in front], "k--", lw=1,
                    label="Pareto front", zorder=2)
            ax.axhline(1.0, color="gray", lw=0.8, ls=":")
            if noise:
                ax.axhspan(0.0, noise, color="gray", alpha=0.12, zorder=1,
                           label=f"reference's plateau noise (std {noise:.2f} deg)")
            ax.text(ax.get_xlim()[0] if False else min(p["cpu_s"] for p in ok), 1.05, "1 deg", fontsize=7,
                    color="gray")
        else:
            ax.axhline(I_QS, color="gray", lw=0.8, ls=":")
            ax.set_yscale("log")
        bad = [p for p in points if p["verdict"] != "completed"]
        for p in bad:
            ax.annotate(f"{p['group']} {p['setting']}: {p['verdict']}", (0.01, 0.98 - 0.03 * bad.index(p)),
                        xycoords="axes fraction", fontsize=7, color="red", va="top")
        ax.set_xscale("log")
        ax.set_xlabel("cost: CPU seconds of the run (= wall seconds on a quiet machine, 1 thread)")
        ax.set_ylabel(ylabel)
        ax.set_title(f"{sample}: speed against accuracy (phi_ref {ref['phi_peak_deg']:.2f} deg, "
                     f"eps' 1e-7, c_t 0.3, OD 0.3 %)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
        fig.tight_layout()
        fig.savefig(os.path.join(HERE, sample, fname), dpi=110)
        plt.close(fig)


COLS = ["group", "setting", "threads", "verdict", "cpu_s", "wall_s", "steps", "phi_peak_deg", "error_deg",
        "eps_peak", "mean_i_mom", "quasi_static", "eps_prime_min", "eps_prime_max", "energy_error",
        "lateral_rms", "lateral_at_peak", "message"]


def report(sample):
    points = collect(sample)
    ref = reference(points)
    if ref is None:
        log(f"{sample}: no reference run yet (fixed_ct03 at 1e-7)")
        return None
    for p in points:
        p["error_deg"] = abs(p["phi_peak_deg"] - ref["phi_peak_deg"]) if p["phi_peak_deg"] != "" else ""
    front = pareto(points)
    noise = plateau_noise(sample, ref)
    plot(sample, points, front, ref, noise)
    write_csv(os.path.join(HERE, sample, "points.csv"), points, COLS)
    write_csv(os.path.join(HERE, sample, "pareto.csv"), front, COLS)
    log(f"{sample}: {len(points)} runs, phi_ref {ref['phi_peak_deg']:.3f} deg, Pareto front: " +
        ", ".join(f"{p['group']} {p['setting']} ({p['cpu_s']:.0f} s, {p['error_deg']:.2f} deg)" for p in front))
    log(f"{sample}: plateau noise of the reference's phi (std from 0.5 % before its peak to the end): "
        f"{noise if noise is None else round(noise, 3)} deg")
    return {"sample": sample, "phi_ref_deg": ref["phi_peak_deg"], "reference_mean_i_mom": ref["mean_i_mom"],
            "reference_plateau_std_deg": noise,
            "runs": len(points), "pareto": [{k: p[k] for k in COLS} for p in front]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--jobs", type=int, default=2, help="runs at a time (one OpenMP thread each)")
    ap.add_argument("--samples", default=",".join(SAMPLES))
    ap.add_argument("--groups", default="", help="only these groups (comma separated)")
    ap.add_argument("--report-only", action="store_true", help="no runs: tables and figures of what exists")
    a = ap.parse_args()
    samples = [s for s in a.samples.split(",") if s]
    for s in samples:
        if s not in SAMPLES:
            raise SystemExit(f"speed_accuracy: --samples: unknown sample '{s}'; known: {', '.join(SAMPLES)}")
    if a.jobs < 1:
        raise SystemExit("speed_accuracy: --jobs: must be >= 1")
    only = [g for g in a.groups.split(",") if g]
    out = []
    for s in samples:
        if not a.report_only:
            run_groups(s, a.jobs, only)
        r = report(s)
        if r:
            out.append(r)
    with open(os.path.join(HERE, "summary.json"), "w") as f:
        json.dump(out, f, indent=1)
    print(json.dumps({"samples": [r["sample"] for r in out], "summary": os.path.join(HERE, "summary.json")}))


if __name__ == "__main__":
    main()
