"""The quick mode of the benchmark issue 28 added (run here so that it keeps working; its
figures are the benchmark's, not asserted as times). bench_kc.py's quick mode, which issue 28
extended, runs in tests/test_benchmarks.py with the other K&C benchmarks."""

import json
import subprocess
import sys

import pytest

from .conftest import ROOT


@pytest.mark.slow
@pytest.mark.parametrize("script", ["bench_design.py"])
def test_benchmark_quick_mode(tmp_path, script):
    out = tmp_path / "result.json"
    done = subprocess.run([sys.executable, str(ROOT / "benchmarks" / script), "--quick",
                           "--out", str(out)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    result = json.loads(out.read_text())
    assert result["quick"] is True
    assert result["optimize"]["exact"]["met"]
    assert result["sensitivity"][0]["coordinates"] == 33
