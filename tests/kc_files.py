"""Helpers of the K&C test-file tests: a rig-like sweep, a file written from text, and the
reader's one-line error."""

from __future__ import annotations

import numpy as np
import pytest

from elastokin.errors import MeasurementError
from elastokin.formats.kc_test import read_kc_test


def sweep(peak: float, n: int = 20) -> np.ndarray:
    """0 -> +peak -> -peak -> 0, as a rig records a force sweep (3 branches)."""
    return np.r_[np.linspace(0, peak, n + 1), np.linspace(peak, -peak, 2 * n + 1)[1:],
                 np.linspace(-peak, 0, n + 1)[1:]]


def put(tmp_path, name: str, text: str):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def fails(path, *fragments):
    """read_kc_test raises MeasurementError whose message names the file and every fragment,
    on one line."""
    with pytest.raises(MeasurementError) as err:
        read_kc_test(path)
    msg = str(err.value)
    assert str(path) in msg
    for f in fragments:
        assert f in msg, (f, msg)
    assert "\n" not in msg
    return msg
