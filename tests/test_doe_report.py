"""DOE studies an engineer can read and grow (issue 19, item 6): labels from the channel table,
whole-sample count ticks, the lines of a histogram in its legend, a warning when the samples
cannot support the sensitivity measure, and a Sobol or Monte Carlo study extended in place
(an LHS study refused with the way out)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.errors import ElastokinError
from elastokin.report import doe_charts
from elastokin.studies import doe_runner, doe_sampling, doe_statistics

from .test_doe import write_config


# ------------------------------------------------------------------------- sensitivity
def test_src_standard_error_of_one_regressor_by_hand():
    """y = 2 x + e: SE(b) = s / sqrt(sum (x - mean)^2), s^2 = RSS / (n - 2); the SRC's is
    SE(b) std(x) / std(y)."""
    x = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    y = 2.0 * x + np.array([0.1, -0.1, 0.0, 0.1, -0.1])
    b, a = np.polyfit(x, y, 1)
    rss = float(np.sum((y - (a + b * x)) ** 2))
    se_b = np.sqrt(rss / 3) / np.sqrt(np.sum((x - x.mean()) ** 2))
    [se] = doe_statistics.standardised_regression(x[:, None], y).src_standard_error
    assert se == pytest.approx(se_b * x.std(ddof=1) / y.std(ddof=1), rel=1e-12)
    # no standard error without a degree of freedom left: the regression refuses
    with pytest.raises(ValueError, match="need at least 3"):
        doe_statistics.standardised_regression(x[:2, None], y[:2])


def test_too_few_samples_for_the_measure_is_a_warning():
    """8 samples, 12 components: each joint's R^2 of its own regression, inflated by chance
    (a joint without effect about k / (n - 1)): the figures overlap, and the study says so."""
    rng = np.random.default_rng(0)
    X = rng.uniform(-1, 1, size=(8, 12))
    groups = [g for g in "ABCD" for _ in range(3)]
    y = X[:, 0]
    res = doe_statistics.joint_sensitivity(X, y, groups)
    assert res["method"] == "src_per_joint"
    assert sum(res["joints"].values()) > 1.0  # not shares
    w = res["warning"]
    assert "8 samples are too few" in w and "at least 14 samples" in w and "0.43" in w
    # with enough uncorrelated samples and a linear response: shares, no warning
    many = rng.uniform(-1, 1, size=(4000, 12))
    clean = doe_statistics.joint_sensitivity(many, many[:, 0] + 0.5 * many[:, 4], groups)
    assert clean["method"] == "src" and clean["warning"] is None
    assert sum(clean["joints"].values()) == pytest.approx(clean["r2"], abs=0.02)


def test_correlated_or_noisy_samples_are_a_warning():
    rng = np.random.default_rng(1)
    groups = ["A", "B"]
    # two components correlated in the sample: squared SRCs are not shares
    a = rng.uniform(-1, 1, 40)
    X = np.c_[a, a + 0.2 * rng.uniform(-1, 1, 40)]
    res = doe_statistics.joint_sensitivity(X, X[:, 0] + X[:, 1], groups)
    assert res["method"] == "src" and "correlated in the sample" in res["warning"]
    # independent components, a noisy response, few degrees of freedom: uncertain SRCs
    X = rng.uniform(-1, 1, size=(6, 2))
    res = doe_statistics.joint_sensitivity(X, X[:, 0] + rng.normal(0, 1.0, 6), groups)
    assert "standard errors up to" in res["warning"]


# ------------------------------------------------------------------------------ charts
def _doe(n: int = 8, warning: str | None = None) -> tuple[dict, list[dict]]:
    rng = np.random.default_rng(2)
    values = 0.5 + 0.05 * rng.standard_normal(n)
    records = [{"status": "ok", "characteristics": {"steer_amplitude_deg": float(v)}}
               for v in values]
    stats = doe_statistics.statistics(values)
    doe = {"steer_amplitude_deg": stats, "characteristics": {"steer_amplitude_deg": stats},
           "nominal": {"steer_amplitude_deg": 0.51}, "method": "lhs", "seed": 0,
           "completed": n, "failed": 0, "sensitivity": {"J1": 0.9, "J2": 0.8},
           "sensitivity_method": "src_per_joint", "sensitivity_r2": None,
           "src_components": {"inputs": ["J1.x", "J2.x"], "steer_amplitude_deg": None},
           "warnings": [warning] if warning else []}
    return doe, records


def test_histogram_counts_whole_samples_and_names_its_lines():
    doe, records = _doe()
    fig = doe_charts.steer_amplitude_histogram(doe, records)
    fig.canvas.draw()
    ax = fig.axes[0]
    ticks = ax.get_yticks()
    assert np.allclose(ticks, np.round(ticks)) and len(ticks) >= 2
    labels = ax.get_legend_handles_labels()[1]
    assert labels == ["mean", "5th / 95th percentile", "nominal model (no clearance shift)"]
    assert ax.get_xlabel() == "steer amplitude over the travel stroke [deg]"  # channel table
    grid = doe_charts.characteristics_histograms(doe, records)
    legend = next(a.get_legend() for a in grid.axes if a.get_legend() is not None)
    assert [t.get_text() for t in legend.get_texts()] == labels


def test_tornado_carries_the_sensitivity_warning(tmp_path):
    doe, records = _doe(warning="8 samples are too few for the sensitivity measure")
    fig = doe_charts.sensitivity_tornado(doe)
    assert "too few" in fig.get_suptitle() and "not shares" in fig.axes[0].get_xlabel()
    doe["warnings"], doe["sensitivity_method"], doe["sensitivity_r2"] = [], "src", 0.99
    fig = doe_charts.sensitivity_tornado(doe)
    assert fig.get_suptitle() == "" and "shares sum to 1.70" in fig.axes[0].get_title()
    paths = doe_charts.doe_charts(doe, records, tmp_path, {
        "elastokin_version": "0", "exudyn_version": "0", "config_file": "c.yaml",
        "config_sha256": "0" * 64})
    assert [p.suffix for p in paths] == [".png"] * 3  # SVG only when asked for


# ------------------------------------------------------------------------- extension
@pytest.mark.parametrize("method", ["sobol", "mc"])
def test_sobol_and_mc_designs_extend_lhs_does_not(method):
    small = doe_sampling.unit_samples(method, 8, 12, 5)
    assert np.array_equal(doe_sampling.unit_samples(method, 16, 12, 5)[:8], small)
    assert method in doe_sampling.EXTENSIBLE
    lhs = doe_sampling.unit_samples("lhs", 16, 12, 5)[:8]
    assert not np.array_equal(lhs, doe_sampling.unit_samples("lhs", 8, 12, 5))


def _store(tmp_path, method: str, samples: int):
    header = {"elastokin_doe_samples": 1, "config_sha256": "c" * 64, "method": method,
              "samples": samples, "seed": 0, "load_cases": "travel"}
    return header, doe_runner.SampleStore(tmp_path / "samples.jsonl", header)


def test_a_store_is_extended_in_place_only_when_the_design_extends(tmp_path):
    header, store = _store(tmp_path, "sobol", 4)
    for k in range(4):
        store.add({"sample": k, "shifts_mm": {"J1": [0.1 * k, 0.0, 0.0]}, "status": "ok"})
    bigger = doe_runner.SampleStore(store.path, {**header, "samples": 8})
    assert bigger.extended_from == 4 and sorted(bigger.records) == [0, 1, 2, 3]
    assert json.loads(store.path.read_text().splitlines()[0])["samples"] == 8
    with pytest.raises(ElastokinError, match="holds a 8-sample study; ask for at least 8"):
        doe_runner.SampleStore(store.path, {**header, "samples": 6})
    # the stored samples must be this design's first ones
    bigger.check_design(lambda k: {"J1": [0.1 * k, 0.0, 0.0]})
    with pytest.raises(ElastokinError, match="sample 1 is not sample 1 of this design"):
        bigger.check_design(lambda k: {"J1": [0.2 * k, 0.0, 0.0]})
    lhs_header, lhs = _store(tmp_path / "lhs", "lhs", 4)
    lhs.add({"sample": 0, "shifts_mm": {}, "status": "ok"})
    with pytest.raises(ElastokinError, match="4-sample Latin hypercube, which cannot be "
                                             "extended to 8 samples.*--method sobol or mc"):
        doe_runner.SampleStore(lhs.path, {**lhs_header, "samples": 8})


def test_extended_study_gives_the_fresh_study(case_path, tmp_path):
    """`elastokin doe --samples 4 --method sobol`, then `--samples 8` into the same folder:
    the 4 samples are kept, 4 more run, and doe.json is the one of a fresh 8-sample study."""
    config = write_config(tmp_path, case_path)
    args = ["--method", "sobol", "--load-cases", "travel", "--workers", "1"]

    def run(out, samples, quiet=True):
        return CliRunner().invoke(main, ["doe", "--config", str(config), "--out", str(out),
                                         "--samples", str(samples), *args,
                                         *(["--quiet"] if quiet else [])])

    assert run(tmp_path / "grown", 4).exit_code == 0
    grown = run(tmp_path / "grown", 8, quiet=False)
    assert grown.exit_code == 0, grown.output
    assert "extending: the 4 samples" in grown.output
    assert json.loads((tmp_path / "grown" / "doe_run.json").read_text())[
        "samples_evaluated_this_run"] == 4
    assert run(tmp_path / "fresh", 8).exit_code == 0
    assert (tmp_path / "grown" / "doe.json").read_bytes() == \
        (tmp_path / "fresh" / "doe.json").read_bytes()
    doc = json.loads((tmp_path / "fresh" / "doe.json").read_text())
    assert doc["warnings"] and "too few" in doc["warnings"][0]  # 8 samples, 12 components
    assert "elastokin: warning: 8 samples are too few" in grown.output
