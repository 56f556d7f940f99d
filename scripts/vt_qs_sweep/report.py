"""The report folder of a quasi-static sweep: runs.csv, q_eps_a.csv and the
figures (matplotlib, Agg):
  rate sweep:    i_mom_vs_rate.png    mean I_mom to the peak against eps'
                                      (log-log), the eq. 73 fit, the I_QS line
                                      and the fitted eps'_QS;
                 tan_phi_vs_i_mom.png tan phi_peak against I_mom, the eq. 74
                                      line and its intercept phi_QS;
  damping sweep: i_mom_vs_damping.png mean I_mom against xi (log-log) and the
                                      optimum;
                 tan_phi_vs_i_mom.png the runs (above the optimum: eq. 74);
  both:          q_eps_a.png          q against eps_a of every run overlaid.
The shear stage's rows of a results file are those after the steps of the
stages before it (the first recorded row is one control tick after the
start of the test)."""
import csv
import math
import os

import numpy as np

RUN_COLUMNS = ["run", "status", "exit_code", "damping_model", "damping_ratio", "eps_prime", "strain_rate_per_s",
               "phi_peak_deg", "eps_peak", "q_peak_pa", "mean_moment_index_to_peak", "max_moment_index_to_peak",
               "quasi_static", "e0", "shear_steps", "wall_s", "message"]


def write_runs_csv(path, runs):
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(RUN_COLUMNS)
        for r in runs:
            w.writerow(["" if r.get(c) is None else r.get(c) for c in RUN_COLUMNS])


def shear_curve(results, steps_before, control_interval, axis):
    """(eps_a, q [Pa]) of the shear stage in a triax_run results file;
    axis 0, 1, 2 = the stage's axial_axis x, y, z."""
    import h5py
    with h5py.File(results, "r") as f:
        g = f[list(f.keys())[0]]["series"]
        step = np.array(g["step"])
        start = step[0] - control_interval + steps_before
        m = step > start
        strain, q = np.array(g["strain"])[m], np.array(g["q"])[m]
    return strain[:, axis], q


def write_curves(path, curves):
    """q_eps_a.csv: run, eps_prime, damping_ratio, eps_a, q_pa (<= ~400 rows a run)."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["run", "eps_prime", "damping_ratio", "eps_a", "q_pa"])
        for r, eps, q in curves:
            keep = slice(None, None, max(1, len(eps) // 400))
            for e_, q_ in zip(eps[keep], q[keep]):
                w.writerow([r["run"], r["eps_prime"], r["damping_ratio"], "%.6g" % e_, "%.6g" % q_])


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, ax, path, title):
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def plot_curves(path, curves, label, title):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for r, eps, q in curves:
        ax.plot(100 * eps, q / 1e3, label=label(r))
    ax.set_xlabel("axial strain eps_a [%]")
    ax.set_ylabel("deviator stress q [kPa]")
    _save(fig, ax, path, title)
    plt.close(fig)


def plot_rate_fit(path, runs, fit, threshold, title):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    x = np.array([r["eps_prime"] for r in runs])
    y = np.array([r["mean_moment_index_to_peak"] for r in runs])
    ax.loglog(x, y, "o", label="runs")
    qs = fit.get("eps_prime_qs_eq73")
    if qs and math.isfinite(qs):
        xs = np.logspace(math.log10(min(x.min(), qs) / 2), math.log10(x.max() * 2), 60)
        ax.loglog(xs, fit["a_i_eq73"] * xs ** fit["b_i_eq73"], "-",
                  label="eq. 73: I_mom = %.3g eps'^%.3f" % (fit["a_i_eq73"], fit["b_i_eq73"]))
        ax.axvline(qs, color="g", ls="--", label="eps'_QS = %.3g" % qs)
    ax.axhline(threshold, color="k", ls=":", label="I_QS = %g" % threshold)
    ax.set_xlabel("dimensionless strain rate eps' [-]")
    ax.set_ylabel("mean I_mom to the peak [-]")
    _save(fig, ax, path, title)
    plt.close(fig)


def plot_friction_line(path, runs, phi_qs, slope, title, note):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    im = np.array([r["mean_moment_index_to_peak"] for r in runs])
    tp = np.tan(np.radians([r["phi_peak_deg"] for r in runs]))
    ax.plot(im, tp, "o", label="runs")
    if phi_qs is not None and math.isfinite(phi_qs):
        xs = np.linspace(0, im.max() * 1.1, 20)
        ax.plot(xs, math.tan(math.radians(phi_qs)) + slope * xs, "-",
                label="%s: phi_QS = %.2f deg" % (note, phi_qs))
    ax.set_xlim(left=0)
    ax.set_xlabel("mean I_mom to the peak [-]")
    ax.set_ylabel("tan phi_peak [-]")
    _save(fig, ax, path, title)
    plt.close(fig)


def plot_damping(path, runs, fit, title):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.loglog([r["damping_ratio"] for r in runs], [r["mean_moment_index_to_peak"] for r in runs], "o-",
              label="runs")
    xi = fit.get("optimum_damping_ratio")
    if xi and math.isfinite(xi):
        ax.loglog([xi], [fit["min_mean_moment_index"]], "*", ms=12,
                  label="optimum xi = %.3g %% (parabola in ln-ln)" % (100 * xi))
    ax.set_xlabel("damping ratio xi [-]")
    ax.set_ylabel("mean I_mom to the peak [-]")
    _save(fig, ax, path, title)
    plt.close(fig)
