"""The quick modes of the benchmarks issue 28 added to or extended (run here so that they keep
working; their figures are the benchmarks', not asserted as times)."""

import json
import subprocess
import sys

import pytest

from .conftest import ROOT


@pytest.mark.slow
@pytest.mark.parametrize("script", ["bench_kc.py", "bench_design.py"])
def test_benchmark_quick_mode(tmp_path, script):
    out = tmp_path / "result.json"
    done = subprocess.run([sys.executable, str(ROOT / "benchmarks" / script), "--quick",
                           "--out", str(out)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    result = json.loads(out.read_text())
    assert result["quick"] is True
    if script == "bench_kc.py":
        assert result["max_spin_axis_difference_before_issue28"] == 0.0  # the same results
    else:
        assert result["optimize"]["exact"]["met"]
        assert result["sensitivity"][0]["coordinates"] == 33
