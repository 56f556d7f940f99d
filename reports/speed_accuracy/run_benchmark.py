#!/usr/bin/python3
"""Benchmark of issue 16: time to a quasi-static phi_peak, adaptive rate against a fixed rate at eps'_QS.

For each sample folder given (default: dense_1000_benchmark and dense_4000_benchmark)
the two protocols `adaptive.yaml` (rate: adaptive, target 0.7, time_step_basis:
contacts) and `fixed_at_eps_qs.yaml` (rate: predicted, target 1.0, i.e. a fixed
rate at eq. 84's eps'_QS for the sample, with the default c_t = 0.3) are run with
`triax_run --threads T` in interleaved rounds (A B A B ...). Each run's wall and
CPU seconds come from the kernel's accounting of the finished process
(os.wait4). Written beside the protocols:
  timing.csv      one row per run (round, run, wall_s, cpu_user_s, cpu_sys_s)
  benchmark.json  medians, the per-round ratios fixed/adaptive and their median,
                  phi_peak, mean I_mom and steps of both runs (the runs are
                  deterministic, so every round gives the same answer: checked)
The packing state (void ratio, contacts per particle, mean stress) of each
sample is in config/samples/README.md; the report README quotes it.

and benchmark.png (here) draws both samples: median wall time of each run
with the rounds' range, the median ratio and phi_peak of each run.

Usage: reports/speed_accuracy/run_benchmark.py [--rounds 3] [--threads 1] [--plot-only] [FOLDER ...]
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
RUNS = ("adaptive", "fixed_at_eps_qs")
ANSWER = ("phi_peak_deg", "eps_peak", "steps", "mean_moment_index_to_peak", "quasi_static",
          "strain_rate_dimensionless_min", "strain_rate_dimensionless_max", "verdict")


def triax_run():
    path = os.path.join(ROOT, "build", "devel", "lib", "virtual_triaxial", "triax_run")
    if not os.access(path, os.X_OK):
        sys.exit(f"run_benchmark: {path} not found; build first (tests/run_tests.sh or "
                 "launch_equiv_scripts/run_triaxial.sh)")
    return path


def run_once(binary, folder, name, threads, scratch):
    out = os.path.join(scratch, name)
    os.makedirs(out, exist_ok=True)
    cmd = [binary, os.path.join(folder, f"{name}.yaml"), "--out", os.path.join(out, "results.h5"),
           "--threads", str(threads)]
    start = time.monotonic()
    with open(os.path.join(out, "log.txt"), "w") as log, \
            open(os.path.join(out, "summary.json"), "w") as summary_out:
        proc = subprocess.Popen(cmd, stdout=summary_out, stderr=log, cwd=folder)
        _, status, usage = os.wait4(proc.pid, 0)
    wall = time.monotonic() - start
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        sys.exit(f"run_benchmark: {name} in {folder} exited {code}; see {out}/log.txt")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    return wall, usage.ru_utime, usage.ru_stime, {k: summary.get(k) for k in ANSWER}


def bench(folder, rounds, threads):
    binary = triax_run()
    scratch = os.path.join(folder, "runs")
    rows, answers = [], {}
    for r in range(1, rounds + 1):
        for name in (RUNS if r % 2 else RUNS[::-1]):
            print(f"[benchmark] {os.path.basename(folder)} round {r}/{rounds}: {name} ...", flush=True)
            wall, user, sys_s, answer = run_once(binary, folder, name, threads, scratch)
            print(f"[benchmark]   {wall:.1f} s wall, {user + sys_s:.1f} s CPU, phi_peak "
                  f"{answer['phi_peak_deg']:.3f} deg", flush=True)
            if name in answers and answers[name] != answer:
                sys.exit(f"run_benchmark: {name} gave a different answer in round {r}: not deterministic")
            answers[name] = answer
            rows.append({"round": r, "run": name, "wall_s": round(wall, 3),
                         "cpu_user_s": round(user, 3), "cpu_sys_s": round(sys_s, 3)})
    with open(os.path.join(folder, "timing.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)

    def per_run(name, key):
        return [row[key] for row in rows if row["run"] == name]

    ratios = [b / a for a, b in zip(per_run("adaptive", "wall_s"), per_run("fixed_at_eps_qs", "wall_s"))]
    result = {
        "rounds": rounds, "threads": threads, "order": "interleaved, A B / B A alternating",
        "load_average_at_end": os.getloadavg(),
        "median_wall_s": {n: statistics.median(per_run(n, "wall_s")) for n in RUNS},
        "median_cpu_s": {n: statistics.median([u + s for u, s in zip(per_run(n, "cpu_user_s"),
                                                                      per_run(n, "cpu_sys_s"))]) for n in RUNS},
        "wall_ratio_fixed_over_adaptive_per_round": [round(x, 3) for x in ratios],
        "median_wall_ratio_fixed_over_adaptive": statistics.median(ratios),
        "answers": answers,
        "phi_peak_difference_deg": answers["adaptive"]["phi_peak_deg"] - answers["fixed_at_eps_qs"]["phi_peak_deg"],
    }
    with open(os.path.join(folder, "benchmark.json"), "w") as f:
        json.dump(result, f, indent=1)
    print(f"[benchmark] {os.path.basename(folder)}: median wall adaptive "
          f"{result['median_wall_s']['adaptive']:.1f} s, fixed at eps'_QS "
          f"{result['median_wall_s']['fixed_at_eps_qs']:.1f} s, ratio {result['median_wall_ratio_fixed_over_adaptive']:.2f}x "
          f"(rounds {result['wall_ratio_fixed_over_adaptive_per_round']}), phi_peak "
          f"{answers['adaptive']['phi_peak_deg']:.2f} / {answers['fixed_at_eps_qs']['phi_peak_deg']:.2f} deg", flush=True)


def plot(paths):
    """benchmark.png: per sample, the two runs' median wall time (bars) and range (error bars)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(paths), figsize=(4.2 * len(paths), 3.8), squeeze=False)
    for ax, path in zip(axes[0], paths):
        with open(os.path.join(path, "benchmark.json")) as f:
            b = json.load(f)
        with open(os.path.join(path, "timing.csv")) as f:
            rows = list(csv.DictReader(f))
        for k, name in enumerate(RUNS):
            walls = [float(r["wall_s"]) for r in rows if r["run"] == name]
            med = statistics.median(walls)
            ax.bar(k, med, color=("tab:green", "tab:gray")[k],
                   yerr=[[med - min(walls)], [max(walls) - med]], capsize=4)
            a = b["answers"][name]
            ax.text(k, 1.02 * max(walls), f"{med:.0f} s\nphi {a['phi_peak_deg']:.2f} deg\n{a['steps']} steps",
                    ha="center", va="bottom", fontsize=7)
        ax.set_xticks([0, 1])
        ax.set_xticklabels(["adaptive 0.7\ncontact step", "fixed eps'_QS (eq. 84)\nc_t 0.3"], fontsize=8)
        ax.set_ylabel("wall time, 1 thread [s]")
        ax.set_ylim(0, 1.35 * max(b["median_wall_s"].values()))
        ax.set_title(f"{os.path.basename(path).replace('_benchmark', '')}: "
                     f"{b['median_wall_ratio_fixed_over_adaptive']:.2f}x (median of {b['rounds']} rounds)",
                     fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "benchmark.png"), dpi=120)
    print(f"[benchmark] {os.path.join(HERE, 'benchmark.png')}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--plot-only", action="store_true", help="redraw benchmark.png from the folders' data")
    ap.add_argument("folders", nargs="*", default=["dense_1000_benchmark", "dense_4000_benchmark"])
    args = ap.parse_args()
    if args.rounds < 1:
        sys.exit("run_benchmark: --rounds must be at least 1")
    paths = [f if os.path.isabs(f) else os.path.join(HERE, f) for f in args.folders]
    for path in paths:
        for name in RUNS:
            if not os.path.exists(os.path.join(path, f"{name}.yaml")):
                sys.exit(f"run_benchmark: {path}/{name}.yaml not found")
    if not args.plot_only:
        for path in paths:
            bench(path, args.rounds, args.threads)
    plot(paths)


if __name__ == "__main__":
    main()
