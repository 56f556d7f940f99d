"""triax_qs rate-sweep / damping-sweep: plan, run (vt_sweep), fit (triax_qs), report.

    triax_qs rate-sweep PROTOCOL.yaml --rates 1e-5,5e-6,2e-6 [--jobs J] [--out DIR]
                        [--backend local|slurm] [--threshold I_QS]
    triax_qs damping-sweep PROTOCOL.yaml --ratios 0.001,0.003,0.01,0.03 --model OD|ND
                        --rate EPS' [--jobs J] [--out DIR] [--backend local|slurm] [--threshold I_QS]

Rates are dimensionless (eps' = eps_dot T0), damping ratios fractions (0.003
= 0.3 %). I_QS defaults to the protocol's control.quasi_static_threshold.
Runs already finished in DIR (same input) are reused. Progress with ETA on
stderr; the result is the last stdout line, one JSON object, keys named with
their units. Exit codes as triax_run's: 0 done, 2 bad input (one line naming
the field, e.g. `--rates[1]: ...`), else the exit code of the first failed
run (3 unstable, 4 step limit, ...), 5 interrupted, 6 the report folder
could not be written.
"""
import argparse
import json
import math
import os
import sys
import time

from vt_sweep import results, run_sweep, spec_from_dict
from vt_sweep.errors import SweepError
from vt_sweep.fsutil import write_atomic
from vt_sweep.plan import program_dir

from . import base, fit, report

EXIT_BAD_INPUT, EXIT_ABORTED, EXIT_OUTPUT = 2, 5, 6


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        # argparse's "the following arguments are required: --rate, --model"
        if "arguments are required:" in message:
            raise SweepError(message.split(":", 1)[1].split(",")[0].strip(), "required")
        raise SweepError("", message)


def _parser(cmd):
    ap = _Parser(prog=f"triax_qs {cmd}", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("protocol", metavar="PROTOCOL.yaml")
    if cmd == "rate-sweep":
        ap.add_argument("--rates", required=True, help="comma-separated eps' (dimensionless), at least 2")
    else:
        ap.add_argument("--ratios", required=True, help="comma-separated damping ratios xi, at least 3")
        ap.add_argument("--model", required=True, help="OD or ND")
        ap.add_argument("--rate", required=True, help="eps' of every run (dimensionless)")
    ap.add_argument("--jobs", "-j", default="2", help="local: runs at a time (default 2)")
    ap.add_argument("--out", help="report folder (default: ./<protocol>_%s)" % cmd.replace("-", "_"))
    ap.add_argument("--backend", default="local", help="local or slurm (sbatch, waits for the job)")
    ap.add_argument("--threshold", help="I_QS (default: the protocol's control.quasi_static_threshold)")
    return ap


def _positive(text, field):
    try:
        v = float(text)
    except ValueError:
        raise SweepError(field, f"expected a number, got '{text}'") from None
    if not (math.isfinite(v) and v > 0):
        raise SweepError(field, f"must be a number > 0, got '{text}'")
    return v


def _list(text, field, minimum):
    values = [_positive(t.strip(), f"{field}[{i}]") for i, t in enumerate(text.split(","))]
    if len(values) < minimum:
        raise SweepError(field, f"at least {minimum} values needed, got {len(values)}")
    if len(set(values)) != len(values):
        raise SweepError(field, "a value is listed twice")
    return values


def _options(cmd, argv):
    a = _parser(cmd).parse_args(argv)
    o = {"cmd": cmd, "protocol": os.path.abspath(a.protocol)}
    if cmd == "rate-sweep":
        o["values"] = _list(a.rates, "--rates", 2)
        o["field"] = "--rates"
    else:
        o["values"] = _list(a.ratios, "--ratios", 3)
        o["field"] = "--ratios"
        if a.model.upper() not in ("OD", "ND"):
            raise SweepError("--model", f"must be OD or ND, got '{a.model}'")
        o["model"] = a.model.upper()
        o["rate"] = _positive(a.rate, "--rate")
    try:
        o["jobs"] = int(a.jobs)
    except ValueError:
        raise SweepError("--jobs", f"expected a whole number, got '{a.jobs}'") from None
    if o["jobs"] < 1:
        raise SweepError("--jobs", f"must be >= 1, got {o['jobs']}")
    if a.backend not in ("local", "slurm"):
        raise SweepError("--backend", f"must be local or slurm, got '{a.backend}'")
    o["backend"] = a.backend
    o["threshold"] = _positive(a.threshold, "--threshold") if a.threshold is not None else None
    stem = os.path.splitext(os.path.basename(a.protocol))[0]
    o["out"] = os.path.abspath(a.out or f"{stem}_{cmd.replace('-', '_')}")
    return o


def _note(text):
    print(f"triax_qs: {text}", file=sys.stderr, flush=True)


def _runs(out, key, kind, model, fixed):
    """The runs of the sweep folder as report rows (plan order)."""
    _, rows = results(os.path.join(out, "sweep"))
    runs = []
    for row in rows:
        v = row[f"{key} [-]"]
        r = {"run": row["run"], "status": row["status"], "exit_code": row["exit_code"], "message": row["message"],
             "damping_model": model, "summary": os.path.join(out, "sweep", "runs", row["run"], "summary.json"),
             "results": os.path.join(out, "sweep", "runs", row["run"], "results.h5")}
        r["eps_prime"], r["damping_ratio"] = (v, fixed) if kind == "rate" else (fixed, v)
        t0 = row.get("t0_s")
        r["strain_rate_per_s"] = _g6(r["eps_prime"] / t0) if t0 else None
        for k in ("phi_peak_deg", "eps_peak", "q_peak_pa", "mean_moment_index_to_peak", "max_moment_index_to_peak",
                  "quasi_static", "e0"):
            r[k] = row.get(k)
        r["shear_steps"] = None
        r["stage_steps"] = [row.get(f"stages[{i}].steps") for i in range(64) if f"stages[{i}].steps" in row]
        runs.append(r)
    return runs


def _g6(v):
    return float("%.6g" % v)


def _exit_code(code, runs):
    failed = [r for r in runs if r["status"] == "failed"]
    if failed:
        c = failed[0]["exit_code"]
        return c if isinstance(c, int) and c not in (0, 1) else 4
    if code != 0 or any(r["status"] != "completed" for r in runs):
        return EXIT_ABORTED
    return 0


def sweep(o):
    t_start = time.monotonic()
    cmd, out = o["cmd"], o["out"]
    rate_sweep = cmd == "rate-sweep"
    doc0 = base.read_protocol(o["protocol"])
    damping0 = doc0.get("damping") if isinstance(doc0.get("damping"), dict) else {}
    model = o.get("model") or str(damping0.get("model", "OD")).upper()
    fixed = o["rate"] if not rate_sweep else float(damping0.get("ratio", 0.0))
    doc, stage = (base.derive(o["protocol"], o["values"][0]) if rate_sweep else
                  base.derive(o["protocol"], o["rate"], model, o["values"][0]))
    threshold = o["threshold"] or base.quasi_static_threshold(doc)
    axis = {"x": 0, "y": 1, "z": 2}.get(str(doc["stages"][stage].get("axial_axis", "z")).lower(), 2)
    key = f"stages[{stage}].strain_rate_dimensionless" if rate_sweep else "damping.ratio"
    try:
        os.makedirs(out, exist_ok=True)
        base_path = base.write(doc, out)
    except OSError as e:
        raise OSError(f"--out: cannot write '{out}': {e.strerror}") from None
    spec = spec_from_dict({"name": cmd.replace("-", "_"), "output": os.path.join(out, "sweep"), "base": base_path,
                           "parameters": {key: o["values"]}, "threads": 1}, folder=out)
    _note(f"{cmd}: {len(o['values'])} runs of {os.path.basename(o['protocol'])} (shear stage stages[{stage}], "
          f"{model}, " + (f"xi = {fixed:g}" if rate_sweep else f"eps' = {fixed:g}") + f", I_QS = {threshold:g}); "
          f"report {out}")
    try:
        code = run_sweep(spec, backend=o["backend"], jobs=o["jobs"], stream=sys.stderr,
                         program_path=os.path.join(program_dir(), "triax_run"), wait=True)
    except SweepError as e:
        if e.path.startswith(f"parameters.{key}["):   # a value triax_run refuses: name the option
            raise SweepError(o["field"] + e.path[len(f"parameters.{key}"):], e.reason) from None
        raise
    runs = _runs(out, key, "rate" if rate_sweep else "damping", model, fixed)
    for r in runs:
        if r["stage_steps"] and len(r["stage_steps"]) > stage:
            r["shear_steps"] = r["stage_steps"][stage]
    timing = _timing(os.path.join(out, "sweep"))
    for r in runs:
        r["wall_s"] = round(timing[r["run"]], 3) if r["run"] in timing else None
    report.write_runs_csv(os.path.join(out, "runs.csv"), runs)
    done = [r for r in runs if r["status"] == "completed"]
    result = {"command": cmd, "protocol": o["protocol"], "report_dir": out, "runs": len(runs),
              "runs_completed": len(done), "runs_failed": sum(r["status"] == "failed" for r in runs),
              "damping_model": model, "quasi_static_threshold": threshold}
    if rate_sweep:
        result["damping_ratio"] = fixed
    else:
        result["eps_prime"] = fixed
    code = _exit_code(code, runs)
    t0 = _t0(done)
    _figures(out, runs, done, stage, doc, axis, rate_sweep)
    fitted = None
    need = 2 if rate_sweep else 3
    if len(done) >= need:
        try:
            fitted, notes = (fit.fit_rates([(r["eps_prime"], r["summary"]) for r in done], threshold) if rate_sweep
                             else fit.fit_damping([(r["damping_ratio"], r["eps_prime"], r["summary"]) for r in done],
                                                  threshold))
        except SweepError as e:
            _note(f"error: {o['field']}: no fit: {e.reason}")
            code = code or EXIT_BAD_INPUT
        else:
            for n in notes:
                if "warning" in n:
                    _note(n.replace("triax_qs: ", "", 1))
            write_atomic(os.path.join(out, "fit.json"), json.dumps(fitted, indent=1) + "\n")
            result.update(fitted)
            result.pop("runs", None)
            result["runs"] = len(runs)
            _figures_fit(out, done, fitted, threshold, rate_sweep, os.path.basename(o["protocol"]))
    else:
        _note(f"error: {o['field']}: {len(done)} runs completed, {need} needed for the fit")
        code = code or EXIT_ABORTED
    if fitted and rate_sweep:
        _summarise_rates(result, fitted, t0)
    elif fitted:
        _summarise_damping(result, fitted)
    result["wall_s"] = round(time.monotonic() - t_start, 3)
    result["load_average_1min"] = round(os.getloadavg()[0], 2)
    line = json.dumps(result, separators=(",", ":"))
    write_atomic(os.path.join(out, "result.json"), line + "\n")
    print(line, flush=True)
    return code


def _timing(folder):
    import csv
    path = os.path.join(folder, "sweep_timing.csv")
    if not os.path.isfile(path):
        return {}
    with open(path, newline="") as f:
        return {r["run"]: float(r["wall_seconds"]) for r in csv.DictReader(f) if r.get("wall_seconds")}


def _t0(done):
    for r in done:
        if r["strain_rate_per_s"]:
            return r["eps_prime"] / r["strain_rate_per_s"]
    return None


def _summarise_rates(result, f, t0):
    qs, se = f.get("eps_prime_qs_eq73"), f.get("se_ln_eps_prime_qs_eq73")
    if qs and se is not None:
        result["eps_prime_qs_eq73_low_1se"] = _g6(qs * math.exp(-se))
        result["eps_prime_qs_eq73_high_1se"] = _g6(qs * math.exp(se))
    if qs and t0:
        result["t0_s"] = _g6(t0)
        result["strain_rate_qs_eq73_per_s"] = _g6(qs / t0)
    factor = "x/÷ %.2f" % math.exp(se) if se is not None else "no uncertainty (2 runs)"
    _note("eps'_QS = %.3g (%s, 1 s.e.; eq. 73, I_QS = %g)%s" %
          (qs, factor, result["quasi_static_threshold"],
           ", %.3g 1/s" % (qs / t0) if qs and t0 else ""))
    se_phi = f.get("se_phi_qs_eq74_deg")
    _note("phi_QS = %.2f deg (+- %s deg, 1 s.e.; eq. 74)%s" %
          (f["phi_qs_eq74_deg"], "%.2f" % se_phi if se_phi is not None else "?",
           "; eq. 75: %.2f deg" % f["phi_qs_eq75_deg"] if f.get("phi_qs_eq75_deg") is not None else ""))


def _summarise_damping(result, f):
    _note("optimum damping ratio xi = %.3g %% (%s), mean I_mom there %.3g" %
          (100 * f["optimum_damping_ratio"], result["damping_model"], f["min_mean_moment_index"]))
    if f.get("phi_qs_damping_based_deg") is not None:
        _note("phi_QS = %.2f deg (+- %.2f deg, 1 s.e.; eq. 74 over xi >= xi_opt)" %
              (f["phi_qs_damping_based_deg"], f.get("se_phi_qs_damping_based_deg") or float("nan")))


def _figures(out, runs, done, stage, doc, axis, rate_sweep):
    """q - eps_a of every completed run (the curves are an illustration: a
    missing results file is a warning, the numbers are in runs.csv)."""
    curves = []
    interval = base.control_interval(doc)
    for r in done:
        try:
            eps, q = report.shear_curve(r["results"], sum(r["stage_steps"][:stage]), interval, axis)
            curves.append((r, eps, q))
        except Exception as e:  # noqa: BLE001
            _note(f"warning: no q - eps_a curve of run {r['run']}: {e}")
    report.write_curves(os.path.join(out, "q_eps_a.csv"), curves)
    label = (lambda r: "eps' = %.3g" % r["eps_prime"]) if rate_sweep else \
        (lambda r: "xi = %.3g %%" % (100 * r["damping_ratio"]))
    if curves:
        report.plot_curves(os.path.join(out, "q_eps_a.png"), curves, label, "q - eps_a of the sweep's runs")


def _figures_fit(out, done, f, threshold, rate_sweep, name):
    if rate_sweep:
        report.plot_rate_fit(os.path.join(out, "i_mom_vs_rate.png"), done, f, threshold, f"{name}: eq. 73")
        report.plot_friction_line(os.path.join(out, "tan_phi_vs_i_mom.png"), done, f.get("phi_qs_eq74_deg"),
                                  f.get("k_eq74", 0.0), f"{name}: eq. 74", "eq. 74")
    else:
        report.plot_damping(os.path.join(out, "i_mom_vs_damping.png"), done, f, f"{name}: optimum damping")
        report.plot_friction_line(os.path.join(out, "tan_phi_vs_i_mom.png"),
                                  [r for r in done if r["damping_ratio"] >= f["optimum_damping_ratio"]],
                                  f.get("phi_qs_damping_based_deg"), f.get("k_damping_based", 0.0),
                                  f"{name}: runs at xi >= xi_opt", "eq. 74")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    usage = "usage: triax_qs rate-sweep PROTOCOL.yaml --rates ... | triax_qs damping-sweep PROTOCOL.yaml " \
            "--ratios ... --model OD|ND --rate EPS'"
    if not argv or argv[0] not in ("rate-sweep", "damping-sweep"):
        print(f"triax_qs: error: command: expected rate-sweep or damping-sweep\n{usage}", file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        return sweep(_options(argv[0], argv[1:]))
    except SweepError as e:
        print(f"triax_qs: error: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as e:
        print(f"triax_qs: error: {e}", file=sys.stderr)
        return EXIT_OUTPUT
    except KeyboardInterrupt:
        print("\ntriax_qs: interrupted; finished runs are kept, the same command continues", file=sys.stderr)
        return EXIT_ABORTED
