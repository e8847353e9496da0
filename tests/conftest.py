import copy
from pathlib import Path

import pytest

from elastokin.config.loading import load_suspension, read_yaml, suspension_from_dict

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"


@pytest.fixture(scope="session")
def case_path() -> Path:
    return CASE


@pytest.fixture(scope="session")
def case():
    return load_suspension(CASE)


@pytest.fixture(scope="session")
def case_design(case):
    from elastokin.mbs.design import design_state

    return design_state(case)


@pytest.fixture
def case_dict() -> dict:
    """A fresh, mutable copy of the shipped config's mapping without its CMM measurements:
    the nominal model (Table 2 geometry)."""
    data = copy.deepcopy(read_yaml(CASE)[0])
    del data["measurements"]
    data.pop("kc_test", None)
    return data


def make_suspension(data: dict, name: str = "test.yaml"):
    return suspension_from_dict(data, name)
