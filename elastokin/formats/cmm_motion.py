"""The CMM files of a motion plan (the config's ``motion`` section, docs/measurements.md
"Joints from motion"): per rig position one file with the marks of every marked body (parts,
ground, marked links, the wheel) in the CMM's frame, in any order; the ground's marks in the
config frame; for synthetic data the as-built truth. Units mm."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from elastokin.config.confined import data_file
from elastokin.config.loading import read_yaml
from elastokin.config.schema.motion import MotionSpec
from elastokin.config.schema.suspension import PartMeasurementSpec
from elastokin.config.suspension import Suspension
from elastokin.errors import MeasurementError
from elastokin.formats.cmm_parts import read_labelled_marks, read_part

#: the name of the wheel's marks (``motion.wheel_marks``) among the measured bodies
WHEEL = "wheel"


@dataclass
class MotionMeasurement:
    """Marks of every body at every position, as read (unordered, the CMM frame of each
    position, mm); the ground's marks in the config frame (its 4 marks in order)."""

    positions: list[str]
    files: list[str]
    marks: list[dict[str, np.ndarray]]  # per position: body -> (3 or 4, 3)
    ground_marks: np.ndarray  # (4, 3), config frame
    ground_file: str
    labels: list[dict[str, list[str]]] | None = None  # the marks' labels in the files


def mark_patterns(spec: MotionSpec) -> dict[str, str]:
    """Every measured body's label pattern: the ``marks`` and, with ``wheel_marks``, the
    wheel's."""
    return {**spec.marks, **({WHEEL: spec.wheel_marks} if spec.wheel_marks else {})}


def motion_paths(s: Suspension, folder: str | Path | None = None) -> dict[str, Path]:
    """The files of the config's motion plan: ``ground``, then each position's by name and
    (synthetic data) ``truth``, in ``motion.folder`` or in ``folder`` (typed on the command
    line); each confined to the config's folders
    (:func:`elastokin.config.confined.data_file`), none opened."""
    mo = s.motion
    if mo is None:
        return {}
    out = {"ground": data_file(s, "motion", mo.ground.file, "motion.ground.file", folder)}
    for name, p in mo.positions.items():
        out[name] = data_file(s, "motion", p.file, f"motion.positions.{name}.file", folder)
    if mo.truth is not None:
        out["truth"] = data_file(s, "motion", mo.truth, "motion.truth", folder)
    return out


def read_motion(s: Suspension) -> MotionMeasurement:
    """Read the ground's marks and every position's file of the config's motion plan
    (:func:`motion_paths`; errors name the file and the body: a file without a body's marks,
    fewer than 3 of them, more than 4)."""
    spec, paths = s.motion, motion_paths(s)
    g = read_part(s.ground, PartMeasurementSpec(file=spec.ground.file, marks=spec.ground.marks),
                  paths["ground"])
    patterns = mark_patterns(spec)
    files, marks, labels = [], [], []
    for name in spec.positions:
        source, found, named = read_labelled_marks(paths[name], patterns, "measured")
        files.append(source)
        marks.append(found)
        labels.append(named)
    return MotionMeasurement(list(spec.positions), files, marks, g.marks, g.source, labels)


def read_motion_truth(path: Path) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The synthetic truth of a motion plan: true joint locations and axes (unit) at the
    design position (mm, config frame)."""
    try:
        data = read_yaml(path, "truth file")[0]
        points = {k: np.asarray(v, float) for k, v in data["joints"].items()}
        axes = {k: np.asarray(v, float) for k, v in data.get("axes", {}).items()}
    except (OSError, yaml.YAMLError, KeyError, TypeError, ValueError, AttributeError) as exc:
        raise MeasurementError(f"{path}: unreadable truth file ({exc})") from None
    return points, axes
