#!/usr/bin/python3
"""Sample-preparation grid of chapter 4 (Yousefi 2017), run with triax_prepare.

usage: prep_grid_report.py [--out-dir reports/prep_grid] [--particles 1000]
                           [--psd config/psd/mono_0.48mm.yaml] [--seed 1]
                           [--shape sphere|psd] [--quick] [--program PATH] [--table49 CSV]
                           [--replot] [--retry-failed] [--resume]
                           [--sweep-dir DIR] [--backend local|slurm] [--jobs J] [--wait]
                           [--partition P] [--time T] [--mem M] [--max-parallel K] [--collect]

Prepares one sample for every shrinkage friction mu1 in {0, 0.03, 0.1, 0.2,
0.3, 0.5} and every confining pressure in {39, 390, 3900, 39000} kPa (the
grid of section 4.4 / table 49, 24 preparations; --quick runs the 2x2 subset
mu1 {0, 0.5} x {390, 39000} kPa). Chapter 4 material (4.3.5): rho 2650
kg/m^3, G 30 GPa, nu 0.3 -> E = 2 G (1 + nu) = 78 GPa, final mu 0.5.
With --shape sphere (default; the report in reports/prep_grid) a spheroid PSD
is used through its nominal (equal-volume) radius; with --shape psd the
program prepares the PSD's spheroids (aspect 1.2 for mono_0.48mm, the
dissertation's shape), about 4-6x slower per step.

The preparations run as a triax_sweep sweep (scripts/vt_sweep) in --sweep-dir
(default build/sweeps/<name of --out-dir>; one folder per run with its
sample, log and summary), each with OMP_NUM_THREADS=1: on --jobs local
workers (default 1, so the wall times stay comparable), or with --backend
slurm as one Slurm job array (--wait follows it; otherwise run the script
again with --collect once the job has ended). A restart skips the
preparations already finished; --retry-failed runs the failed ones again.
Writes into --out-dir:
  grid.csv                    mu1, pressure, e0, Z, idle mass fraction, steps, wall s
  void_ratio_vs_mu1.png       fig. 11 analogue, one curve per pressure; table 49
                              (spheroids, aspect 1.2) dashed if --table49 exists
  coordination_vs_mu1.png     fig. 15 analogue (mechanical coordination number)
  idle_fraction_vs_mu1.png    fig. 17 analogue (idle particles, % by mass)
Prints progress per sample, a markdown table of the results (with table 49's
void ratio next to each sample) and the total wall time.
"""
import argparse
import csv
import json
import os
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.path.join(REPO, "build", "devel", "lib", "virtual_triaxial", "triax_prepare")
TABLE49 = os.path.join(REPO, "scripts", "data", "table49_void_ratio.csv")

MU1 = [0.0, 0.03, 0.1, 0.2, 0.3, 0.5]
PRESSURES_KPA = [39, 390, 3900, 39000]
QUICK_MU1 = [0.0, 0.5]
QUICK_PRESSURES_KPA = [390, 39000]

# Chapter 4.3.5 material.
DENSITY = 2650.0
SHEAR_MODULUS = 30e9
POISSON = 0.3
YOUNG = 2.0 * SHEAR_MODULUS * (1.0 + POISSON)  # 78 GPa
FINAL_FRICTION = 0.5

FIELDS = ["mu1", "pressure_kpa", "converged", "e0", "coordination_number", "idle_mass_fraction", "ufr",
          "stress_xx_kpa", "stress_yy_kpa", "stress_zz_kpa", "max_overlap_ratio", "particles", "steps",
          "wall_seconds", "exit_code", "failure"]


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out-dir", default=os.path.join(REPO, "reports", "prep_grid"),
                    help="output folder (default: reports/prep_grid in the repository)")
    ap.add_argument("--particles", type=int, default=1000)
    ap.add_argument("--psd", default=os.path.join(REPO, "config", "psd", "mono_0.48mm.yaml"),
                    help="PSD file (default: config/psd/mono_0.48mm.yaml)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--shape", choices=["sphere", "psd"], default="sphere",
                    help="sphere: equal-volume spheres (the report in reports/prep_grid); "
                         "psd: the PSD's own spheroids (aspect 1.2 for mono_0.48mm)")
    ap.add_argument("--compare", default="",
                    help="another grid.csv (e.g. reports/prep_grid/grid.csv, spheres) drawn dotted beside this grid")
    ap.add_argument("--replot", action="store_true",
                    help="only redraw the figures and the table from the grid.csv in --out-dir (no preparation)")
    ap.add_argument("--quick", action="store_true",
                    help="2x2 subset (mu1 0, 0.5 x 390, 39000 kPa) for testing")
    ap.add_argument("--program", default=PROGRAM, help="triax_prepare executable")
    ap.add_argument("--retry-failed", action="store_true",
                    help="re-run only the rows of an existing grid.csv that did not converge, then re-plot")
    ap.add_argument("--resume", action="store_true",
                    help="(always on) finished preparations in --sweep-dir are kept, only the rest run")
    ap.add_argument("--sweep-dir", default="",
                    help="the sweep's folder (default: build/sweeps/<name of --out-dir>)")
    ap.add_argument("--backend", choices=["local", "slurm"], default="local")
    ap.add_argument("--jobs", type=int, default=1, help="local workers (default 1)")
    ap.add_argument("--wait", action="store_true", help="slurm: wait for the job, then write the report")
    ap.add_argument("--partition", help="slurm partition")
    ap.add_argument("--time", help="slurm time limit per preparation")
    ap.add_argument("--mem", help="slurm memory per preparation")
    ap.add_argument("--max-parallel", type=int, help="slurm: at most K preparations at once")
    ap.add_argument("--collect", action="store_true",
                    help="only gather the finished preparations of --sweep-dir into the report (after a slurm job)")
    ap.add_argument("--table49", default=TABLE49,
                    help="transcribed table 49 (default: scripts/data/table49_void_ratio.csv)")
    return ap.parse_args()


def load_table49(path):
    """{pressure_kpa: {mu1: e}} from the transcribed table 49, or {} if absent."""
    if not os.path.isfile(path):
        return {}
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    table = {}
    for col in rows[0].keys():
        if col == "mu1":
            continue
        p = int(col.replace("e_", "").replace("kPa", ""))
        table[p] = {round(float(r["mu1"]), 4): float(r[col]) for r in rows}
    return table


def sweep_spec(args, mu1s, pressures):
    """The grid as a triax_sweep spec: triax_prepare with the chapter 4.3.5
    material, pressure (highest first: the fastest preparations) x mu1."""
    from vt_sweep import spec_from_dict
    name = os.path.basename(os.path.normpath(args.out_dir))
    doc = {
        "name": name, "output": args.sweep_dir or os.path.join(REPO, "build", "sweeps", name),
        "prepare": {"psd": args.psd, "particles": args.particles, "seed": args.seed, "shape": args.shape,
                    "young_modulus": YOUNG, "poisson_ratio": POISSON, "density": DENSITY,
                    "friction": FINAL_FRICTION},
        "parameters": {"pressure": [p * 1e3 for p in sorted(pressures, reverse=True)], "mu1": list(mu1s)},
        "combine": "grid", "threads": 1,
    }
    return spec_from_dict(doc, REPO)


def grid_rows(out):
    """grid.csv rows from the sweep folder (runs not finished are left out)."""
    from vt_sweep.plan import read_plan
    from vt_sweep.run_one import is_published, read_status
    plan = read_plan(out)
    rows = []
    for run in plan["runs"]:
        if not is_published(out, run["id"]):
            continue
        st = read_status(out, run["id"])
        row = {k: float("nan") for k in FIELDS}
        row.update(mu1=float(run["values"]["mu1"]), pressure_kpa=float(run["values"]["pressure"]) / 1e3,
                   converged=False, particles=args_particles(plan), wall_seconds=st["wall_seconds"],
                   exit_code=st["exit_code"], failure=st["message"])
        path = os.path.join(out, "runs", run["id"], "summary.json")
        summary = {}
        if os.path.isfile(path):
            with open(path) as f:
                summary = json.load(f)
        if st["status"] == "completed" and summary.get("converged"):
            s = summary["stress_pa"]
            row.update(converged=True, e0=summary["e0"], coordination_number=summary["coordination_number"],
                       idle_mass_fraction=summary["idle_mass_fraction"], ufr=summary["ufr"],
                       stress_xx_kpa=s[0] / 1e3, stress_yy_kpa=s[1] / 1e3, stress_zz_kpa=s[2] / 1e3,
                       max_overlap_ratio=summary["max_overlap_ratio"], particles=summary["particles"],
                       steps=summary["steps"], wall_seconds=summary["wall_seconds"])
        rows.append(row)
    return rows


def args_particles(plan):
    argv = plan["runs"][0]["argv"]
    return float(argv[argv.index("--particles") + 1]) if "--particles" in argv else float("nan")


def read_csv(path):
    """Rows of an existing grid.csv with numbers parsed."""
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            row = {}
            for k in FIELDS:
                v = r.get(k, "")
                if k == "converged":
                    row[k] = v == "True"
                elif k == "failure":
                    row[k] = v
                else:
                    row[k] = float(v) if v not in ("", "nan") else float("nan")
            rows.append(row)
    return rows


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k]) for k in FIELDS})


def series(rows, p_kpa, key):
    pts = sorted((r["mu1"], r[key]) for r in rows if r["pressure_kpa"] == p_kpa and r["converged"])
    return np.array([a for a, _ in pts]), np.array([b for _, b in pts])


def plot(rows, pressures, mu1s, key, ylabel, title, path, scale=1.0, table49=None, shape="spheres",
         compare=None, compare_shape="spheres"):
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, p in enumerate(pressures):
        x, y = series(rows, p, key)
        c = colors[i % len(colors)]
        ax.plot(x, y * scale, "o-", color=c, label=f"{p:g} kPa ({shape})")
        if compare:
            cx, cy = series(compare, p, key)
            if len(cx):
                ax.plot(cx, cy * scale, "^:", color=c, alpha=0.7, label=f"{p:g} kPa ({compare_shape})")
        if table49 and p in table49:
            tx = [m for m in mu1s if round(m, 4) in table49[p]]
            ty = [table49[p][round(m, 4)] for m in tx]
            ax.plot(tx, ty, "s--", color=c, mfc="none", label=f"{p:g} kPa (table 49, spheroids 1.2)")
    ax.set_xlabel(r"friction coefficient in the shrinkage phase, $\mu_1$")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, ncol=2 if (table49 or compare) else 1)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main():
    args = parse_args()
    args.psd = os.path.abspath(args.psd)
    if not args.replot and not os.access(args.program, os.X_OK):
        sys.exit(f"prep_grid_report: {args.program}: not found or not executable (build the project first)")
    if not os.path.isfile(args.psd):
        sys.exit(f"prep_grid_report: {args.psd}: no such PSD file")
    mu1s = QUICK_MU1 if args.quick else MU1
    pressures = QUICK_PRESSURES_KPA if args.quick else PRESSURES_KPA
    os.makedirs(args.out_dir, exist_ok=True)
    csv_path = os.path.join(args.out_dir, "grid.csv")
    table49 = load_table49(args.table49)

    n = len(mu1s) * len(pressures)
    t_start = time.monotonic()
    if args.replot:
        rows = read_csv(csv_path)
        n = len(rows)
    else:
        sys.path.insert(0, os.path.join(REPO, "scripts"))
        from vt_sweep import SweepError, run_sweep
        try:
            spec = sweep_spec(args, mu1s, pressures)
            print(f"prep_grid_report: {n} preparations, {args.particles} particles, psd {args.psd}, seed {args.seed}, "
                  f"E {YOUNG / 1e9:g} GPa, nu {POISSON:g}, rho {DENSITY:g}, OMP_NUM_THREADS=1; sweep {spec.output}",
                  flush=True)
            if not args.collect:
                code = run_sweep(spec, args.backend, jobs=args.jobs, retry_failed=args.retry_failed,
                                 program_path=args.program, wait=args.wait, partition=args.partition,
                                 time=args.time, mem=args.mem, max_parallel=args.max_parallel)
                if args.backend == "slurm" and not args.wait:
                    print(f"prep_grid_report: submitted; when the job has ended: {' '.join(sys.argv)} --collect")
                    return code
        except SweepError as e:
            sys.exit(f"prep_grid_report: error: {e}")
        rows = grid_rows(spec.output)
        write_csv(csv_path, rows)
    total = time.monotonic() - t_start

    shape = "spheres" if args.shape == "sphere" else "spheroids 1.2" if "mono_0.48" in args.psd else "PSD shapes"
    compare = read_csv(args.compare) if args.compare else None
    compare_shape = "spheres" if args.shape != "sphere" else "other grid"
    extra = dict(shape=shape, compare=compare, compare_shape=compare_shape)
    plot(rows, pressures, mu1s, "e0", "void ratio, $e_0$",
         f"Void ratio vs $\\mu_1$ (fig. 11 analogue), {args.particles} {shape}",
         os.path.join(args.out_dir, "void_ratio_vs_mu1.png"), table49=table49, **extra)
    plot(rows, pressures, mu1s, "coordination_number", "mechanical coordination number, Z",
         f"Coordination number vs $\\mu_1$ (fig. 15 analogue), {args.particles} {shape}",
         os.path.join(args.out_dir, "coordination_vs_mu1.png"), **extra)
    plot(rows, pressures, mu1s, "idle_mass_fraction", "idle particles (% by mass)",
         f"Idle particles vs $\\mu_1$ (fig. 17 analogue), {args.particles} {shape}",
         os.path.join(args.out_dir, "idle_fraction_vs_mu1.png"), scale=100.0, **extra)

    print("\n| mu1 | p (kPa) | e0 | e table 49 | e0 - e49 | Z | idle (% mass) | steps | wall (s) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in sorted(rows, key=lambda r: (r["pressure_kpa"], r["mu1"])):
        e49 = table49.get(r["pressure_kpa"], {}).get(round(r["mu1"], 4), float("nan"))
        if not r["converged"]:
            print(f"| {r['mu1']:g} | {r['pressure_kpa']:g} | not prepared: {r['failure']} | {e49:.3f} | | | | | "
                  f"{r['wall_seconds']:.1f} |")
            continue
        print(f"| {r['mu1']:g} | {r['pressure_kpa']:g} | {r['e0']:.4f} | {e49:.3f} | {r['e0'] - e49:+.3f} | "
              f"{r['coordination_number']:.3f} | {100 * r['idle_mass_fraction']:.1f} | {r['steps']:.0f} | "
              f"{r['wall_seconds']:.1f} |")
    failed = [r for r in rows if not r["converged"]]
    print(f"\nprep_grid_report: {n - len(failed)}/{n} prepared, total wall time {total:.0f} s "
          f"({total / 60:.1f} min); wrote {csv_path} and 3 figures in {args.out_dir}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
