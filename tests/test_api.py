"""The public Python API (elastokin/__init__.py) as the README shows it: a job from variants,
results written and read back, one variant on the rig."""

import numpy as np
import pytest

import elastokin as ek

from .conftest import CASE, ROOT

DW = ROOT / "tests" / "data" / "double_wishbone.yaml"


def test_job_from_variants_written_and_read_back(tmp_path):
    s = ek.load_suspension(DW)
    variants = {"nominal": ek.ModelVariant("nominal", s),
                "stiff": ek.ModelVariant("stiff", ek.kinematic(s))}
    run = ek.run_kc_from_variants(s, variants, "nominal")
    assert set(run.models) == {"nominal", "stiff"} and run.static is not None
    summary = ek.write_kc_results(run, tmp_path)
    again, sweeps = ek.read_results(tmp_path)
    assert again["models"] == summary["models"]
    toe = {(sw.model, sw.load_case): sw.columns["toe_deg"] for sw in sweeps}
    for label, m in run.models.items():
        for sw in m.sweeps:
            # kc.csv keeps 10 decimals
            np.testing.assert_allclose(toe[(label, sw.load_case)], sw.columns["toe_deg"],
                                       atol=1e-10)


@pytest.mark.slow
def test_readme_example(case_kc):
    s = ek.load_suspension(CASE)
    nominal = ek.suspension_from_dict({**s.raw, "measurements": None, "kc_test": None})
    model = ek.build_model(ek.kinematic(nominal))
    travel = ek.parallel_travel(model, "kinematic")
    assert travel.columns["toe_deg"].shape == travel.columns["wheel_travel_mm"].shape
    summary, sweeps = ek.read_results(case_kc)
    assert {sw.model for sw in sweeps} == set(summary["models"])
    # the kinematic nominal model's steer amplitude (0.548 deg, test_cli's regression)
    assert ek.summary_figures([travel], True)["steer_amplitude_deg"] == pytest.approx(
        0.5479, abs=0.005)
