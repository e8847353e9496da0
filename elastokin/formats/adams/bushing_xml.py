"""XML bushing property files (``<ConnectorBushingProperties>``, newer ADAMS/Car versions),
read into the same curves as a TeimOrbit ``.bus`` file.

Pure Python (the standard library's expat parser: no entity expansion beyond XML's own, no
network). The file's units come from its ``<Units>`` block (``<UnitSetting name="length"
current="mm"/>``...; ADAMS/Car's defaults when it has none); the ``xUnit``/``yUnit`` labels of
a curve are labels only, as in ADAMS/Car. Each ``<ConnectorDirectionComponent name="x">`` gives
one direction: a ``<ConnectorStiffness type="spline">`` with its ``<ConnectorSplineData>``
points (one ``deflection load`` pair a line), or ``type="linear"`` with the ``rate`` of its
``<ConnectorLinearData>``. Values are converted to mm, N, N*mm, deg. Format: ``docs/adams.md``.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat

from elastokin.errors import ConfigError
from elastokin.formats.adams.teimorbit import decode_text
from elastokin.formats.adams.teimorbit_units import QUANTITY_UNITS, UNIT_FACTORS, Units, unit_factor

__all__ = ["XML_DIRECTIONS", "XmlBushing", "is_xml", "read_bushing_xml"]

#: direction names of ``<ConnectorDirectionComponent name=...>`` (case-insensitive) and the
#: elastokin direction they are
XML_DIRECTIONS = {"x": "x", "y": "y", "z": "z", "rx": "rx", "ry": "ry", "rz": "rz",
                  "ax": "rx", "ay": "ry", "az": "rz", "tx": "rx", "ty": "ry", "tz": "rz"}


@dataclass
class _Node:
    tag: str
    attrs: dict[str, str]
    line: int
    children: list[_Node] = field(default_factory=list)
    text: list[tuple[int, str]] = field(default_factory=list)  # (line, chunk)

    def find_all(self, tag: str) -> list[_Node]:
        out = [c for c in self.children if c.tag == tag]
        for c in self.children:
            out += [n for n in c.find_all(tag) if n not in out]
        return out

    def attr(self, name: str, default: str | None = None) -> str | None:
        return {k.lower(): v for k, v in self.attrs.items()}.get(name.lower(), default)


def _parse(text: str, path: str) -> _Node:
    root = _Node("#document", {}, 0)
    stack = [root]
    p = expat.ParserCreate()

    def start(tag, attrs):
        node = _Node(tag.rsplit(":", 1)[-1], attrs, p.CurrentLineNumber)
        stack[-1].children.append(node)
        stack.append(node)

    def end(tag):
        stack.pop()

    def chars(data):
        stack[-1].text.append((p.CurrentLineNumber, data))

    p.StartElementHandler, p.EndElementHandler, p.CharacterDataHandler = start, end, chars
    try:
        p.Parse(text, True)
    except expat.ExpatError as exc:
        raise ConfigError(f"{path}, line {exc.lineno}: not well-formed XML "
                          f"({expat.ErrorString(exc.code)})") from None
    return root


def is_xml(path: str | Path) -> bool:
    """True when the file starts (after blanks) with ``<``: an XML property file."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(512)
    except OSError:
        return False
    return head.lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"<")


@dataclass
class XmlBushing:
    """The stiffness of each direction as read: ``curves`` direction -> (deflection, load,
    lines) converted, or ``rates`` direction -> (rate N/mm or N*mm/deg, line); ``damping``
    as (value, unit); ``units`` of the file."""

    path: str
    units: Units
    curves: dict[str, tuple[list[float], list[float], list[int]]] = field(default_factory=dict)
    rates: dict[str, tuple[float, int]] = field(default_factory=dict)
    damping: dict[str, tuple[float, str]] = field(default_factory=dict)
    lines: dict[str, int] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)


def _units(root: _Node, path: str) -> Units:
    given = {}
    for node in root.find_all("UnitSetting"):
        dim, name = (node.attr("name") or "").lower(), node.attr("current") or ""
        if dim not in UNIT_FACTORS:
            continue
        if unit_factor(dim, name) is None:
            raise ConfigError(f"{path}, line {node.line}, <UnitSetting name=\"{dim}\">: unknown "
                              f"{dim} unit {name!r} (known: {', '.join(UNIT_FACTORS[dim])})")
        given[dim] = name
    return dataclasses.replace(Units(), **given)


def _number(text: str, where: str) -> float:
    try:
        return float(text.replace("d", "e").replace("D", "e"))
    except ValueError:
        raise ConfigError(f"{where}: {text!r} is not a number") from None


def _spline(node: _Node, where: str, fu: float, ff: float) -> tuple[list, list, list]:
    u, f, lines = [], [], []
    for line0, chunk in node.text:
        for k, row in enumerate(chunk.split("\n")):
            vals = re.split(r"[\s,;]+", row.strip())
            if vals == [""]:
                continue
            at = f"{where}, line {line0 + k}"
            if len(vals) != 2:
                raise ConfigError(f"{at}: expected one 'deflection load' pair, got {row.strip()!r}")
            u.append(float(f"{_number(vals[0], at) * fu:.12g}"))
            f.append(float(f"{_number(vals[1], at) * ff:.12g}"))
            lines.append(line0 + k)
    return u, f, lines


def _direction(out: XmlBushing, comp: _Node, d: str, where: str) -> None:
    rot = d.startswith("r")
    fu, ff = out.units.factor("angle" if rot else "length"), out.units.factor(
        "torque" if rot else "force")
    stiff = comp.find_all("ConnectorStiffness")
    if not stiff:
        raise ConfigError(f"{where}: no <ConnectorStiffness>")
    s = stiff[0]
    kind = (s.attr("type") or "").lower()
    spline = s.find_all("ConnectorSplineData")
    linear = s.find_all("ConnectorLinearData")
    if kind == "linear" or (not kind and linear and not spline):
        if not linear or linear[0].attr("rate") is None:
            raise ConfigError(f"{where}, line {s.line}: type linear without <ConnectorLinearData "
                              "rate=...>")
        q = "rotational_stiffness" if rot else "stiffness"
        rate = _number(linear[0].attr("rate"), f"{where}, line {linear[0].line}")
        out.rates[d] = (float(f"{rate * out.units.factor(q):.12g}"), linear[0].line)
    elif spline:
        out.curves[d] = _spline(spline[0], where, fu, ff)
    else:
        raise ConfigError(f"{where}, line {s.line}: stiffness type {kind or '(none)'!r} "
                          "without <ConnectorSplineData>: expected type spline or linear")
    out.lines[d] = comp.line
    for damp in comp.find_all("ConnectorDamping")[:1]:
        lin = damp.find_all("ConnectorLinearData")
        if (damp.attr("type") or "linear").lower() == "linear" and lin and lin[0].attr("rate"):
            q = "rotational_damping" if rot else "damping"
            value = _number(lin[0].attr("rate"), f"{where}, line {lin[0].line}")
            key = {"x": "FX", "y": "FY", "z": "FZ", "rx": "TX", "ry": "TY", "rz": "TZ"}[d]
            out.damping[f"{key}_DAMPING"] = (float(f"{value * out.units.factor(q):.12g}"),
                                             QUANTITY_UNITS[q][1])
        else:
            out.warnings.append(f"{where}, line {damp.line}: damping not linear: not read "
                                "(elastokin is quasi-static)")


def read_bushing_xml(path: str | Path) -> XmlBushing:
    """Read an XML bushing property file: per direction its curve or linear rate (converted to
    mm, N, N*mm, deg); ConfigError naming file, element and line for what is broken."""
    p = Path(path)
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise ConfigError(f"{p}: cannot read file ({exc.strerror})") from None
    text, warnings = decode_text(data, str(p), "an XML bushing property file")
    root = _parse(text, str(p))
    props = root.find_all("ConnectorBushingProperties")
    if not props:
        raise ConfigError(f"{p}: no <ConnectorBushingProperties> element: not an XML bushing "
                          "property file")
    out = XmlBushing(str(p), _units(root, str(p)), warnings=warnings)
    for comp in props[0].find_all("ConnectorDirectionComponent"):
        name = (comp.attr("name") or "").lower()
        where = f"{p}, <ConnectorDirectionComponent name=\"{comp.attr('name')}\">"
        if name not in XML_DIRECTIONS:
            raise ConfigError(f"{where}, line {comp.line}: unknown direction (expected "
                              f"{', '.join(XML_DIRECTIONS)})")
        d = XML_DIRECTIONS[name]
        if d in out.lines:
            raise ConfigError(f"{where}, line {comp.line}: direction {d} given again (first at "
                              f"line {out.lines[d]})")
        _direction(out, comp, d, where)
    missing = [d for d in ("x", "y", "z", "rx", "ry", "rz") if d not in out.lines]
    if missing:
        raise ConfigError(f"{p}, line {props[0].line}, <ConnectorBushingProperties>: no "
                          f"<ConnectorDirectionComponent> for {', '.join(missing)}")
    return out
