"""A config file with design variables moved, written as the user wrote it: the lines that
hold a moved value are edited in place (the value replaced, a comment with the old value
appended), every other line, comment and blank kept. What cannot be edited in place (a curve,
a key the file does not have yet) makes the whole mapping be written again instead, with the
changes listed in its header. Either way the written file is read back and checked to hold
the new values. Units as in the config (mm, N, N*mm, deg).
"""

from __future__ import annotations

import re
from collections.abc import Sequence

import yaml

from elastokin.config.design_variables import DesignVariable, design_suspension
from elastokin.config.frozen import plain_data
from elastokin.config.loading import parse_yaml
from elastokin.config.suspension import Suspension
from elastokin.errors import ElastokinError

TAG = "elastokin optimize"


def _fmt(v: float, decimals: int) -> str:
    text = f"{round(float(v), decimals):.{decimals}f}".rstrip("0")
    return text + "0" if text.endswith(".") else text


def _block(lines: list[str], path: Sequence[str]) -> int | None:
    """The index of the line holding the last key of ``path`` in block-style YAML (each key
    of the path on a line of its own, deeper keys indented further); None when absent."""
    start, indent = 0, -1
    for depth, key in enumerate(path):
        pattern = re.compile(rf"^(\s*){re.escape(key)}\s*:")
        found = None
        for i in range(start, len(lines)):
            line = lines[i]
            stripped = line.strip()
            if not stripped or stripped.startswith("#"):
                continue
            ind = len(line) - len(line.lstrip())
            if ind <= indent:
                break
            m = pattern.match(line)
            if m and (depth == 0 and ind == 0 or depth > 0):
                found = i
                indent = ind
                break
        if found is None:
            return None
        start = found + 1
    return start - 1


def _edit_point(lines: list[str], name: str, new, old, decimals: int) -> bool:
    i = _block(lines, ["hardpoints", name])
    if i is None:
        return False
    m = re.match(rf"^(\s*{re.escape(name)}\s*:\s*)\[[^\]]*\](.*)$", lines[i])
    if m is None:
        return False
    was = ", ".join(_fmt(v, 6) for v in old)
    rest = m.group(2).rstrip()
    comment = f"  # was [{was}] ({TAG})"
    lines[i] = f"{m.group(1)}[{', '.join(_fmt(v, decimals) for v in new)}]{rest}{comment}"
    return True


def _edit_scalar(lines: list[str], path: Sequence[str], new: float, old: float,
                 decimals: int) -> bool:
    """``path``'s value on its own line, or inside a one-line flow mapping of its parent."""
    key = path[-1]
    i = _block(lines, path)
    if i is not None:
        m = re.match(rf"^(\s*{re.escape(key)}\s*:\s*)([-+.\deE]+)(.*)$", lines[i])
    else:
        i = _block(lines, path[:-1])
        m = None if i is None else re.match(
            rf"^(.*[{{,]\s*{re.escape(key)}\s*:\s*)([-+.\deE]+)(.*)$", lines[i])
    if m is None:
        return False
    lines[i] = (f"{m.group(1)}{_fmt(new, decimals)}{m.group(3).rstrip()}"
                f"  # {key} was {_fmt(old, 6)} ({TAG})")
    return True


def edited_config(text: str, template: Suspension, variables: Sequence[DesignVariable],
                  values: Sequence[float], decimals: int = 6) -> str:
    """The config ``text`` (the template's file) with ``variables`` at ``values``, rounded to
    ``decimals`` (module docstring)."""
    base = plain_data(template.raw)
    lines = text.splitlines()
    ok = True
    for v, x in zip(variables, values):
        old = v.value(base)
        if v.kind == "hardpoint" and v.side == "both" and not (
                (base.get("axle") or {}).get("other_side") or {}).get("hardpoints", {}).get(
                v.item):
            point = list(base["hardpoints"][v.item])
            new = list(point)
            new[v.axis] = round(float(x), decimals)
            ok &= _edit_point(lines, v.item, new, point, decimals)
        elif v.kind == "spring_rate":
            ok &= _edit_scalar(lines, ["springs", v.item, "rate_N_per_mm"], x, old, decimals)
        elif v.kind == "rack_ratio" and base["axle"]["steering"].get("ratio_mm_per_rev"):
            ok &= _edit_scalar(lines, ["axle", "steering", "ratio_mm_per_rev"], x, old,
                               decimals)
        else:
            ok = False
    if ok:
        return "\n".join(lines) + "\n"
    return _rewritten(template, variables, values, decimals)


def _rewritten(template: Suspension, variables, values, decimals: int) -> str:
    """The whole mapping written again (its comments lost), the changes in the header."""
    base = plain_data(template.raw)
    raw = plain_data(design_suspension(template, variables,
                                       [round(float(x), decimals) for x in values]).raw)
    head = [f"# written by {TAG}: the config mapping with these design variables moved"]
    head += [f"#   {v.name}: {_fmt(v.value(base), 6)} -> {_fmt(x, decimals)} {v.unit}"
             for v, x in zip(variables, values)]
    return "\n".join(head) + "\n" + yaml.safe_dump(raw, sort_keys=False)


def check_written(text: str, source: str, template: Suspension, variables, values,
                  decimals: int) -> None:
    """Raise when the written config, read back, is not the template's mapping with the
    variables at their rounded values."""
    want = plain_data(design_suspension(template, variables,
                                        [round(float(x), decimals) for x in values]).raw)
    got = parse_yaml(text, source)
    # the rig may come from a rig file (--rig): not part of the design
    where = _first_difference({k: v for k, v in got.items() if k != "rig"},
                              {k: v for k, v in want.items() if k != "rig"},
                              0.5 * 10.0 ** -decimals)
    if where is not None:
        raise ElastokinError(f"{source}: the optimised config written does not hold the "
                             f"optimised design (key '{where}'); nothing was written")


def _first_difference(a, b, tol: float, path: str = "") -> str | None:
    if isinstance(a, dict) and isinstance(b, dict):
        for k in set(a) | set(b):
            if k not in a or k not in b:
                if a.get(k) is None and b.get(k) is None:
                    continue
                return f"{path}{k}"
            found = _first_difference(a[k], b[k], tol, f"{path}{k}.")
            if found is not None:
                return found
        return None
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return path.rstrip(".")
        for i, (x, y) in enumerate(zip(a, b)):
            found = _first_difference(x, y, tol, f"{path}[{i}].")
            if found is not None:
                return found
        return None
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        return None if abs(a - b) <= tol * max(1.0, abs(b)) else path.rstrip(".")
    return None if a == b else path.rstrip(".")
