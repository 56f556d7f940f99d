#!/usr/bin/python3
"""Turn rosbag recordings of the virtual rig into a per-tick CSV and plots.

usage: bag_report.py BAG [BAG ...] --out DIR [--csv-only] [--ns NS] [--axis z]

Reads the rig topics of one or more bags (the files of a split recording may
be given in any order: they are read in time order, the files of a resumed
test, PREFIX_rN_K.bag as run_triaxial.sh names them, after those of the run
it resumes), found by MESSAGE TYPE,
so namespaced rigs work (/rig1/stress ...):
  virtual_triaxial/Stress, Strain, MomentIndex, KineticEnergy, Fabric,
  ServoState, ProtocolStatus (each optional, at least one required).
Joins them by their `tick` field and writes
  DIR/rig_series.csv        one row per tick (rising), units in the header
                            (_Pa, _J, _s, _rad, _per_s; none = dimensionless);
                            a tick a topic has no message for is left empty;
                            the ProtocolStatus columns (sent on events and
                            sample ticks) carry the status that holds at the
                            tick (see _event_tick)
  DIR/q_eps_a.png           deviator stress against axial strain
  DIR/eps_v_eps_a.png       volumetric against axial strain
  DIR/q_p_stress_path.png   q - p stress path
  DIR/e_log_p.png           void ratio against log p
  DIR/I_mom_eps_a.png       moment index (and UFR) against axial strain
  DIR/kinetic_energy_eps_a.png  kinetic energy against axial strain
(PNGs are skipped with --csv-only, or one by one when its topics are absent.)
SI units, compression positive everywhere (DESIGN §2; the messages already
are). eps_a is the strain of the loading axis (--axis, default z), measured
from the strain reference of dem_node (not from the start of a stage).

When several topics carry one type (several rigs in one bag), pick the rig
with --ns (e.g. --ns /rig1). Exit status 2 with a message naming the file or
topic for a missing/unreadable bag, a bag without rig topics, or an
ambiguous rig; 0 otherwise. Prints what it wrote.
"""
import argparse
import csv
import math
import os
import re
import sys

PROG = "bag_report"

# message type -> short name
RIG_TYPES = {
    "virtual_triaxial/Stress": "stress",
    "virtual_triaxial/Strain": "strain",
    "virtual_triaxial/MomentIndex": "moment_index",
    "virtual_triaxial/KineticEnergy": "kinetic_energy",
    "virtual_triaxial/Fabric": "fabric",
    "virtual_triaxial/ServoState": "servo_state",
    "virtual_triaxial/ProtocolStatus": "protocol_status",
}
XYZ = "xyz"


class ReportError(Exception):
    """A user-facing error: exit status 2."""


def die(msg):
    sys.stderr.write("%s: error: %s\n" % (PROG, msg))
    sys.exit(2)


# ---- columns ---------------------------------------------------------------------------
# Each extractor: list of (column name, function(msg) -> value). Names carry
# the unit; dimensionless quantities have none.

def _stress_cols(axis):
    cols = [("time_s", lambda m: m.time), ("control_period_s", lambda m: m.control_period)]
    for i, a in enumerate(XYZ):
        cols.append(("sigma_%s%s_Pa" % (a, a), lambda m, j=4 * i: m.stress[j]))
    for name, j in (("xy", 1), ("xz", 2), ("yz", 5)):
        cols.append(("sigma_%s_Pa" % name, lambda m, j=j: m.stress[j]))
    for i in range(3):
        cols.append(("s%d_Pa" % (i + 1), lambda m, i=i: m.principal[i]))
    cols += [("p_Pa", lambda m: m.p), ("q_Pa", lambda m: m.q), ("phi_rad", lambda m: m.phi),
             ("phi_deg", lambda m: math.degrees(m.phi)), ("sigma_bar_p", lambda m: m.sigma_bar_p)]
    for i, a in enumerate(XYZ):
        cols.append(("stiffness_%s_Pa" % a, lambda m, i=i: m.stiffness[i]))
    return cols


def _strain_cols(axis):
    ia = XYZ.index(axis)
    cols = [("eps_a", lambda m: m.strain[ia]), ("eps_v", lambda m: m.volumetric)]
    for i, a in enumerate(XYZ):
        cols.append(("eps_%s" % a, lambda m, i=i: m.strain[i]))
    for i, a in enumerate(XYZ):
        cols.append(("eps_rate_%s_per_s" % a, lambda m, i=i: m.strain_rate[i]))
    for i, a in enumerate(XYZ):
        cols.append(("eps_rate_dimensionless_%s" % a, lambda m, i=i: m.strain_rate_dimensionless[i]))
    return cols


def _moment_cols(axis):
    return [("I_mom", lambda m: m.moment_index), ("ufr", lambda m: m.ufr), ("I_uf", lambda m: m.iuf),
            ("I_in", lambda m: m.inertia_index)]


def _energy_cols(axis):
    return [("ke_trans_J", lambda m: m.translational), ("ke_rot_J", lambda m: m.rotational),
            ("ke_total_J", lambda m: m.translational + m.rotational),
            ("boundary_work_J", lambda m: m.boundary_work), ("elastic_energy_J", lambda m: m.elastic),
            ("damping_dissipation_J", lambda m: m.damping), ("friction_dissipation_J", lambda m: m.friction),
            ("energy_balance_error_J", lambda m: m.balance_error),
            ("energy_relative_balance_error", lambda m: m.relative_balance_error)]


def _fabric_cols(axis):
    return [("e", lambda m: m.void_ratio), ("Z_mech", lambda m: m.coordination_number),
            ("Z_raw", lambda m: m.raw_coordination_number), ("idle_mass_fraction", lambda m: m.idle_mass_fraction),
            ("contacts", lambda m: m.contacts), ("sliding_contacts", lambda m: m.sliding_contacts)]


def _servo_cols(axis):
    cols = [("servo_enabled", lambda m: int(bool(m.enabled)))]
    for i, a in enumerate(XYZ):
        cols.append(("servo_target_%s_Pa" % a, lambda m, i=i: m.targets[i]))
    for i, a in enumerate(XYZ):
        cols.append(("servo_error_%s_Pa" % a, lambda m, i=i: m.errors[i]))
    for i, a in enumerate(XYZ):
        cols.append(("servo_rate_%s_per_s" % a, lambda m, i=i: m.strain_rate[i]))
    for i, a in enumerate(XYZ):
        cols.append(("servo_saturated_%s" % a, lambda m, i=i: int(bool(m.saturated[i]))))
    return cols


def _protocol_cols(axis):
    return [("protocol_state", lambda m: m.state), ("protocol_stage", lambda m: m.stage),
            ("protocol_stage_index", lambda m: m.stage_index),
            ("stage_eps_a", lambda m: m.eps_a), ("stage_eps_v", lambda m: m.eps_v)]


COLUMNS = {"stress": _stress_cols, "strain": _strain_cols, "moment_index": _moment_cols,
           "kinetic_energy": _energy_cols, "fabric": _fabric_cols, "servo_state": _servo_cols,
           "protocol_status": _protocol_cols}
ORDER = ["stress", "strain", "moment_index", "kinetic_energy", "fabric", "servo_state", "protocol_status"]
# the first topic that has a message for a tick gives time_s when stress is absent
TIME_FIELDS = ["strain", "moment_index", "kinetic_energy", "fabric"]
# Topics published on events (a stage's start and end, the verdict) and on the
# judge's sample ticks, not on every tick. Beside a per-tick rig topic they
# make no rows of their own; each row takes the last message that holds at its
# tick (_event_tick), and none of them missing from a row, or two of them on
# one tick, is worth a warning. (Alone in a recording, they make the rows.)
EVENT_TOPICS = {"protocol_status"}


def _event_tick(msg, events):
    """The tick from which a status holds, or None when it belongs to no tick
    of a test: "idle" (the node between tests) and, after the first, a status
    without its tick (a refused goal; older nodes' stage starts and verdicts).
    A stage start (running after a verdict or another stage) is sent with the
    tick the stage starts after, so it holds from the next one: the last tick
    of the stage or test before keeps its own status."""
    tick = int(msg.tick)
    if msg.state == "idle" or (tick == 0 and events):
        return None
    prev = events[-1][2] if events else None
    starts = msg.state == "running" and prev is not None and (
        prev.state != "running" or (prev.protocol, prev.stage_index) != (msg.protocol, msg.stage_index))
    return tick + 1 if starts else tick


# ---- reading -----------------------------------------------------------------------------
def open_bags(paths):
    import rosbag  # late: a missing file is reported without importing ROS
    for p in paths:
        if not os.path.exists(p):
            raise ReportError("%s: no such file" % p)
        if not os.path.isfile(p):
            raise ReportError("%s: not a file" % p)
    bags = []
    for p in paths:
        try:
            bags.append((p, rosbag.Bag(p, "r")))
        except Exception as e:  # ROSBagException, ROSBagFormatException, OSError, ...
            raise ReportError("%s: not a readable bag (%s)" % (p, e))
    stems = {split_stem(p) for p, _ in bags}
    bags.sort(key=lambda pb: (resume_number(pb[0], stems), bag_start(pb[1])))
    return bags


def split_stem(path):
    """PREFIX of a split recording's file PREFIX_K.bag, None for other names."""
    m = re.match(r"(.*)_\d+\.bag$", os.path.basename(path))
    return m.group(1) if m else None


def resume_number(path, stems):
    """N when the file is PREFIX_rN_K.bag of a test resumed from the one
    recorded in PREFIX_K.bag, also given (stems: the given files'
    split_stem; run_triaxial.sh names them so); else 0. A resumed run's
    files come after the run it resumes, whose ticks they run again. Their
    first message does not say so: the resumed recorder may take its node's
    latched idle status before the first /clock, at time 0 (session 35:
    unit_rig_resume then lost tick 1's status)."""
    m = re.match(r"(.*)_r(\d+)_\d+\.bag$", os.path.basename(path))
    return int(m.group(2)) if m and m.group(1) in stems else 0


def bag_start(bag):
    """A file's first message time (split recordings are read in that order;
    empty files last)."""
    try:
        return bag.get_start_time()
    except Exception:
        return math.inf


def _namespace(topic):
    return topic.rsplit("/", 1)[0] or "/"


def pick_topics(bags, ns):
    """{short name: topic}; raises ReportError when nothing or ambiguous."""
    found = {}  # short name -> set of topics
    for _, bag in bags:
        for topic, info in bag.get_type_and_topic_info().topics.items():
            short = RIG_TYPES.get(info.msg_type)
            if short:
                found.setdefault(short, set()).add(topic)
    if ns is not None:
        want = "/" + ns.strip("/") if ns.strip("/") else "/"
        found = {k: {t for t in v if _namespace(t) == want} for k, v in found.items()}
        found = {k: v for k, v in found.items() if v}
    if not found:
        names = ", ".join(p for p, _ in bags)
        raise ReportError("%s: no rig topics%s (looked for the message types %s)" % (
            names, "" if ns is None else " in namespace %s" % ns, ", ".join(sorted(RIG_TYPES))))
    topics = {}
    for short, ts in found.items():
        if len(ts) > 1:
            raise ReportError("several %s topics (%s): choose the rig with --ns" % (short, ", ".join(sorted(ts))))
        topics[short] = ts.pop()
    return topics


def read_series(bags, topics, axis):
    """{tick: {column: value}} and the ordered column list."""
    by_topic = {t: s for s, t in topics.items()}
    extract = {s: COLUMNS[s](axis) for s in topics}
    # with no per-tick topic at all, the event topics' own ticks make the rows
    events_apart = any(s not in EVENT_TOPICS for s in topics)
    rows = {}
    repeated = {}
    events = []  # (tick from which it holds, short, message), in recording order
    for path, bag in bags:
        rerun = False
        for topic, msg, _t in bag.read_messages(topics=list(by_topic)):
            short = by_topic[topic]
            tick = int(msg.tick)
            if events_apart and short in EVENT_TOPICS:
                held = _event_tick(msg, events)
                if held is not None:
                    events.append((held, short, msg))
                continue
            row = rows.setdefault(tick, {})
            if short in row.get("_from", ()):
                repeated[short] = repeated.get(short, 0) + 1  # later message wins
                if not rerun:
                    # this file runs ticks again (a resumed test): its statuses
                    # replace the older ones from the first tick run again
                    rerun = True
                    events = [e for e in events if e[0] < tick]
            row.setdefault("_from", set()).add(short)
            for name, f in extract[short]:
                row[name] = f(msg)
            if short in TIME_FIELDS and "time_s" not in row and "stress" not in topics:
                row["time_s"] = msg.time
    # each row: the last event message that holds at its tick (stable sort:
    # recording order within a tick)
    events.sort(key=lambda e: e[0])
    current, k = {}, 0
    for tick in sorted(rows):
        while k < len(events) and events[k][0] <= tick:
            current[events[k][1]] = events[k][2]
            k += 1
        for short, msg in current.items():
            for name, f in extract[short]:
                rows[tick][name] = f(msg)
    # a recorder that could not keep up drops messages: say so (cells stay empty)
    for short, topic in sorted(topics.items()):
        if events_apart and short in EVENT_TOPICS:
            continue
        n = sum(1 for r in rows.values() if short in r["_from"])
        if n < len(rows):
            sys.stderr.write("%s: warning: %s (%s): no message for %d of %d ticks (left empty)\n" % (
                PROG, topic, short, len(rows) - n, len(rows)))
    if rows:
        lo, hi = min(rows), max(rows)
        if hi - lo + 1 > len(rows):
            sys.stderr.write("%s: warning: %d ticks between %d and %d are in no rig topic (not recorded, or "
                             "published every few ticks)\n" % (PROG, hi - lo + 1 - len(rows), lo, hi))
    for short, n in repeated.items():
        sys.stderr.write("%s: warning: %s (%s): %d tick(s) seen twice (dem_node restarted?); the later message "
                         "is used\n" % (PROG, topics[short], short, n))
    columns = ["tick"]
    if "stress" not in topics:
        columns.append("time_s")
    for short in ORDER:
        if short in topics:
            columns += [n for n, _ in extract[short] if n not in columns]
    return rows, columns


# ---- writing ------------------------------------------------------------------------------
def _cell(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return repr(v)  # shortest text that reads back to the same double
    return str(v)


def write_csv(path, rows, columns):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for tick in sorted(rows):
            r = rows[tick]
            w.writerow([str(tick)] + [_cell(r.get(c)) for c in columns[1:]])


def _array(rows, name):
    import numpy as np
    out = []
    for t in sorted(rows):
        v = rows[t].get(name)
        out.append(float(v) if isinstance(v, (int, float)) else math.nan)
    return np.array(out, dtype=float)


def write_plots(out, rows, columns, axis):
    """Returns (written paths, skipped messages)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    have = set(columns)
    col = {}

    def c(name):
        if name not in col:
            col[name] = _array(rows, name)
        return col[name]

    written, skipped = [], []
    xa = "axial strain eps_%s [%%] (from the strain reference)" % axis

    def plot(fname, needs, draw):
        missing = [n for n in needs if n not in have]
        if missing:
            skipped.append("%s: no %s column (topic not recorded)" % (fname, ", ".join(missing)))
            return
        fig, ax = plt.subplots(figsize=(7, 4.5))
        draw(ax)
        ax.grid(alpha=0.3, which="both")
        fig.tight_layout()
        p = os.path.join(out, fname)
        fig.savefig(p, dpi=110)
        plt.close(fig)
        written.append(p)

    def xy(x, y):
        """Points where both are known (a tick a topic missed is skipped, not a gap)."""
        x, y = c(x), c(y)
        ok = np.isfinite(x) & np.isfinite(y)
        return x[ok], y[ok]

    def q_eps(ax):
        x, y = xy("eps_a", "q_Pa")
        ax.plot(100 * x, y / 1e3)
        ax.set(xlabel=xa, ylabel="q [kPa]", title="deviator stress")
    plot("q_eps_a.png", ["eps_a", "q_Pa"], q_eps)

    def epsv_eps(ax):
        x, y = xy("eps_a", "eps_v")
        ax.plot(100 * x, 100 * y)
        ax.set(xlabel=xa, ylabel="volumetric strain eps_v [%] (compression +)", title="volume change")
    plot("eps_v_eps_a.png", ["eps_a", "eps_v"], epsv_eps)

    def q_p(ax):
        x, y = xy("p_Pa", "q_Pa")
        ax.plot(x / 1e3, y / 1e3)
        ax.set(xlabel="p [kPa]", ylabel="q [kPa]", title="stress path")
    plot("q_p_stress_path.png", ["p_Pa", "q_Pa"], q_p)

    def e_log_p(ax):
        p, e = xy("p_Pa", "e")
        ok = p > 0
        ax.semilogx(p[ok] / 1e3, e[ok])
        ax.set(xlabel="p [kPa] (log)", ylabel="void ratio e", title="compression curve")
    plot("e_log_p.png", ["p_Pa", "e"], e_log_p)

    def imom(ax):
        x, y = xy("eps_a", "I_mom")
        ax.semilogy(100 * x, np.maximum(y, 1e-12), label="moment index I_mom (eq. 67)")
        x, y = xy("eps_a", "ufr")
        ax.semilogy(100 * x, np.maximum(y, 1e-12), label="UFR (eq. 66)")
        ax.axhline(1e-3, color="k", ls="--", lw=0.8, label="I_QS = 0.1 %")
        ax.set(xlabel=xa, ylabel="index [-]", title="equilibrium")
        ax.legend(fontsize=8)
    plot("I_mom_eps_a.png", ["eps_a", "I_mom", "ufr"], imom)

    def ke(ax):
        x, y = xy("eps_a", "ke_trans_J")
        ax.semilogy(100 * x, np.maximum(y, 1e-300), label="translational")
        x, y = xy("eps_a", "ke_rot_J")
        ax.semilogy(100 * x, np.maximum(y, 1e-300), label="rotational")
        ax.set(xlabel=xa, ylabel="kinetic energy [J]", title="kinetic energy")
        ax.legend(fontsize=8)
    plot("kinetic_energy_eps_a.png", ["eps_a", "ke_trans_J", "ke_rot_J"], ke)
    return written, skipped


def main(argv=None):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.splitlines()[0])
    ap.add_argument("bags", nargs="+", metavar="BAG", help="bag file(s); the files of a split recording")
    ap.add_argument("--out", required=True, metavar="DIR", help="output folder (created)")
    ap.add_argument("--csv-only", action="store_true", help="write the CSV only, no PNGs")
    ap.add_argument("--ns", default=None, help="rig namespace when a bag holds several rigs, e.g. /rig1")
    ap.add_argument("--axis", default="z", choices=list(XYZ), help="loading (axial) axis, default z")
    a = ap.parse_args(argv)
    try:
        bags = open_bags(a.bags)
        try:
            topics = pick_topics(bags, a.ns)
            rows, columns = read_series(bags, topics, a.axis)
        finally:
            for _, b in bags:
                b.close()
        if not rows:
            raise ReportError("%s: the rig topics hold no messages (%s)" % (
                ", ".join(a.bags), ", ".join(sorted(topics.values()))))
        os.makedirs(a.out, exist_ok=True)
    except ReportError as e:
        die(str(e))
    except OSError as e:
        die("%s: %s" % (getattr(e, "filename", None) or a.out, e.strerror or e))
    csv_path = os.path.join(a.out, "rig_series.csv")
    write_csv(csv_path, rows, columns)
    ticks = sorted(rows)
    print("%s: read %s from %d bag(s)" % (
        PROG, ", ".join("%s (%s)" % (t, s) for s, t in sorted(topics.items())), len(bags)))
    print("%s: wrote %s (%d ticks %d..%d, %d columns)" % (PROG, csv_path, len(ticks), ticks[0], ticks[-1],
                                                         len(columns)))
    if not a.csv_only:
        written, skipped = write_plots(a.out, rows, columns, a.axis)
        for p in written:
            print("%s: wrote %s" % (PROG, p))
        for s in skipped:
            print("%s: skipped %s" % (PROG, s))
    return 0


if __name__ == "__main__":
    sys.exit(main())
