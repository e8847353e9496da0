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
    """A second `elastokin kc` into the same folder with nothing changed reuses both and
    gives the same kc.csv; a corrupt entry is ignored (one warning) and recomputed."""
    out = tmp_path / "res"
    shutil.copytree(case_kc, out)
    result = CliRunner().invoke(main, ["kc", "--config", str(case_path), "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "Reused from the previous results" in result.output
    summary = json.loads((out / "summary.json").read_text())
    assert summary["reused_from_cache"] == ["geometry", "stiffness_fit"]
    assert (out / "kc.csv").read_bytes() == (case_kc / "kc.csv").read_bytes()
    (out / ".cache" / "geometry.pkl").write_bytes(b"garbage")
    result = CliRunner().invoke(main, ["kc", "--config", str(case_path), "--out", str(out),
                                       "--models", "initial,identified", "--quiet"])
    assert result.exit_code == 0, result.output
    assert result.output.count("cache entry ignored") == 1
    assert json.loads((out / "summary.json").read_text())["reused_from_cache"] == []
