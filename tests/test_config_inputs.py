"""Bad config inputs (issue 15, items 1, 2, 3, 7): strict YAML (no key twice, malformed YAML
with its line), finite numbers only, degenerate directions, distinct names, bounded work (rig
steps, curve sizes), unknown keys with a suggestion and key paths in the config's own terms.
Every refusal is one line naming the file and the key. Pure and fast: no solve."""

from __future__ import annotations

import copy
import math
import re
from pathlib import Path

import pytest
import yaml

from elastokin.config import bounds
from elastokin.config.loading import load_rig, load_suspension, parse_yaml, read_yaml
from elastokin.config.schema.base import CurveSpec
from elastokin.config.schema.rig import RigSpec
from elastokin.errors import ConfigError, ElastokinError
from elastokin.formats.adams.car import read_mapping
from elastokin.formats.cmm_parts import read_truth
from elastokin.rig.paths import sweep_path, travel_path, vertical_force_path

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"
WISHBONE = ROOT / "tests" / "data" / "double_wishbone.yaml"
MAPPING = ROOT / "tests" / "data" / "adams" / "double_wishbone_mapping.yaml"
TRUTH = ROOT / "configs" / "pseudo_mcpherson_measurements" / "truth.yaml"

#: pydantic's own location segments, never shown to the user
INTERNALS = (".bushing.", ".float'", ".float.", "CurveSpec", "function-after", "tuple[", ".str'",
             ".str.", "[key]", "AxisBetween", ".link.", ".cylindrical.")


def _set(*path_and_value):
    """A mutation setting ``d[k1][k2]...[kn] = value``."""
    *keys, value = path_and_value

    def mutate(d: dict) -> None:
        for k in keys[:-1]:
            d = d.setdefault(k, {})
        d[keys[-1]] = copy.deepcopy(value)
    return mutate


def _rename(*path_and_new):
    """A mutation renaming key ``path[-1]`` of ``d[path[0]]...`` to ``new``."""
    *keys, new = path_and_new

    def mutate(d: dict) -> None:
        for k in keys[:-1]:
            d = d[k]
        d[new] = d.pop(keys[-1])
    return mutate


def _clash(section: str, name: str, like: tuple[str, str]):
    """A mutation adding to ``section`` an entry named ``name``, copied from ``like``."""
    def mutate(d: dict) -> None:
        d[section][name] = copy.deepcopy(d[like[0]][like[1]])
    return mutate


def _both(*mutations):
    def mutate(d: dict) -> None:
        for m in mutations:
            m(d)
    return mutate


CURVE = {"deflection": [-1.0, 0.0, 1.0], "load": [-650.0, 0.0, 650.0]}
BIG = list(range(-5000, 5001))  # 10,001 points

# name -> (mutation of the config mapping, words the message must contain, words it must not)
BAD_CONFIGS = {
    # --- finite numbers (item 2)
    "nan hardpoint": (_set("hardpoints", "J4", [73.7, math.nan, 762.6]),
                      ["hardpoints.J4[1]", "finite"], []),
    "inf hardpoint": (_set("hardpoints", "J9", [0.0, -math.inf, 305.0]),
                      ["hardpoints.J9[1]", "finite"], []),
    "inf bushing rate": (_set("connections", "J4", "stiffness", "x", math.inf),
                         ["connections.J4.stiffness.x", "finite"], []),
    "nan spring rate": (_set("springs", "coil", "rate_N_per_mm", math.nan),
                        ["springs.coil.rate_N_per_mm", "finite"], []),
    "nan in a curve": (_set("connections", "J4", "stiffness", "y",
                            {"deflection": [-1.0, 0.0, 1.0], "load": [-650.0, 0.0, math.nan]}),
                       ["connections.J4.stiffness.y.load[2]", "finite"], []),
    "inf loaded radius": (_set("wheel", "loaded_radius_mm", math.inf),
                          ["wheel.loaded_radius_mm", "finite"], []),
    "nan loaded radius": (_set("wheel", "loaded_radius_mm", math.nan),
                          ["wheel.loaded_radius_mm", "finite"], []),
    "inf rig stroke": (_set("rig", "parallel_travel", {"rebound_mm": -90, "bump_mm": math.inf}),
                       ["rig.parallel_travel.bump_mm", "finite"], []),
    "nan inline point": (_set("connections", "J8", "at", [-25.5, math.nan, 233.0]),
                         ["connections.J8.at[1]", "finite"], []),
    "nan design load": (_set("design", "wheel_load_N", math.nan),
                        ["design.wheel_load_N", "finite"], []),
    # --- degenerate directions (item 2)
    "vertical spin axis": (_set("wheel", "spin_axis", [0.0, 0.0, 1.0]),
                           ["wheel.spin_axis", "vertical"], []),
    "spin axis 0.5 deg from vertical": (
        _set("wheel", "spin_axis", [0.0, math.sin(math.radians(0.5)),
                                    math.cos(math.radians(0.5))]),
        ["wheel.spin_axis", "at least 1 deg"], []),
    "radial along the bushing axis": (
        _set("connections", "J4", "radial", {"from": "J5", "to": "J4"}),
        ["connections.J4.radial", "parallel"], []),
    "zero axis": (_set("connections", "strut", "axis", [0.0, 0.0, 0.0]),
                  ["connections.strut.axis", "zero"], []),
    "axis between coincident points": (_set("connections", "strut", "axis",
                                            {"from": "J4", "to": "J4"}),
                                       ["connections.strut.axis", "same point"], []),
    # --- distinct names (item 1)
    "connection named like a part": (_clash("connections", "knuckle", ("connections", "J8")),
                                     ["connections.knuckle", "parts.knuckle"], []),
    "spring named like a connection": (_clash("springs", "J4", ("springs", "coil")),
                                       ["springs.J4", "connections.J4"], []),
    "connection named like the ground": (_clash("connections", "body", ("connections", "J8")),
                                         ["connections.body", "'ground'"], []),
    "part named like the ground": (_set("parts", "body", {}), ["parts.body", "'ground'"], []),
    # --- bounded work (item 3)
    "parallel travel steps": (
        _set("rig", "parallel_travel", {"rebound_mm": -90, "bump_mm": 90, "step_mm": 0.001}),
        ["rig.parallel_travel.step_mm", "450,000 steps", "at most 100,000"], []),
    "parallel travel stroke": (
        _set("rig", "parallel_travel", {"rebound_mm": -1e6, "bump_mm": 1e6, "step_mm": 1}),
        ["rig.parallel_travel.step_mm", "5,000,000 steps", "at most 100,000"], []),
    "vertical force steps": (
        _set("rig", "vertical_force", {"min_N": 1000, "max_N": 7500, "step_N": 0.01}),
        ["rig.vertical_force.step_N", "1,300,001 steps", "at most 100,000"], []),
    "vertical force approach": (
        _set("design", "wheel_load_N", 1e9),
        ["rig.vertical_force.step_N", "design.wheel_load_N", "20,000,240 steps"], []),
    "lateral force steps": (_set("rig", "lateral_force", {"amplitude_N": 2000, "step_N": 0.01}),
                            ["rig.lateral_force.step_N", "800,000 steps"], []),
    "longitudinal force at the patch": (
        _set("rig", "longitudinal_force_patch", {"amplitude_N": 1e7}),
        ["rig.longitudinal_force_patch.step_N", "800,000 steps"], []),
    "longitudinal force at the centre": (
        _set("rig", "longitudinal_force_centre", {"amplitude_N": 2000, "step_N": 1e-300}),
        ["rig.longitudinal_force_centre.step_N", "steps", "at most 100,000"], []),
    "aligning torque steps": (_set("rig", "aligning_torque", {"step_Nmm": 1.0}),
                              ["rig.aligning_torque.step_Nmm", "400,000 steps"], []),
    "oversized curve": (_set("connections", "J4", "stiffness", "x",
                             {"deflection": BIG, "load": BIG}),
                        ["connections.J4.stiffness.x.deflection", "10000"], []),
    "too many substeps": (_set("kc_test", "synthetic", "substeps", 10**9),
                          ["kc_test.synthetic.substeps", "100"], []),
    # --- unknown keys and key paths (item 7)
    "misspelt spring rate": (_rename("springs", "coil", "rate_N_per_mm", "rate_N_per_m"),
                             ["springs.coil", "unknown key 'rate_N_per_m'",
                              "did you mean 'rate_N_per_mm'?", "(1 more problem)"],
                             ["Field required"]),
    "misspelt top-level key": (_rename("hardpoints", "hardpoint"),
                               ["unknown top-level key 'hardpoint'",
                                "did you mean 'hardpoints'?"], ["Field required"]),
    "misspelt bushing key": (_rename("connections", "J4", "stiffness", "stifness"),
                             ["connections.J4", "unknown key 'stifness'",
                              "did you mean 'stiffness'?"], []),
    "misspelt curve key": (_set("connections", "J4", "stiffness", "z",
                                {"deflections": [0, 1], "load": [0, 650]}),
                           ["connections.J4.stiffness.z", "'deflections'",
                            "did you mean 'deflection'?"], []),
    "misspelt axis key": (_set("connections", "strut", "axis", {"from": "J5", "too": "J4"}),
                          ["connections.strut.axis", "'too'", "did you mean 'to'?"], []),
    "key path without internals": (_set("connections", "J4", "stiffness", "rx", "stiff"),
                                   ["connections.J4.stiffness.rx", "valid number"], []),
    "missing key in a bushing": (
        lambda d: d["connections"]["J4"]["stiffness"].pop("rz"),
        ["connections.J4.stiffness.rz", "required"], []),
    "unknown connection type": (_set("connections", "J8", "type", "ball"),
                                ["connections.J8", "'ball'"], []),
    # --- two points that must differ
    "link of one point": (_set("connections", "tie_rod", "at", ["J3", "J3"]),
                          ["connections.tie_rod.at", "two distinct points"], []),
    "spring seats coincide": (_set("springs", "coil", "seats",
                                   ["spring_upper_seat", "spring_upper_seat"]),
                              ["springs.coil.seats", "the two spring seats coincide"], []),
}


@pytest.mark.parametrize("name", list(BAD_CONFIGS))
def test_bad_config_is_one_line_naming_file_and_key(case_dict, tmp_path, name):
    mutate, words, absent = BAD_CONFIGS[name]
    mutate(case_dict)
    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(case_dict, sort_keys=False))
    with pytest.raises(ConfigError) as exc:
        load_suspension(path)
    message = str(exc.value)
    assert "\n" not in message and message.startswith(f"{path}: "), message
    for word in words:
        assert word in message, message
    for word in (*absent, *INTERNALS):
        assert word not in message, message


def _insert_after(line: str, extra: str):
    """A text mutation inserting ``extra`` (one line) after the line starting ``line``; the
    line number (1-based) of ``extra`` comes back with the text."""
    def mutate(text: str) -> tuple[str, int]:
        lines = text.splitlines()
        i = next(n for n, t in enumerate(lines) if t.startswith(line))
        return "\n".join([*lines[: i + 1], extra, *lines[i + 1:]]) + "\n", i + 2
    return mutate


def _replace(line: str, new: str):
    """A text mutation replacing the line starting ``line`` by ``new``."""
    def mutate(text: str) -> tuple[str, int]:
        lines = text.splitlines()
        i = next(n for n, t in enumerate(lines) if t.startswith(line))
        lines[i] = new
        return "\n".join(lines) + "\n", i + 1
    return mutate


def _line_of(text: str, start: str) -> int:
    return next(n for n, t in enumerate(text.splitlines(), 1) if t.startswith(start))


# name -> (file the text mutation is applied to, mutation, reader, words of the message)
BAD_FILES = {
    "duplicate top-level key": (CASE, _insert_after("side: left", "side: right"),
                                load_suspension,
                                ["key 'side' appears twice at the top level",
                                 "(first at line {first})"]),
    "duplicate hardpoint": (CASE, _insert_after("  J9:", "  J4: [0, 0, 0]"), load_suspension,
                            ["key 'J4' appears twice in 'hardpoints'",
                             "(first at line {first})"]),
    "duplicate connection": (CASE, _insert_after("  J8: {type", "  J8: {type: fixed}"),
                             load_suspension, ["key 'J8' appears twice in 'connections'"]),
    "duplicate key in a connection": (
        CASE, _insert_after("    radial: [-1.0", "    radial: [1.0, 0.0, 0.0]"),
        load_suspension, ["key 'radial' appears twice in 'connections.J4'"]),
    "duplicate rig load case": (
        ROOT / "configs" / "rigs" / "paper_fig9.yaml",
        _insert_after("  lateral_force:", "  lateral_force: null"), load_rig,
        ["key 'lateral_force' appears twice in 'rig'"]),
    "duplicate truth joint": (TRUTH, _insert_after("  J2:", "  J2: [0.0, 0.0, 0.0]"),
                              read_truth,
                              ["key 'J2' appears twice in 'clearance_shift_mm'"]),
    "duplicate mapping hardpoint": (MAPPING, _insert_after("  lca_rear:", "  lca_front: x"),
                                    read_mapping,
                                    ["key 'lca_front' appears twice in 'hardpoints'"]),
    "malformed YAML": (CASE, _insert_after("side: left", "wheel: [unclosed"),
                       load_suspension, ["malformed YAML"]),
    "inf in a rig file": (ROOT / "configs" / "rigs" / "travel_only.yaml",
                          _replace("lateral_force:", "lateral_force: {amplitude_N: .inf}"),
                          load_rig, ["(rig file)", "lateral_force.amplitude_N", "finite"]),
    "huge step count in a rig file": (
        ROOT / "configs" / "rigs" / "paper_fig9.yaml",
        _replace("  vertical_force:", "  vertical_force: {min_N: 1000, step_N: 0.001}"),
        load_rig, ["rig.vertical_force.step_N", "at most 100,000"]),
    "misspelt rig load case": (
        ROOT / "configs" / "rigs" / "travel_only.yaml",
        _insert_after("aligning_torque", "paralel_travel: {step_mm: 2}"), load_rig,
        ["unknown top-level key 'paralel_travel'", "did you mean 'parallel_travel'?"]),
}


@pytest.mark.parametrize("name", list(BAD_FILES))
def test_bad_file_is_one_line_naming_file_line_and_key(tmp_path, name):
    source, mutate, reader, words = BAD_FILES[name]
    original = source.read_text()
    text, line = mutate(original)
    path = tmp_path / source.name
    path.write_text(text)
    with pytest.raises(ElastokinError) as exc:
        reader(path)
    assert isinstance(exc.value, ConfigError)
    message = str(exc.value)
    assert "\n" not in message and message.startswith(f"{path}"), message
    if "appears twice" in words[0]:
        assert f"line {line}: " in message, message
    if "malformed" in words[0]:
        assert re.search(r": line \d+, column \d+: ", message), message
    inserted = text.splitlines()[line - 1]
    first = _line_of(text, inserted.split(":")[0] + ":")  # the key's first place
    for word in words:
        assert word.format(first=first) in message, message


def test_duplicate_key_line_numbers_are_exact(tmp_path):
    path = tmp_path / "d.yaml"
    path.write_text("a: 1\nb:\n  c: [1, 2]\n  d: {e: 1}\n  c: 3\n")
    with pytest.raises(ConfigError, match=r"d\.yaml: line 5: key 'c' appears twice in 'b' "
                                          r"\(first at line 3\)$"):
        read_yaml(path)


def test_duplicate_key_in_a_list_item_and_a_flow_mapping():
    with pytest.raises(ConfigError, match=r"line 4: key 'x' appears twice in 'l\[1\]' "
                                          r"\(first at line 3\)"):
        parse_yaml("l:\n  - {x: 1}\n  - {x: 1,\n     x: 2}\n", "f.yaml")


def test_merge_keys_may_be_overridden():
    data = parse_yaml("base: &b {x: 1, y: 2}\nc:\n  <<: *b\n  x: 3\n", "f.yaml")
    assert data["c"] == {"x": 3, "y": 2}


def test_malformed_yaml_always_has_a_line(tmp_path):
    for text in (b"a: [1,\n", b"a: 1\n---\nb: 2\n", b"a: 1\n b: 2\n", b"a: 1\nb: \xff\n",
                 b"x: !!python/object:os.system 1\n"):
        with pytest.raises(ConfigError, match=r"^f\.yaml: line \d+.*malformed YAML: \S"
                           ) as exc:
            parse_yaml(text, "f.yaml")
        assert "\n" not in str(exc.value)


def test_a_nan_spelt_as_text_is_refused_too(case_dict):
    from elastokin.config.loading import suspension_from_dict

    case_dict["hardpoints"]["J4"] = [73.7, "NaN", 762.6]
    with pytest.raises(ConfigError, match=r"x\.yaml: key 'hardpoints\.J4\[1\]': .*finite"):
        suspension_from_dict(case_dict, "x.yaml")


# --- the bounds: exact counts and the limits themselves


@pytest.mark.parametrize("spec", [(-90, 90, 1, True), (-90, 90, 1, False), (-50, 50, 2, False),
                                  (-0.3, 7.1, 0.7, True), (-1, 1, 5, True)])
def test_travel_step_count_is_the_paths(spec):
    assert bounds.travel_steps(*spec) == travel_path(*spec)[0].size


@pytest.mark.parametrize("spec", [(4500, 1000, 7500, 50), (4500, 1000, 7500, 33.3),
                                  (500, 1000, 7500, 50), (1000, 1000, 1001, 50)])
def test_vertical_force_step_count_is_the_paths(spec):
    wheel_load, lo, hi, step = spec
    assert (bounds.vertical_force_steps(lo, hi, step, wheel_load)
            == vertical_force_path(wheel_load, lo, hi, step)[0].size)


@pytest.mark.parametrize("spec", [(2000, 50), (2000, 33.3), (1e5, 2500), (10, 50)])
def test_sweep_step_count_is_the_paths(spec):
    assert bounds.sweep_steps(*spec) == sweep_path(*spec)[0].size


def test_the_step_bound_is_inclusive():
    n = bounds.MAX_STEPS_PER_LOAD_CASE
    assert bounds.travel_steps(-n / 5, n / 5, 1, True) == n
    RigSpec.model_validate({"parallel_travel": {"rebound_mm": -n / 5, "bump_mm": n / 5}})
    with pytest.raises(ValueError, match=r"1 mm gives 100,002 steps .*; at most 100,000"):
        RigSpec.model_validate({"parallel_travel": {"rebound_mm": -n / 5,
                                                    "bump_mm": n / 5 + 1}})


def test_the_curve_bound_is_inclusive():
    n = bounds.MAX_CURVE_POINTS
    CurveSpec.model_validate({"deflection": list(range(n)), "load": list(range(n))})
    with pytest.raises(ValueError):
        CurveSpec.model_validate({"deflection": list(range(n + 1)), "load": list(range(n))})


# --- the shipped files still load


def test_shipped_configs_and_files_load():
    assert load_suspension(CASE).name
    assert load_suspension(WISHBONE).name
    rigs = sorted((ROOT / "configs" / "rigs").glob("*.yaml"))
    assert rigs
    for rig in rigs:
        assert isinstance(load_rig(rig), dict)
    assert read_mapping(MAPPING).hardpoints
    assert read_truth(TRUTH)
