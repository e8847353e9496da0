"""Every benchmark script uses only elastokin's public names: the API (``import elastokin as
ek``: ``elastokin.__all__``) and the command line (``elastokin.cli``). A benchmark that reached
into elastokin's modules broke unnoticed (bench_doe.py's profile: KeyError 'knuckle_right').
Every script has a quick mode (benchmarks/bench_common.py) that one test runs, exactly one:
the K&C benchmarks' here, the others' beside the feature they measure (QUICK_ELSEWHERE), so a
benchmark that no longer runs fails CI. Quick runs write into a temporary folder, never into
benchmarks/results."""

import ast
import json
import runpy
from pathlib import Path

import pytest

import elastokin

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
#: every benchmark script (bench_common.py: what they share, no benchmark of its own)
ALL_SCRIPTS = sorted(p for p in BENCHMARKS.glob("*.py") if p.name != "bench_common.py")
#: the K&C benchmarks (README "Benchmarks"), their quick mode run here
SCRIPTS = [BENCHMARKS / name for name in ("bench_axle.py", "bench_doe.py", "bench_kc.py",
                                          "steer_amplitude.py")]
#: the test file that runs each other script's quick mode (with checks of its own figures)
QUICK_ELSEWHERE = {"beam_refinement.py": "test_twist_beam.py",
                   "bench_design.py": "test_benchmarks_design.py",
                   "bench_loads.py": "test_loads.py", "bench_view.py": "test_view.py",
                   "motion_positions.py": "test_motion_case.py"}
RESULTS = BENCHMARKS / "results"


def elastokin_uses(path: Path) -> list[str]:
    """Every use of elastokin in a script that is not a public name: an import of one of its
    modules (other than the command line), or an attribute of ``ek`` outside its API."""
    tree = ast.parse(path.read_text())
    bad = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("elastokin") and alias.name != "elastokin":
                    bad.append(f"import {alias.name}")
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("elastokin"):
            if not node.module.startswith("elastokin.cli"):
                bad.append(f"from {node.module} import ...")
            bad += [f"{node.module}.{a.name}" for a in node.names if a.name.startswith("_")]
        elif (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
              and node.value.id == "ek"
              and node.attr not in {*elastokin.__all__, "__version__"}):
            bad.append(f"ek.{node.attr}")
    return bad


@pytest.mark.parametrize("path", [*ALL_SCRIPTS, BENCHMARKS / "bench_common.py"],
                         ids=lambda p: p.stem)
def test_benchmarks_use_public_names_only(path):
    assert elastokin_uses(path) == []


def test_every_quick_mode_is_run_by_one_test():
    """Each script's quick mode: here or in the one test file QUICK_ELSEWHERE names, which
    runs it with ``--quick``; no other test file names the script (a second run)."""
    names = {p.name for p in ALL_SCRIPTS}
    assert {p.name for p in SCRIPTS} | set(QUICK_ELSEWHERE) == names
    assert not {p.name for p in SCRIPTS} & set(QUICK_ELSEWHERE)
    tests = {p.name: p.read_text() for p in Path(__file__).parent.glob("test_*.py")
             if p.name != Path(__file__).name}
    for name in sorted(names):
        naming = [f for f, text in tests.items() if name in text]
        assert naming == ([QUICK_ELSEWHERE[name]] if name in QUICK_ELSEWHERE else []), name
        if name in QUICK_ELSEWHERE:
            assert "--quick" in tests[QUICK_ELSEWHERE[name]], name


@pytest.mark.parametrize("path", ALL_SCRIPTS, ids=lambda p: p.stem)
def test_a_quick_run_refuses_the_committed_results(path):
    main = runpy.run_path(str(path), run_name="benchmark")["main"]
    with pytest.raises(SystemExit, match="no committed result"):
        main(["--quick", "--out", str(RESULTS / f"{path.stem}.json")])


def test_the_check_sees_a_private_use(tmp_path):
    """The check can fail: the old bench_doe's imports and a name outside the API."""
    script = tmp_path / "b.py"
    script.write_text("import elastokin as ek\nfrom elastokin.studies import doe\n"
                      "from elastokin.cli.kc import _x\nek.run_kc(1)\nek._context(2)\n")
    assert elastokin_uses(script) == ["from elastokin.studies import ...",
                                      "elastokin.cli.kc._x", "ek._context"]


def committed() -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in RESULTS.glob("*.json")}


@pytest.mark.slow  # the four quick modes: ~10 s of CPU together (dask, subprocesses)
@pytest.mark.parametrize("path", SCRIPTS, ids=lambda p: p.stem)
def test_quick_mode_runs_and_leaves_the_committed_results(path, tmp_path):
    before = committed()
    main = runpy.run_path(str(path), run_name="benchmark")["main"]
    out = tmp_path / f"{path.stem}.json"
    assert main(["--quick", "--out", str(out)]) in (None, 0)
    doc = json.loads(out.read_text())
    assert doc["quick"] is True and doc["elastokin_version"] == elastokin.__version__
    if path.stem == "bench_kc":  # issue 28's sweep gives the results it gave before
        assert doc["max_spin_axis_difference_before_issue28"] == 0.0
    assert committed() == before
