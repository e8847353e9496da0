"""The resolved Suspension as a Python object (issue 19, item 5): read-only (a change that
would be ignored raises, naming the API that makes a changed copy), picklable and replaceable
without losing that; configs built in Python with numpy numbers; the config and rig hashes
reported apart while the result cache stays keyed on both."""

from __future__ import annotations

import copy
import dataclasses
import pickle

import numpy as np
import pytest
import yaml

import elastokin as ek
from elastokin.config.frozen import FrozenMapping, plain_data
from elastokin.config.loading import load_suspension, load_suspension_with_rig
from elastokin.config.variants import with_hardpoints
from elastokin.studies.cache import ResultCache
from elastokin.studies.kc_job import geometry

from .conftest import CASE, ROOT

DW = ROOT / "tests" / "data" / "double_wishbone.yaml"
RIGS = CASE.parent / "rigs"


@pytest.fixture(scope="module")
def dw():
    return load_suspension(DW)


def _arrays(s):
    """Every array of a resolved suspension."""
    out = list(s.hardpoints.values()) + [s.wheel.centre_mm, s.wheel.spin_axis]
    for j in s.joints:
        out += [j.position_mm, j.frame]
    for b in s.bushings:
        out += [b.position_mm, b.frame, b.initial_deflection]
    for sp in s.springs:
        out += list(sp.seats_mm)
    for link in s.links:
        out += list(link.points_mm)
    return out


def _assert_read_only(s):
    assert isinstance(s.hardpoints, FrozenMapping) and isinstance(s.raw, FrozenMapping)
    assert all(not a.flags.writeable for a in _arrays(s))


def test_assigning_a_hardpoint_raises_and_names_the_override_api(dw):
    name = next(iter(dw.hardpoints))
    with pytest.raises(TypeError, match="with_hardpoints"):
        dw.hardpoints[name] = np.zeros(3)
    with pytest.raises(dataclasses.FrozenInstanceError, match="with_hardpoints"):
        dw.hardpoints = {}
    with pytest.raises(ValueError, match="read-only"):
        dw.hardpoints[name][2] += 1.0
    with pytest.raises(TypeError, match="suspension_from_dict"):
        dw.raw["hardpoints"][name] = [0.0, 0.0, 0.0]
    with pytest.raises(ValueError, match="read-only"):
        dw.joints[0].position_mm[0] = 0.0
    _assert_read_only(dw)


def test_the_override_api_moves_the_hardpoint_and_leaves_the_template(dw):
    name = next(iter(dw.hardpoints))
    before = dw.hardpoints[name].copy()
    moved = with_hardpoints(dw, {name: dw.hardpoints[name] + [0.0, 0.0, 5.0]})
    np.testing.assert_allclose(moved.hardpoints[name] - before, [0.0, 0.0, 5.0])
    np.testing.assert_array_equal(dw.hardpoints[name], before)
    _assert_read_only(moved)
    # the caller's array is never frozen
    mine = np.array([1.0, 2.0, 3.0])
    with_hardpoints(dw, {name: mine})
    mine[0] = 7.0


def test_pickle_replace_and_deepcopy_keep_it_read_only(dw):
    for again in (pickle.loads(pickle.dumps(dw)), copy.deepcopy(dw),
                  dataclasses.replace(dw, name="renamed")):
        _assert_read_only(again)
        for name, p in dw.hardpoints.items():
            np.testing.assert_array_equal(again.hardpoints[name], p)
    raw = copy.deepcopy(dw.raw)  # the config mapping to edit: plain and editable
    assert type(raw) is dict and type(raw["hardpoints"]) is dict
    raw["name"] = "edited"
    assert ek.suspension_from_dict(raw).name == "edited"


def test_configs_accept_numpy_numbers_and_arrays(dw):
    raw = copy.deepcopy(dw.raw)
    name = next(iter(raw["hardpoints"]))
    raw["hardpoints"][name] = np.asarray(raw["hardpoints"][name]) + np.float32(0.5)
    raw["design"]["wheel_load_N"] = np.float64(raw["design"]["wheel_load_N"])
    raw["side"] = np.str_(raw["side"])
    s = ek.suspension_from_dict(raw)
    np.testing.assert_allclose(s.hardpoints[name], dw.hardpoints[name] + 0.5)
    # the same config as plain numbers gives the same suspension and the same hash
    plain = yaml.safe_load(yaml.safe_dump(plain_data(raw)))
    assert ek.suspension_from_dict(plain).sha256 == s.sha256
    assert isinstance(plain_data(np.int64(3)), int) and plain_data((np.bool_(True),)) == [True]


def test_config_and_rig_hashes_apart_and_the_cache_keyed_on_both(tmp_path):
    plain = load_suspension(CASE)
    quick = load_suspension_with_rig(CASE, RIGS / "travel_only.yaml")
    paper = load_suspension_with_rig(CASE, RIGS / "paper_fig9.yaml")
    assert plain.rig_sha256 is None and plain.config_sha256 == plain.sha256
    # the config's hash does not change when a rig file is added; the rig's is its own
    assert quick.config_sha256 == paper.config_sha256 == plain.config_sha256
    assert None is not quick.rig_sha256 != paper.rig_sha256
    # the identity of everything (what results are cached under) covers both
    assert len({plain.sha256, quick.sha256, paper.sha256}) == 3
    # ... and so does the cache: an identification stored for one rig is not reused for
    # another, nor for another config with the same rig
    store = tmp_path / "store"
    first = geometry(quick, cache=ResultCache(None, store))
    cache = ResultCache(store, None)
    assert geometry(quick, cache=cache) is not None and cache.reused == ["geometry"]
    cache = ResultCache(store, None)
    geometry(paper, cache=cache)
    assert cache.reused == []
    edited = tmp_path / "case.yaml"
    edited.write_text(CASE.read_text() + "\n# a comment changes the bytes\n")
    other = load_suspension_with_rig(edited, RIGS / "travel_only.yaml")
    assert other.rig_sha256 == quick.rig_sha256 and other.config_sha256 != quick.config_sha256
    assert other.sha256 != quick.sha256  # the cache key of every step starts from it
    assert first is not None
