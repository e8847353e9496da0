"""The CMM files of a motion plan (the config's ``motion`` section, docs/measurements.md
"Joints from motion"): per rig position one file with the marks of every marked body (parts,
ground, marked links, the wheel) in the CMM's frame, in any order; the ground's marks in the
config frame; for synthetic data the as-built truth. Units mm."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from elastokin.config.loading import read_yaml
from elastokin.config.schema import PartMeasurementSpec
from elastokin.config.schema_motion import MotionSpec
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


def read_motion(spec: MotionSpec, folder: Path, ground: str) -> MotionMeasurement:
    """Read the ground's marks and every position's file (errors name the file and the
    body: a file without a body's marks, fewer than 3 of them, more than 4)."""
    g = read_part(ground, PartMeasurementSpec(file=spec.ground.file, marks=spec.ground.marks),
                  folder)
    patterns = mark_patterns(spec)
    files, marks, labels = [], [], []
    for p in spec.positions.values():
        source, found, named = read_labelled_marks(folder / p.file, patterns, "measured")
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
