"""The examples under examples/ run as scripts (a fresh process, the package from this
checkout) and give what they say."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from .conftest import ROOT

EXAMPLES = sorted((ROOT / "examples").glob("*.py"))


def run_example(path, tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    chart = tmp_path / f"{path.stem}.png"
    done = subprocess.run([sys.executable, str(path), str(chart)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout, chart


def test_there_are_examples():
    assert EXAMPLES


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_example_runs_and_draws_its_chart(path, tmp_path):
    from PIL import Image

    out, chart = run_example(path, tmp_path)
    assert Image.open(chart).size[0] >= 600


def test_tie_rod_height_example(tmp_path):
    """A resolved suspension's hardpoint is moved with with_hardpoints: raising the tie rod's
    inner joint 5 mm changes the bump steer a lot (the nominal steer amplitude is test_cli's
    regression, 0.519 deg)."""
    out, _ = run_example(ROOT / "examples" / "tie_rod_height.py", tmp_path)
    amplitude = {m[0]: float(m[1]) for m in re.findall(
        r"^(.+): steer amplitude ([0-9.]+) deg", out, re.MULTILINE)}
    assert amplitude["nominal"] == pytest.approx(0.5188, abs=0.005)
    assert amplitude["J3 5 mm higher"] > amplitude["nominal"] + 0.5
    assert "moved J3 [mm]: [ -73.7 -353.4  233.3]" in out
