"""The cache of a K&C run's expensive results (elastokin.studies.cache): reused only when
every input is the same, a corrupt entry ignored with a warning, --refit recomputes."""

import json
import shutil

import pytest
from click.testing import CliRunner

from elastokin.cli import main
from elastokin.studies.cache import CacheWarning, ResultCache, content_key


def test_a_changed_input_file_changes_the_key(tmp_path):
    data = tmp_path / "lateral_force.csv"
    data.write_text("lateral_force [N],toe [deg]\n0,0\n1,1\n")
    before = content_key("fit", "sha", data)
    assert content_key("fit", "sha", data) == before  # deterministic
    data.write_text("lateral_force [N],toe [deg]\n0,0\n1,1.0001\n")
    assert content_key("fit", "sha", data) != before
    assert content_key("fit", "other sha", data) != content_key("fit", "sha", data)


def test_entries_round_trip_and_are_never_trusted_under_another_key(tmp_path):
    first = ResultCache(None, tmp_path / "a")
    first.put("fit", "key-1", {"J1": 1.35})
    again = ResultCache(tmp_path / "a", tmp_path / "b")
    assert again.get("fit", "key-2") is None and again.reused == []
    assert again.get("fit", "key-1") == {"J1": 1.35} and again.reused == ["fit"]
    assert ResultCache(tmp_path / "a", None, enabled=False).get("fit", "key-1") is None


def test_a_corrupt_entry_is_ignored_with_a_warning(tmp_path):
    (tmp_path / "fit.pkl").write_bytes(b"\x80\x04 not a pickle at all")
    cache = ResultCache(tmp_path, None)
    with pytest.warns(CacheWarning, match="cache entry ignored"):
        assert cache.get("fit", "key") is None


@pytest.mark.slow
def test_second_run_reuses_identification_and_fit(case_kc, case_path, tmp_path):
    """A second `elastokin kc` into the same folder with nothing changed reuses the
    identification, the fit and every model's load cases and gives the same kc.csv; a corrupt
    entry is ignored (one warning) and recomputed."""
    out = tmp_path / "res"
    shutil.copytree(case_kc, out)
    result = CliRunner().invoke(main, ["kc", "--config", str(case_path), "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "Reused from the previous results" in result.output
    summary = json.loads((out / "summary.json").read_text())
    assert summary["reused_from_cache"] == ["geometry", "models", "stiffness_fit"]
    assert (out / "kc.csv").read_bytes() == (case_kc / "kc.csv").read_bytes()
    (out / ".cache" / "geometry.pkl").write_bytes(b"garbage")
    result = CliRunner().invoke(main, ["kc", "--config", str(case_path), "--out", str(out),
                                       "--models", "initial,identified", "--quiet"])
    assert result.exit_code == 0, result.output
    assert result.output.count("cache entry ignored") == 1
    assert json.loads((out / "summary.json").read_text())["reused_from_cache"] == []


def _copy_case(case_path, tmp_path):
    """The case study's config, CMM and K&C test files copied into ``tmp_path``."""
    for name in ("pseudo_mcpherson_measurements", "pseudo_mcpherson_kc_test"):
        shutil.copytree(case_path.parent / name, tmp_path / name)
    shutil.copy(case_path, tmp_path / case_path.name)
    return tmp_path / case_path.name


@pytest.mark.slow
def test_a_changed_input_is_never_answered_from_the_cache(case_path, coarse_travel, tmp_path):
    """One toe value of the K&C test data changed by 0.001 deg after a run: the next run
    recomputes every model (the identification, which does not read the test data, is
    reused); nothing changed, everything is reused."""
    config = _copy_case(case_path, tmp_path)
    out = tmp_path / "res"
    args = ["kc", "--config", str(config), "--out", str(out), "--quiet", "--models",
            "initial,identified", "--rig", str(coarse_travel)]
    assert CliRunner().invoke(main, args).exit_code == 0
    CliRunner().invoke(main, args)
    assert json.loads((out / "summary.json").read_text())["reused_from_cache"] == [
        "geometry", "models"]
    data = tmp_path / "pseudo_mcpherson_kc_test" / "parallel_travel.csv"
    lines = data.read_text().splitlines()
    row = next(i for i, line in enumerate(lines) if line[:1] in "-0123456789")
    fields = lines[row].split(",")
    fields[1] = repr(float(fields[1]) + 0.001)  # toe [deg]
    lines[row] = ",".join(fields)
    data.write_text("\n".join(lines) + "\n")
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert json.loads((out / "summary.json").read_text())["reused_from_cache"] == [
        "geometry"]


@pytest.mark.slow
def test_concurrent_runs_into_one_folder_leave_valid_results(case_path, coarse_travel, tmp_path):
    """Two `elastokin kc` processes at once into the same folder: both succeed, the folder
    holds one run's complete results, and its cache entries serve the next run."""
    import subprocess
    import sys

    out = tmp_path / "res"
    cmd = [sys.executable, "-c", "import sys; from elastokin.cli import main; "
           "sys.exit(main())", "kc", "--config", str(case_path), "--out", str(out),
           "--quiet", "--models", "initial,identified", "--rig", str(coarse_travel)]
    procs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True) for _ in range(2)]
    for p in procs:
        _, err = p.communicate(timeout=300)
        assert p.returncode == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert sorted(summary["models"]) == ["identified", "initial", "test"]
    result = CliRunner().invoke(main, cmd[3:])
    assert result.exit_code == 0, result.output
    assert json.loads((out / "summary.json").read_text())["reused_from_cache"] == [
        "geometry", "models"]
