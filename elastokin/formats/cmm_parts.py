"""The CMM measurements of a suspension's parts, read from the files its config's
``measurements`` section names (docs/measurements.md): each part measured alone (4 marks,
joint centres, axis and radial lines; the part's own frame, mm), the assembled marks (CMM
frame, unordered) and, for synthetic data, the as-built truth."""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from elastokin.config.confined import data_file
from elastokin.config.loading import read_yaml
from elastokin.config.suspension import Suspension
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
    labels: dict[str, str] = field(default_factory=dict)  # hardpoint -> its label in the file

    def label(self, hardpoint: str, suffix: str = "") -> str:
        """The label ``hardpoint`` has in the file (+ ``suffix``: ``.Z``, ``.X`` for its
        lines), quoted, and where the label comes from (messages)."""
        label = f"'{self.labels.get(hardpoint, hardpoint)}{suffix}'"
        if hardpoint in self.labels:
            label += (f" (measurements.parts.{self.part}.labels gives "
                      f"'{self.labels[hardpoint]}' for hardpoint '{hardpoint}')")
        return label


def measurement_paths(s: Suspension, folder: str | Path | None = None) -> dict[str, Path]:
    """The CMM files of the config's ``measurements`` section: per part its file, then
    ``assembly`` and (synthetic data) ``truth``, in its folder or in ``folder`` (typed on
    the command line); each confined to the config's folders
    (:func:`elastokin.config.confined.data_file`), none opened."""
    m = s.measurements
    if m is None:
        return {}
    out = {p: data_file(s, "measurements", spec.file, f"measurements.parts.{p}.file", folder)
           for p, spec in m.parts.items()}
    out["assembly"] = data_file(s, "measurements", m.assembly.file,
                                "measurements.assembly.file", folder)
    if m.truth is not None:
        out["truth"] = data_file(s, "measurements", m.truth, "measurements.truth", folder)
    return out


def _unit(seg: np.ndarray) -> np.ndarray:
    v = seg[1] - seg[0]
    return v / np.linalg.norm(v)


def read_part(part: str, spec, path: Path) -> PartMeasurement:
    """Read a part's file; labels -> marks and hardpoints (see ``docs/measurements.md``)."""
    data = read_points(path)
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
    return PartMeasurement(part, data.source, marks, points, axes, radials, dict(spec.labels))


def read_assembly(spec, path: Path, parts: list[str]) -> tuple[str, dict[str, np.ndarray]]:
    """The assembled marks of each part (unordered), selected by the label patterns."""
    return read_marks(path, {p: spec.marks[p] for p in parts})


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


def read_measurements(s: Suspension) -> tuple[dict[str, PartMeasurement], str,
                                              dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Every file of the config's ``measurements`` section (:func:`measurement_paths`: none
    outside the config's folders is opened): each part measured alone, the assembly file's
    name and its marks per part, and the synthetic truth's joints (empty without one)."""
    m = s.measurements
    files = measurement_paths(s)
    parts = {p: read_part(p, spec, files[p]) for p, spec in m.parts.items()}
    assembly_file, assembled = read_assembly(m.assembly, files["assembly"], list(m.parts))
    truth = read_truth(files["truth"]) if "truth" in files else {}
    return parts, assembly_file, assembled, truth
