"""Dotted keys into a YAML tree: `stages[1].stop.axial_strain`, `damping.ratio`."""
import re

from .errors import SweepError

_TOKEN = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)((?:\[[0-9]+\])*)")


def parse(key, where):
    """['stages', 1, 'strain_rate_dimensionless'] from 'stages[1].strain_rate_dimensionless'."""
    if not isinstance(key, str) or not key:
        raise SweepError(where, "a parameter key must be a non-empty dotted key such as damping.ratio")
    tokens = []
    for part in key.split("."):
        m = _TOKEN.fullmatch(part)
        if not m:
            raise SweepError(where, f"'{part}' is not a key: expected name or name[index] between the dots")
        tokens.append(m.group(1))
        tokens.extend(int(i) for i in re.findall(r"\[([0-9]+)\]", m.group(2)))
    return tokens


def render(tokens):
    out = ""
    for t in tokens:
        out += f"[{t}]" if isinstance(t, int) else (("." if out else "") + t)
    return out


def locate(tree, tokens, where):
    """Walks to the parent of the last token; creates missing mappings on the way.

    A list index must exist (a sweep cannot invent a stage); a missing mapping
    key is allowed (an optional section or key the base file leaves at its
    default; triax_run --check decides whether it is a known key). Returns
    (parent, last token, whether the key exists in the base file)."""
    node = tree
    for depth, t in enumerate(tokens[:-1]):
        nxt = tokens[depth + 1]
        here = render(tokens[: depth + 1])
        if isinstance(t, int):
            if not isinstance(node, list):
                raise SweepError(where, f"'{render(tokens[:depth])}' is not a list in the base file")
            if t >= len(node):
                raise SweepError(where, f"'{here}' does not exist in the base file "
                                        f"({render(tokens[:depth])} has {len(node)} entries)")
            node = node[t]
        else:
            if not isinstance(node, dict):
                raise SweepError(where, f"'{render(tokens[:depth]) or 'top level'}' is not a mapping in the base file")
            if t not in node or node[t] is None:
                if isinstance(nxt, int):
                    raise SweepError(where, f"'{here}' does not exist in the base file")
                node[t] = {}
            node = node[t]
    last = tokens[-1]
    if isinstance(last, int):
        if not isinstance(node, list) or last >= len(node):
            raise SweepError(where, f"'{render(tokens)}' does not exist in the base file")
        return node, last, True
    if not isinstance(node, dict):
        raise SweepError(where, f"'{render(tokens[:-1])}' is not a mapping in the base file")
    return node, last, last in node


def assign(tree, tokens, value, where):
    parent, last, _ = locate(tree, tokens, where)
    parent[last] = value
