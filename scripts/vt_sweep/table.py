"""The results table of a sweep: `sweep.csv` and `sweep.h5`, one row per run.

Columns, in this order: `run` (id), `index`, one column per parameter named
`KEY [UNIT]` (SI), `status` (completed | failed | pending), `exit_code`,
`message`, then the program's JSON summary flattened (`stages[1].steps`,
`stress_pa[2]`; names as triax_run / triax_prepare print them, units in the
name: `_pa` Pa, `_deg` degrees, `_s` seconds). What depends on the machine
(wall times, host, backend) is in `sweep_timing.csv` instead, so the same
sweep gives the same table on every backend, bit for bit.
`sweep.h5` holds the same columns as datasets under /runs (in column order,
attribute `unit`), numbers as float64 (NaN = missing) or int64, text as UTF-8.
"""
import csv
import io
import json
import os

from .fsutil import write_atomic
from .plan import read_plan
from .run_one import is_published, read_status

MACHINE_KEYS = {"wall_seconds", "results"}


def _flatten(prefix, value, out):
    if isinstance(value, dict):
        for k, v in value.items():
            _flatten(f"{prefix}.{k}" if prefix else k, v, out)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            _flatten(f"{prefix}[{i}]", v, out)
    else:
        out[prefix] = value


def collect(out):
    """(columns, rows, timing rows) of the sweep in `out`, in run order."""
    plan = read_plan(out)
    params = plan["parameters"]
    rows, timing, summary_cols = [], [], []
    for run in plan["runs"]:
        row = {"run": run["id"], "index": run["index"]}
        for p in params:
            v = run["values"][p["key"]]
            row[p["column"]] = json.dumps(v) if isinstance(v, list) else v
        row.update(status="pending", exit_code=None, message="")
        if is_published(out, run["id"]):
            st = read_status(out, run["id"])
            row.update(status=st["status"], exit_code=st["exit_code"], message=st["message"])
            timing.append({"run": run["id"], "status": st["status"], "wall_seconds": st["wall_seconds"],
                           "cpu_seconds": st.get("cpu_seconds", ""), "host": st["host"], "backend": st["backend"], "started_utc": st["started_utc"],
                           "finished_utc": st["finished_utc"]})
            path = os.path.join(out, "runs", run["id"], "summary.json")
            if os.path.isfile(path):
                with open(path, encoding="utf-8") as f:
                    flat = {}
                    _flatten("", {k: v for k, v in json.load(f).items() if k not in MACHINE_KEYS}, flat)
                for k, v in flat.items():
                    if k not in summary_cols:
                        summary_cols.append(k)
                    row[k] = v
        rows.append(row)
    columns = ["run", "index"] + [p["column"] for p in params] + ["status", "exit_code", "message"] + [
        c for c in summary_cols if c not in ("status", "exit_code", "message", "run", "index")]
    return columns, rows, timing


def _cell(v):
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def _csv_text(columns, rows):
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(columns)
    for r in rows:
        w.writerow([_cell(r.get(c)) for c in columns])
    return buf.getvalue()


def unit_of(column, params):
    for p in params:
        if p["column"] == column:
            return p["unit"]
    for suffix, unit in (("_pa", "Pa"), ("_deg", "deg"), ("_s", "s")):
        if column.endswith(suffix) or f"{suffix}[" in column:
            return unit
    return "text" if column in ("run", "status", "message") or column.endswith((".name", ".type", ".stop")) \
        or column in ("verdict", "failure") else "-"


def _write_h5(path, plan, columns, rows):
    import h5py  # noqa: E402 (only the table writer needs it)
    import numpy as np

    tmp = f"{path}.tmp-{os.getpid()}"
    # no modification times in object headers, link order = column order:
    # the same table gives the same bytes
    order = h5py.h5p.CRT_ORDER_TRACKED | h5py.h5p.CRT_ORDER_INDEXED
    fcpl = h5py.h5p.create(h5py.h5p.FILE_CREATE)
    fcpl.set_obj_track_times(False)
    fcpl.set_link_creation_order(order)
    gcpl = h5py.h5p.create(h5py.h5p.GROUP_CREATE)
    gcpl.set_obj_track_times(False)
    gcpl.set_link_creation_order(order)
    with h5py.File(h5py.h5f.create(tmp.encode(), h5py.h5f.ACC_TRUNC, fcpl=fcpl)) as f:
        f.attrs["name"] = plan["name"]
        f.attrs["program"] = plan["program"]
        f.attrs["combine"] = plan["combine"]
        g = h5py.Group(h5py.h5g.create(f.id, b"runs", gcpl=gcpl))
        for c in columns:
            vals = [r.get(c) for r in rows]
            present = [v for v in vals if v is not None]
            if present and all(isinstance(v, bool) for v in present):
                data = np.array([-1 if v is None else int(v) for v in vals], dtype=np.int8)
            elif present and all(isinstance(v, int) and not isinstance(v, bool) for v in present) \
                    and len(present) == len(vals):
                data = np.array(vals, dtype=np.int64)
            elif present and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in present):
                data = np.array([np.nan if v is None else float(v) for v in vals], dtype=np.float64)
            else:
                data = np.array([_cell(v) for v in vals], dtype=h5py.string_dtype("utf-8"))
            d = g.create_dataset(c, data=data, track_times=False)
            d.attrs["unit"] = unit_of(c, plan["parameters"])
    os.replace(tmp, path)


def write_tables(out):
    """Writes sweep.csv, sweep.h5 and sweep_timing.csv into `out`; returns (columns, rows)."""
    plan = read_plan(out)
    columns, rows, timing = collect(out)
    write_atomic(os.path.join(out, "sweep.csv"), _csv_text(columns, rows))
    tcols = ["run", "status", "wall_seconds", "cpu_seconds", "host", "backend", "started_utc", "finished_utc"]
    write_atomic(os.path.join(out, "sweep_timing.csv"), _csv_text(tcols, timing))
    _write_h5(os.path.join(out, "sweep.h5"), plan, columns, rows)
    return columns, rows


def counts(out, plan=None):
    """{'completed': n, 'failed': n, 'pending': n} of the runs in `out`."""
    plan = plan or read_plan(out)
    c = {"completed": 0, "failed": 0, "pending": 0}
    for run in plan["runs"]:
        c[read_status(out, run["id"])["status"] if is_published(out, run["id"]) else "pending"] += 1
    return c
