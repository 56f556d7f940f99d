"""The sweep file: what to run and which parameters to vary (strictly validated).

    name: rate_damping                 # [A-Za-z0-9_.-]+, names the sweep
    output: runs/rate_damping          # folder, relative to this file's folder
    base: ../protocols/drained.yaml    # a scene or protocol run by triax_run
    # or, instead of base, a preparation run by triax_prepare:
    # prepare: {psd: ../psd/mono.yaml, particles: 1000, seed: 1, ...}
    parameters:                        # dotted keys (option names for prepare)
      stages[1].strain_rate_dimensionless: [1.0e-5, 5.0e-6]
      damping.ratio: [0.003, 0.01]
    combine: grid                      # grid (every combination) or zip
    threads: 1                         # OpenMP threads per run
    slurm: {partition: short, time: "00:30:00", mem: 2G, max_parallel: 8}

Every error is one line naming the dotted path, e.g.
`parameters.damping.ratio[1]: must be a number, got 'x'`.
"""
import copy
import math
import os
import re

from . import dotted
from .errors import SweepError
from .strict_yaml import load_file
from .units import PREPARE_OPTIONS, SCENE_PATH_KEYS, scene_unit

TOP_KEYS = ("name", "output", "base", "prepare", "parameters", "combine", "threads", "slurm")
SLURM_KEYS = ("partition", "time", "mem", "max_parallel", "extra_args")


class Parameter:
    """One varied key: its dotted name, parsed tokens (scene) or option name
    (prepare), its values as written, its SI unit and its table column."""

    def __init__(self, key, tokens, values, unit):
        self.key, self.tokens, self.values, self.unit = key, tokens, values, unit
        self.column = f"{key} [{unit}]"


class SweepSpec:
    """A validated sweep file. Construct with `load_spec(path)` or `spec_from_dict`."""

    def __init__(self):
        self.path = ""            # sweep file ('' when built from a dict)
        self.folder = ""          # folder relative paths are taken from
        self.name = ""
        self.output = ""          # absolute output folder
        self.program = ""         # 'triax_run' or 'triax_prepare'
        self.base = ""            # absolute base file (triax_run)
        self.base_tree = None     # its parsed YAML, sample_file made absolute
        self.prepare = {}         # fixed triax_prepare options
        self.parameters = []      # [Parameter]
        self.combine = "grid"
        self.threads = 1
        self.slurm = {}

    def combinations(self):
        """[{key: value}] in run order: grid = first key slowest; zip = i-th of each."""
        if self.combine == "zip":
            n = len(self.parameters[0].values)
            return [{p.key: p.values[i] for p in self.parameters} for i in range(n)]
        combos = [{}]
        for p in self.parameters:
            combos = [dict(c, **{p.key: v}) for c in combos for v in p.values]
        return combos


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _check_value(v, where):
    if isinstance(v, float) and not math.isfinite(v):
        raise SweepError(where, f"must be finite, got {v}")
    if isinstance(v, list):
        if not v:
            raise SweepError(where, "an empty list is not a value")
        for i, x in enumerate(v):
            if not (_is_number(x) or isinstance(x, str)):
                raise SweepError(f"{where}[{i}]", f"must be a number or text, got {type(x).__name__}")
            _check_value(x, f"{where}[{i}]")
    elif not (_is_number(v) or isinstance(v, (str, bool))):
        raise SweepError(where, f"must be a number, text or a list of numbers, got {type(v).__name__}")


def _absolute(path, folder):
    return path if os.path.isabs(path) else os.path.normpath(os.path.join(folder, path))


def _mapping(node, where, allowed):
    if not isinstance(node, dict):
        raise SweepError(where, f"must be a mapping, got {type(node).__name__}")
    for k in node:
        if k not in allowed:
            raise SweepError(f"{where + '.' if where else ''}{k}",
                             f"unknown key; allowed: {', '.join(allowed)}")
    return node


def _text(node, key, where):
    v = node.get(key)
    if not isinstance(v, str) or not v.strip():
        raise SweepError(where, f"must be non-empty text, got {v!r}")
    return v


def _parse_base(spec, doc):
    spec.program = "triax_run"
    spec.base = _absolute(_text(doc, "base", "base"), spec.folder)
    if not os.path.isfile(spec.base):
        raise SweepError("base", f"no such file '{spec.base}'")
    tree = load_file(spec.base, "base")
    if not isinstance(tree, dict):
        raise SweepError("base", f"'{spec.base}' is not a scene or protocol (not a mapping)")
    particles = tree.get("particles")
    if isinstance(particles, dict) and isinstance(particles.get("sample_file"), str):
        particles["sample_file"] = _absolute(particles["sample_file"], os.path.dirname(spec.base))
    spec.base_tree = tree


def _parse_prepare(spec, doc):
    spec.program = "triax_prepare"
    opts = _mapping(doc["prepare"], "prepare", list(PREPARE_OPTIONS))
    for k, v in opts.items():
        spec.prepare[k] = _prepare_value(spec, k, v, f"prepare.{k}")


def _prepare_value(spec, option, v, where):
    unit, kind = PREPARE_OPTIONS[option]
    if kind in ("number", "integer"):
        if not _is_number(v) or (isinstance(v, float) and not math.isfinite(v)):
            raise SweepError(where, f"must be a finite number, got {v!r}")
        if kind == "integer" and float(v) != int(v):
            raise SweepError(where, f"must be an integer, got {v!r}")
        return int(v) if kind == "integer" else v
    if kind == "path":
        if not isinstance(v, str) or not os.path.isfile(_absolute(v, spec.folder)):
            raise SweepError(where, f"no such file {v!r}")
        return v
    if isinstance(v, list):
        return ",".join(repr(x) for x in v)
    return str(v)


def _parse_parameters(spec, doc):
    params = doc.get("parameters")
    if not isinstance(params, dict) or not params:
        raise SweepError("parameters", "required: a mapping of dotted keys to lists of values")
    for key, values in params.items():
        where = f"parameters.{key}"
        if not isinstance(values, list) or not values:
            raise SweepError(where, "must be a non-empty list of values")
        if spec.program == "triax_run":
            tokens = dotted.parse(key, where)
            dotted.locate(copy.deepcopy(spec.base_tree), tokens, where)  # raises if it cannot exist
            for i, v in enumerate(values):
                _check_value(v, f"{where}[{i}]")
                if tokens[-1] in SCENE_PATH_KEYS and not (isinstance(v, str) and os.path.isfile(_absolute(v, spec.folder))):
                    raise SweepError(f"{where}[{i}]", f"no such file {v!r}")
            unit = scene_unit(tokens)
        else:
            option = key.replace("-", "_")
            if option not in PREPARE_OPTIONS:
                raise SweepError(where, f"not a triax_prepare option; allowed: {', '.join(PREPARE_OPTIONS)}")
            if option in spec.prepare:
                raise SweepError(where, f"also fixed in prepare.{option}: give it in one place")
            tokens = [option]
            values = [_prepare_value(spec, option, v, f"{where}[{i}]") for i, v in enumerate(values)]
            unit = PREPARE_OPTIONS[option][0]
        if len(set(map(repr, values))) != len(values):
            raise SweepError(where, "a value is listed twice")
        spec.parameters.append(Parameter(key, tokens, values, unit))
    if spec.program == "triax_prepare":
        given = set(spec.prepare) | {p.tokens[0] for p in spec.parameters}
        for need in ("psd", "pressure", "seed"):
            if need not in given:
                raise SweepError(f"prepare.{need}", "required (in prepare or as a parameter)")
        if not given & {"mu1", "target_void_ratio"}:
            raise SweepError("prepare.mu1", "required (or target_void_ratio), in prepare or as a parameter")


def spec_from_dict(doc, folder, path="", output=None):
    """A SweepSpec from an already-read sweep document; relative paths from `folder`."""
    spec = SweepSpec()
    spec.path, spec.folder = path, os.path.abspath(folder)
    _mapping(doc, "", list(TOP_KEYS))
    spec.name = _text(doc, "name", "name")
    if not re.fullmatch(r"[A-Za-z0-9_.-]+", spec.name):
        raise SweepError("name", f"only letters, digits, '_', '.', '-' allowed, got {spec.name!r}")
    spec.output = os.path.abspath(output) if output else _absolute(_text(doc, "output", "output"), spec.folder)
    if ("base" in doc) == ("prepare" in doc):
        raise SweepError("base", "give exactly one of base (a scene or protocol for triax_run) "
                                 "and prepare (triax_prepare options)")
    (_parse_base if "base" in doc else _parse_prepare)(spec, doc)
    _parse_parameters(spec, doc)
    spec.combine = doc.get("combine", "grid")
    if spec.combine not in ("grid", "zip"):
        raise SweepError("combine", f"must be grid or zip, got {spec.combine!r}")
    if spec.combine == "zip":
        first = spec.parameters[0]
        for p in spec.parameters[1:]:
            if len(p.values) != len(first.values):
                raise SweepError(f"parameters.{p.key}", f"{len(p.values)} values, but parameters.{first.key} has "
                                                        f"{len(first.values)} (combine: zip needs equal lengths)")
    spec.threads = doc.get("threads", 1)
    if not isinstance(spec.threads, int) or isinstance(spec.threads, bool) or spec.threads < 1:
        raise SweepError("threads", f"must be an integer >= 1, got {spec.threads!r}")
    spec.slurm = dict(_mapping(doc.get("slurm") or {}, "slurm", list(SLURM_KEYS)))
    mp = spec.slurm.get("max_parallel")
    if mp is not None and (not isinstance(mp, int) or isinstance(mp, bool) or mp < 1):
        raise SweepError("slurm.max_parallel", f"must be an integer >= 1, got {mp!r}")
    extra = spec.slurm.get("extra_args", [])
    if not isinstance(extra, list) or not all(isinstance(a, str) for a in extra):
        raise SweepError("slurm.extra_args", "must be a list of sbatch arguments (text)")
    for k in ("partition", "time", "mem"):
        if k in spec.slurm and not isinstance(spec.slurm[k], (str, int)):
            raise SweepError(f"slurm.{k}", f"must be text, got {spec.slurm[k]!r}")
    return spec


def load_spec(path, output=None):
    """Reads and validates a sweep file; `output` overrides its output folder."""
    doc = load_file(path, "sweep")
    if not isinstance(doc, dict):
        raise SweepError("sweep", f"'{path}' must be a mapping of sweep keys")
    return spec_from_dict(doc, os.path.dirname(os.path.abspath(path)), os.path.abspath(path), output)
