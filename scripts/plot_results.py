#!/usr/bin/python3
"""Plot a virtual_triaxial results file (HDF5) as PNG figures.

usage: plot_results.py RESULTS.h5 [--group test] [--out DIR] [--axis z]

Writes into DIR (default: the results file's folder):
  stress_strain.png   q - eps_a and eps_v - eps_a
  stress_path.png     q - p path and e - log p
  equilibrium.png     moment index, UFR and kinetic energy against time
  energy_budget.png   boundary work against the sum of its parts
Compression is positive everywhere; stresses in kPa, strains in %.
"""
import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(path, group):
    with h5py.File(path, "r") as f:
        if group not in f:
            sys.exit(f"plot_results: {path}: group '{group}' not found (have: {list(f.keys())})")
        s = f[group]["series"]
        return {k: s[k][()] for k in s.keys()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("--group", default="test")
    ap.add_argument("--out", default=None)
    ap.add_argument("--axis", default="z", choices=["x", "y", "z"])
    a = ap.parse_args()
    if not os.path.exists(a.results):
        sys.exit(f"plot_results: {a.results}: no such file")
    d = load(a.results, a.group)
    if len(d.get("time", [])) == 0:
        sys.exit(f"plot_results: {a.results}: the series is empty")
    out = a.out or os.path.dirname(os.path.abspath(a.results))
    os.makedirs(out, exist_ok=True)
    ax_i = "xyz".index(a.axis)
    eps_a = 100 * d["strain"][:, ax_i]
    eps_v = 100 * d["volumetric_strain"]
    p, q = d["p"] / 1e3, d["q"] / 1e3
    t = d["time"]

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    a1.plot(eps_a, q)
    a1.set(xlabel=f"axial strain eps_{a.axis} [%] (from the stage start)", ylabel="q [kPa]", title="deviator stress")
    a2.plot(eps_a, eps_v)
    a2.set(xlabel=f"axial strain eps_{a.axis} [%]", ylabel="volumetric strain [%]", title="volume change")
    for x in (a1, a2):
        x.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "stress_strain.png"), dpi=110)

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    a1.plot(p, q)
    a1.set(xlabel="p [kPa]", ylabel="q [kPa]", title="stress path")
    ok = d["p"] > 0
    a2.semilogx(d["p"][ok] / 1e3, d["void_ratio"][ok])
    a2.set(xlabel="p [kPa] (log)", ylabel="void ratio e", title="compression curve")
    for x in (a1, a2):
        x.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "stress_path.png"), dpi=110)

    fig, a1 = plt.subplots(figsize=(8, 4.2))
    a1.semilogy(t, np.maximum(d["moment_index"], 1e-12), label="moment index I_mom (eq. 67)")
    a1.semilogy(t, np.maximum(d["ufr"], 1e-12), label="UFR (eq. 66)")
    a1.axhline(1e-3, color="k", ls="--", lw=0.8, label="I_QS = 0.1 %")
    a1.set(xlabel="time [s]", ylabel="index [-]", title="equilibrium")
    a2 = a1.twinx()
    ke = d["energy_kinetic_translational"] + d["energy_kinetic_rotational"]
    a2.semilogy(t, np.maximum(ke, 1e-30), color="tab:red", lw=0.8, label="kinetic energy")
    a2.set_ylabel("kinetic energy [J]", color="tab:red")
    a1.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "equilibrium.png"), dpi=110)

    fig, a1 = plt.subplots(figsize=(8, 4.2))
    w = d["energy_boundary_work"]
    parts = (ke - d["energy_kinetic_reference"] + d["energy_elastic"] - d["energy_elastic_reference"]
             + d["energy_damping"] + d["energy_friction"])
    a1.plot(t, w, label="boundary work W")
    a1.plot(t, parts, "--", label="dKE + dU + damping + friction")
    a1.plot(t, d["energy_damping"], lw=0.8, label="damping")
    a1.plot(t, d["energy_friction"], lw=0.8, label="friction")
    a1.set(xlabel="time [s]", ylabel="energy [J]", title="energy budget")
    a1.legend(fontsize=8)
    a1.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "energy_budget.png"), dpi=110)
    print(f"plot_results: wrote 4 figures to {out}")


if __name__ == "__main__":
    main()
