"""Strict YAML reading for sweep files and the protocols they vary.

PyYAML follows YAML 1.1, where `1e-5` (no dot) is text; scenes are read by
yaml-cpp, which takes it as a number. This loader reads numbers as YAML 1.2
does (`1e-5`, `-2.5E+3`, `.5` are floats) and refuses duplicated keys, naming
the key and its line.
"""
import re

import yaml

from .errors import SweepError

_FLOAT = re.compile(r"""^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+]?[0-9]+)?
                      |[-+]?(?:[0-9][0-9_]*)(?:[eE][-+]?[0-9]+)
                      |[-+]?\.[0-9_]+(?:[eE][-+]?[0-9]+)?
                      |[-+]?\.(?:inf|Inf|INF)
                      |\.(?:nan|NaN|NAN))$""", re.X)


class StrictLoader(yaml.SafeLoader):
    """SafeLoader with YAML 1.2 floats and an error on duplicated keys."""


StrictLoader.yaml_implicit_resolvers = {
    k: [(tag, rx) for tag, rx in v if tag != "tag:yaml.org,2002:float"]
    for k, v in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
StrictLoader.add_implicit_resolver("tag:yaml.org,2002:float", _FLOAT, list("-+0123456789."))


def _mapping(loader, node, deep=False):
    seen = {}
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=True)
        if key in seen:
            raise yaml.constructor.ConstructorError(
                None, None, f"duplicated key '{key}' (first at line {seen[key] + 1})", key_node.start_mark)
        seen[key] = key_node.start_mark.line
    return loader.construct_mapping(node, deep=deep)


StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _mapping)


def load_file(path, what):
    """The document in `path`; SweepError(`what`, ...) if unreadable or not YAML."""
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise SweepError(what, f"cannot open '{path}': {e.strerror}") from None
    try:
        docs = list(yaml.load_all(text, Loader=StrictLoader))
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(e, "problem", None) or str(e)
        raise SweepError(what, f"YAML error in '{path}'{where}: {problem}") from None
    if len(docs) != 1 or docs[0] is None:
        raise SweepError(what, f"'{path}' must hold exactly one non-empty YAML document")
    return docs[0]


class _Dumper(yaml.SafeDumper):
    pass


def _float(dumper, x):
    # repr() is the shortest text that reads back to the same double; yaml-cpp
    # reads it back exactly too (always with a dot or an exponent).
    text = repr(x)
    if text in ("inf", "-inf", "nan"):
        text = {"inf": ".inf", "-inf": "-.inf", "nan": ".nan"}[text]
    elif "." not in text and "e" not in text:
        text += ".0"
    return dumper.represent_scalar("tag:yaml.org,2002:float", text)


_Dumper.add_representer(float, _float)


def dump(data):
    """YAML text of `data`, keys in their order, floats exact."""
    return yaml.dump(data, Dumper=_Dumper, sort_keys=False, default_flow_style=False)
