import copy
import os
from pathlib import Path

import pytest

# One BLAS thread in the tests and in every process they start (elastokin, dask workers, the
# stiffness fit's pool), set before numpy is first imported (elastokin is imported lazily
# below) unless the user set it: the models' matrices are small, and OpenBLAS's second
# thread spin-waits for work, taking the core from the solver whenever anything else runs
# on a 2-core machine (measured under load: the twist beam's roll tests 2.7 s instead of
# 0.1 s, the whole suite 17 % more CPU time).
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"


@pytest.fixture(scope="session", autouse=True)
def user_cache_home(tmp_path_factory) -> Path:
    """The tests' own XDG_CACHE_HOME (inherited by the elastokin processes they start): the
    result cache's secret key is made there, never in the real home's ~/.cache."""
    home = tmp_path_factory.mktemp("xdg_cache")
    before = os.environ.get("XDG_CACHE_HOME")
    os.environ["XDG_CACHE_HOME"] = str(home)
    yield home
    if before is None:
        del os.environ["XDG_CACHE_HOME"]
    else:
        os.environ["XDG_CACHE_HOME"] = before


@pytest.fixture(scope="session")
def case_path() -> Path:
    return CASE


@pytest.fixture(scope="session")
def coarse_travel(tmp_path_factory) -> Path:
    """configs/rigs/travel_only.yaml in 10 mm steps (11 points a branch, not 51): for the
    runs that check what a command does with its results (cache, trust), not the load
    cases."""
    text = (ROOT / "configs" / "rigs" / "travel_only.yaml").read_text()
    assert "step_mm: 2," in text
    path = tmp_path_factory.mktemp("rig") / "coarse_travel.yaml"
    path.write_text(text.replace("step_mm: 2,", "step_mm: 10,"))
    return path


@pytest.fixture(scope="session")
def case():
    from elastokin.config.loading import load_suspension

    return load_suspension(CASE)


@pytest.fixture(scope="session")
def case_design(case):
    from elastokin.mbs.design import design_state

    return design_state(case)


@pytest.fixture
def case_dict() -> dict:
    """A fresh, mutable copy of the shipped config's mapping without its CMM measurements:
    the nominal model (Table 2 geometry)."""
    from elastokin.config.loading import read_yaml

    data = copy.deepcopy(read_yaml(CASE)[0])
    del data["measurements"]
    data.pop("kc_test", None)
    return data


def make_suspension(data: dict, name: str = "test.yaml"):
    from elastokin.config.loading import suspension_from_dict

    return suspension_from_dict(data, name)


@pytest.fixture(scope="session")
def case_kc(tmp_path_factory) -> Path:
    """``elastokin kc`` on the shipped case study, run once per test session and shared by
    every test that reads its files (about 10 s: identification, 4 models, the stiffness
    fit). Tests using it are marked slow."""
    from click.testing import CliRunner

    from elastokin.cli import main

    out = tmp_path_factory.mktemp("case_kc") / "res"
    result = CliRunner().invoke(main, ["kc", "--config", str(CASE), "--out", str(out),
                                       "--quiet"])
    assert result.exit_code == 0, result.output
    return out
