"""The CMM measurements of a suspension's parts, read from the files its config's
``measurements`` section names (docs/measurements.md): each part measured alone (4 marks,
joint centres, axis and radial lines; the part's own frame, mm), the assembled marks (CMM
frame, unordered) and, for synthetic data, the as-built truth."""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from elastokin.config.loading import read_yaml
from elastokin.errors import MeasurementError
from elastokin.formats.cmm import read_points


@dataclass
class PartMeasurement:
    """One part measured alone (mm, the part's own frame)."""

    part: str
    source: str
    marks: np.ndarray  # (4, 3)
    points: dict[str, np.ndarray]  # hardpoint -> centre
    axes: dict[str, np.ndarray]  # hardpoint -> unit axis (``<label>.Z`` line)
    radials: dict[str, np.ndarray]  # hardpoint -> unit radial (``<label>.X`` line)


def _unit(seg: np.ndarray) -> np.ndarray:
    v = seg[1] - seg[0]
    return v / np.linalg.norm(v)


def read_part(part: str, spec, folder: Path) -> PartMeasurement:
    """Read a part's file; labels -> marks and hardpoints (see ``docs/measurements.md``)."""
    data = read_points(folder / spec.file)
    missing = [m for m in spec.marks if m not in data.points]
    if missing:
        raise MeasurementError(
            f"{data.source}: part '{part}': mark(s) {', '.join(missing)} not found (labels in "
            f"the file: {', '.join(data.order) or 'none'}); a part needs its 4 marks "
            f"({', '.join(spec.marks)})")
    to_hardpoint = {label: hp for hp, label in spec.labels.items()}
    points, axes, radials = {}, {}, {}
    for label, xyz in data.points.items():
        if label not in spec.marks:
            points[to_hardpoint.get(label, label)] = xyz
    for label, seg in data.lines.items():
        base, _, kind = label.rpartition(".")
        target = {"Z": axes, "X": radials}.get(kind.upper())
        if base and target is not None:
            target[to_hardpoint.get(base, base)] = _unit(seg)
    marks = np.array([data.points[m] for m in spec.marks])
    return PartMeasurement(part, data.source, marks, points, axes, radials)


def read_assembly(spec, folder: Path, parts: list[str]) -> tuple[str, dict[str, np.ndarray]]:
    """The assembled marks of each part (unordered), selected by the label patterns."""
    return read_marks(folder / spec.file, {p: spec.marks[p] for p in parts})


def read_marks(path: Path, patterns: dict[str, str], what: str = "assembled"
               ) -> tuple[str, dict[str, np.ndarray]]:
    """The marks of each body (unordered, the file's frame, mm) in a file of many bodies'
    marks, selected by each body's label pattern (``fnmatch``); 3 or 4 per body. Returns the
    file's name and the marks."""
    source, marks, _ = read_labelled_marks(path, patterns, what)
    return source, marks


def read_labelled_marks(path: Path, patterns: dict[str, str], what: str = "assembled"
                        ) -> tuple[str, dict[str, np.ndarray], dict[str, list[str]]]:
    """:func:`read_marks`, with each body's marks' labels in the same order."""
    data = read_points(path)
    out: dict[str, list] = {p: [] for p in patterns}
    labels: dict[str, list[str]] = {p: [] for p in patterns}
    for label in data.order:
        owners = [p for p in patterns if fnmatch.fnmatchcase(label, patterns[p])]
        if len(owners) > 1:
            raise MeasurementError(f"{data.source}: mark '{label}' matches the patterns of "
                                   f"parts {', '.join(owners)}")
        if owners:
            out[owners[0]].append(data.points[label])
            labels[owners[0]].append(label)
    for p, pts in out.items():
        if len(pts) < 3:
            raise MeasurementError(
                f"{data.source}: part '{p}': {len(pts)} {what} mark(s) match the label "
                f"pattern '{patterns[p]}'; at least 3 usable marks are needed for its pose")
        if len(pts) > 4:
            raise MeasurementError(f"{data.source}: part '{p}': {len(pts)} {what} marks "
                                   f"match '{patterns[p]}'; a part has 4 marks")
    return data.source, {p: np.array(v) for p, v in out.items()}, labels


def read_truth(path: Path) -> dict[str, np.ndarray]:
    """The synthetic truth file's true joint locations (mm, config frame, loaded)."""
    try:
        data = read_yaml(path, "truth file")[0]  # strict YAML: errors name file and line
        return {k: np.asarray(v, float) for k, v in data["joints"].items()}
    except (OSError, yaml.YAMLError, KeyError, TypeError, ValueError) as exc:
        raise MeasurementError(f"{path}: unreadable truth file ({exc})") from None
