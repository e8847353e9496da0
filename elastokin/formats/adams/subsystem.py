"""An ADAMS/Car subsystem file (``.sub``) out: ``[MDI_HEADER]``, ``[SUBSYSTEM_HEADER]``
(template and roles), ``[UNITS]``, ``[HARDPOINT]`` with the template's hardpoint names (through
the mapping file), and the ``[BUSHING_ASSEMBLY]`` and ``[NSPRING_ASSEMBLY]`` blocks in the form
ADAMS/Car writes them (``DEFINITION``, ``USAGE``, ``SYMMETRY``, ``PROPERTY_FILE`` as an
``mdids://`` database path).

Pure Python/numpy. Hardpoints are in ADAMS/Car's global frame (X rearward, Y right, Z up): a
``left/right`` row stores the left point; two elastokin points mapped onto the two sides of one
ADAMS hardpoint that are not each other's mirror are written as an asymmetric pair (a ``left``
and a ``right`` row); a point mapped onto a ``single`` hardpoint (``hps_`` prefix) is a
``single`` row. On an axle the other side's copy of each hardpoint is written with it: a
``left/right`` row when it is the mirror, else the asymmetric pair. A ``[PARAMETER]`` block
(``{parameter_name symmetry type value}`` with a description row under each, as ADAMS/Car
writes it) carries the anti-roll bar's and the steering's scalar data. Conventions:
``docs/adams.md``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError
from elastokin.formats.adams.mapping import AdamsMapping, config_to_adams
from elastokin.formats.adams.property_files import UNITS_LINES, key_line, number, provenance, rule

__all__ = [
    "MAJOR_ROLES",
    "MINOR_ROLES",
    "AssemblyRow",
    "HardpointRow",
    "ParameterRow",
    "SubsystemSpec",
    "adams_name",
    "hardpoint_rows",
    "file_name",
    "parameter_lines",
    "adams_role",
    "safe_name",
    "subsystem_text",
    "template_path",
]

_PREFIX = {"hpl_": "left", "hpr_": "right", "hps_": "single"}

#: ADAMS/Car's major roles, as real Adams/Car assemblies name them (``../shared/adams_real``:
#: the MDI demo vehicle's and FSAE assemblies' ``[SUBSYSTEM]`` blocks) and ``environment``;
#: elastokin writes the first three
MAJOR_ROLES = ("suspension", "antirollbar", "steering", "wheel", "body", "powertrain",
               "brake_system", "environment")
#: ADAMS/Car's minor roles: where on the vehicle (``any``: not tied to an axle)
MINOR_ROLES = ("front", "rear", "trailer", "any")
#: a file or database name elastokin writes: letters, digits, ``_ . -``
_FILE_NAME = re.compile(r"[A-Za-z0-9_.-]+")
#: a template name (ADAMS/Car's are identifiers, e.g. ``_double_wishbone``)
_IDENTIFIER = r"[A-Za-z_][A-Za-z0-9_]*"
_TEMPLATE = re.compile(rf"(?:mdids://([A-Za-z0-9_.-]+)/|<([A-Za-z0-9_.-]+)>/)templates\.tbl/"
                       rf"({_IDENTIFIER})\.tpl")


def safe_name(name: str) -> str:
    """A name usable as an ADAMS file name or USAGE: letters, digits, ``_ . -``."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_") or "elastokin"


def file_name(name: str, where: str) -> str:
    """``name`` as given when it is a file name elastokin writes (letters, digits, ``_ . -``);
    otherwise an error naming ``where`` (the option or key that gives it)."""
    if not _FILE_NAME.fullmatch(name):
        raise ConfigError(f"{where}: {name!r} is not a name ADAMS/Car files can carry: use "
                          f"letters, digits, '_', '.' and '-' (e.g. {safe_name(name)!r})")
    return name


def template_path(template: str, where: str) -> str:
    """The ``TEMPLATE_NAME`` of a subsystem: a bare template name (``_double_wishbone``,
    ``.tpl`` or not: the one in ``acar_shared``) or ``mdids://<database>/templates.tbl/
    <name>.tpl`` (or ``<database>/templates.tbl/...``); the name an identifier. Otherwise an
    error naming ``where``."""
    bare = template.removesuffix(".tpl")
    if re.fullmatch(_IDENTIFIER, bare):
        return f"mdids://acar_shared/templates.tbl/{bare}.tpl"
    if not _TEMPLATE.fullmatch(template):
        raise ConfigError(f"{where}: template {template!r}: expected a template name (an "
                          "identifier: letters, digits and '_', not starting with a digit, e.g. "
                          "_double_wishbone) or mdids://<database>/templates.tbl/<name>.tpl")
    return template


def adams_role(value: str, allowed: tuple[str, ...], what: str, where: str) -> str:
    """A major or minor role (case-insensitive, written in lower case) that is one of
    ``allowed``; otherwise an error naming ``where``, ``what`` it is for and ADAMS/Car's role
    names."""
    v = value.strip().lower()
    if v in allowed:
        return v
    names = MAJOR_ROLES if allowed[0] in MAJOR_ROLES else MINOR_ROLES
    known = f"ADAMS/Car's: {', '.join(names)}"
    expected = f"'{allowed[0]}'" if len(allowed) == 1 else ", ".join(allowed)
    raise ConfigError(f"{where}: {value!r} is not {what} (expected {expected}; {known})")


@dataclass(frozen=True)
class SubsystemSpec:
    """What the ``[SUBSYSTEM_HEADER]`` says and where the files go: subsystem file ``name``
    (without ``.sub``), ``template`` (an ``mdids://`` path), ``major_role``, ``minor_role``,
    ``database`` (the alias of the ``mdids://`` paths)."""

    name: str
    template: str
    major_role: str
    minor_role: str
    database: str

    def path(self, table: str, file: str) -> str:
        return f"mdids://{self.database}/{table}/{file}"


@dataclass(frozen=True)
class HardpointRow:
    """A ``[HARDPOINT]`` row: ADAMS name, symmetry, point (ADAMS frame, mm) and the elastokin
    hardpoints written in it."""

    name: str
    symmetry: str
    xyz: tuple[float, float, float]
    sources: tuple[str, ...]


@dataclass(frozen=True)
class AssemblyRow:
    """One assembly block: USAGE, PROPERTY_FILE and its other keys, comment lines, and its
    SYMMETRY (``left/right``: the same values on both sides; ``left``, ``right``: one side of
    a pair whose sides differ; ``single``)."""

    usage: str
    property_file: str
    values: tuple[tuple[str, float | str], ...]
    comments: tuple[str, ...] = ()
    symmetry: str = "left/right"


@dataclass(frozen=True)
class ParameterRow:
    """A ``[PARAMETER]`` row: name, symmetry, type (``real`` or ``integer``), value (in the
    unit its description states) and the description row written under it."""

    name: str
    symmetry: str
    type: str
    value: float
    description: str


def adams_name(mapping: AdamsMapping | None, name: str, default_side: str
               ) -> tuple[str, str]:
    """The ADAMS hardpoint an elastokin hardpoint is written as, and its side (``left``,
    ``right`` or ``single``): the mapping's name (an ``hpl_``/``hpr_``/``hps_`` prefix gives the
    side), its explicit side, else the mapping's or the config's side."""
    adams, side = mapping.hardpoints.get(name, (name, None)) if mapping else (name, None)
    for pre, pside in _PREFIX.items():
        if adams.lower().startswith(pre) and len(adams) > len(pre):
            if side is not None and pside != "single" and side != pside:
                raise ConfigError(f"{mapping.path}: key 'hardpoints.{name}': '{adams}' names "
                                  f"the {pside} point but side is {side}")
            adams, side = adams[len(pre):], pside
            break
    return adams, side or (mapping.side if mapping and mapping.side else default_side)


def hardpoint_rows(s: Suspension, mapping: AdamsMapping | None, names: tuple[str, ...],
                   single: frozenset[str] = frozenset()
                   ) -> tuple[list[HardpointRow], dict[str, tuple[str, str]]]:
    """The ``[HARDPOINT]`` rows of a suspension's hardpoints ``names`` (the corner's names on
    an axle: their other-side copies are written with them) in the ADAMS frame and, per
    elastokin hardpoint, the (ADAMS name, side) it was written as: ``single`` rows for the
    points on the centre plane and for those named in ``single`` (on an axle, the points only
    items kept once use: a Panhard rod's ends), unless the mapping gives their side. Two
    points on one ADAMS hardpoint and side must be the same point (ConfigError otherwise)."""
    per: dict[str, dict[str, tuple[np.ndarray, list[str]]]] = {}
    written = {}
    for name in names:
        adams, side = adams_name(mapping, name, s.side)
        entries = [(name, side)]
        if s.axle is not None:
            twin = name + s.axle.suffix
            if (name in single or _on_centre_plane(s, name, twin)) and \
                    not _side_given(mapping, name):
                side = "single"  # a point of a part declared once (the rack, the bar centre)
            other = {"left": "right", "right": "left"}.get(side, side)
            # a point only items kept once use has no other-side copy in the axle
            entries = [(name, side)] + ([] if name in single and side == "single"
                                        else [(twin, other)])
        written[name] = (adams, side)
        for key, pside in entries:
            _add_point(per.setdefault(adams, {}), adams, pside, key,
                       config_to_adams(s.hardpoints[key], s.frame),
                       mapping.path if mapping else s.source)
    rows = []
    mirror = np.array([1.0, -1.0, 1.0])
    for adams, sides in per.items():
        if "single" in sides and len(sides) > 1:
            raise ConfigError(f"{mapping.path if mapping else s.source}: ADAMS hardpoint "
                              f"'{adams}' is written both as a single point and as a side")
        if "single" in sides:
            q, names = sides["single"]
            rows.append(HardpointRow(adams, "single", tuple(q), tuple(names)))
            continue
        left = sides.get("left")
        right = sides.get("right")
        if left and right and np.max(np.abs(left[0] - mirror * right[0])) > 1e-9:
            rows += [HardpointRow(adams, "left", tuple(left[0]), tuple(left[1])),
                     HardpointRow(adams, "right", tuple(right[0]), tuple(right[1]))]
            continue
        q = left[0] if left else mirror * right[0]
        names = (left[1] if left else []) + (right[1] if right else [])
        rows.append(HardpointRow(adams, "left/right", tuple(q), tuple(names)))
    return rows, written


def _on_centre_plane(s: Suspension, name: str, twin: str) -> bool:
    """A hardpoint on the vehicle centre plane whose other-side copy is itself."""
    p, q = s.hardpoints[name], s.hardpoints[twin]
    return bool(p[1] == 0.0 and np.all(p == q))


def _side_given(mapping: AdamsMapping | None, name: str) -> bool:
    """The mapping gives the ADAMS side of hardpoint ``name`` (a prefix or ``side``)."""
    if mapping is None or name not in mapping.hardpoints:
        return False
    adams, side = mapping.hardpoints[name]
    return side is not None or any(adams.lower().startswith(p) for p in _PREFIX)


def _add_point(sides: dict, adams: str, side: str, name: str, q: np.ndarray,
               source: str) -> None:
    """One elastokin point written as ``side`` of ADAMS hardpoint ``adams``."""
    if side in sides:
        old, names = sides[side]
        if np.max(np.abs(old - q)) > 1e-9:
            raise ConfigError(f"{source}: hardpoints {names[0]} and {name} are both written as "
                              f"the {side} point of ADAMS hardpoint '{adams}' but differ")
        names.append(name)
    else:
        sides[side] = (q, [name])


def _assembly(block: str, definition: str, row: AssemblyRow) -> list[str]:
    keys = [("DEFINITION", definition), ("USAGE", row.usage), ("SYMMETRY", row.symmetry),
            ("PROPERTY_FILE", row.property_file), *row.values]
    width = max(len(k) for k, _ in keys)
    return [rule(block), f"[{block}]", *row.comments, *(key_line(k, v, width) for k, v in keys)]


def parameter_lines(rows: list[ParameterRow]) -> list[str]:
    """The ``[PARAMETER]`` block, in the layout of ADAMS/Car's (a description row under each
    parameter)."""
    if not rows:
        return []
    lines = [rule("PARAMETER"), "[PARAMETER]",
             "{parameter_name                  symmetry       type       value}"]
    for r in rows:
        lines += [f" '{r.name.ljust(28)}'  '{r.symmetry.ljust(10)}'   "
                  f"{repr(r.type).ljust(9)}  {number(r.value)}",
                  "  '" + r.description.replace("'", "`") + "'"]
    return lines


def subsystem_text(s: Suspension, spec: SubsystemSpec, rows: list[HardpointRow],
                   bushings: list[AssemblyRow], springs: list[AssemblyRow],
                   timestamp: str, parameters: list[ParameterRow] | None = None,
                   dampers: list[AssemblyRow] | None = None) -> str:
    """The subsystem file: headers, units (mm, newton, deg, kg, sec), hardpoints, bushing,
    spring and damper assemblies (each with its SYMMETRY), parameters."""
    lines = [provenance(s),
             "$ Hardpoints in the ADAMS/Car global frame (X rearward, Y right, Z up), mm;",
             "$ 'left/right' rows store the left point (Y < 0). Bushing preloads: loads at the",
             "$ design position, bushing frame, on the I part; orientations are the template's.",
             *(beam_lines(s) if spec.major_role == "suspension" else []),
             rule("MDI_HEADER"), "[MDI_HEADER]", key_line("FILE_TYPE", "sub", 12),
             key_line("FILE_VERSION", 7.0, 12), key_line("FILE_FORMAT", "ASCII", 12),
             rule("SUBSYSTEM_HEADER"), "[SUBSYSTEM_HEADER]",
             key_line("TEMPLATE_NAME", spec.template, 13),
             key_line("MAJOR_ROLE", spec.major_role, 13),
             key_line("MINOR_ROLE", spec.minor_role, 13),
             key_line("TIMESTAMP", timestamp, 13),
             rule("UNITS"), *UNITS_LINES]
    if rows:
        lines += [rule("HARDPOINT"), "[HARDPOINT]",
                  "{hardpoint_name                  symmetry         x_value    y_value    "
                  "z_value}"]
    width = max([len(r.name) for r in rows] + [28])
    for r in rows:
        lines.append(f" '{r.name.ljust(width)}'  '{r.symmetry.ljust(10)}'"
                     + "".join(" " + number(v).rjust(10) for v in r.xyz))
    for b in bushings:
        lines += _assembly("BUSHING_ASSEMBLY", ".ACAR.forces.ac_bushing", b)
    for sp in springs:
        lines += _assembly("NSPRING_ASSEMBLY", ".ACAR.forces.ac_spring", sp)
    for d in dampers or []:
        lines += _assembly("DAMPER_ASSEMBLY", ".ACAR.forces.ac_damper", d)
    lines += parameter_lines(parameters or [])
    return "\n".join(lines) + "\n"


def beam_lines(s: Suspension) -> list[str]:
    """Comment lines giving each flexible beam part, which the file does not carry (ADAMS/Car
    takes a flexible part as a flexible body or its template's own beams): its nodes (the
    hardpoints above) and section, to rebuild it."""
    out = []
    for b in s.beams:
        sec = b.section
        out += [f"$ NOT EXPORTED: elastokin flexible beam part '{b.part}' (beam elements), nodes "
                f"{', '.join(b.node_names)} (hardpoints above), {b.elements_per_segment} "
                "elements per segment;",
                f"$   section: EA {sec.EA_N:.6g} N, EI_y {sec.EI_y_Nmm2:.6g} N*mm^2, EI_z "
                f"{sec.EI_z_Nmm2:.6g} N*mm^2, GJ {sec.GJ_Nmm2:.6g} N*mm^2, GA_y {sec.GA_y_N:.6g} "
                f"N, GA_z {sec.GA_z_N:.6g} N;",
                "$   shear centre from the node line (config frame, mm, per segment): "
                + "; ".join(" ".join(number(v) for v in e) for e in b.shear_centre_mm)]
    return out
