"""K&C test data files: round trip, unit conversion, load case and branch rules, and a clear
error (naming the file and the column or line) for every malformed file."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from elastokin.errors import MeasurementError
from elastokin.formats.kc_test import (
    CHANNELS,
    LOAD_CASES,
    MAX_BRANCHES,
    UNITS,
    monotonic_branches,
    read_kc_test,
    write_kc_test,
)

from .kc_files import fails, put, sweep

# ------------------------------------------------------------------------------ round trip


def test_round_trip(tmp_path):
    fy = sweep(2000.0)
    channels = {
        "toe": -2.1e-5 * fy + 1e-9 * fy**2,
        "lateral_force": fy,  # not first: the writer puts the input channel first
        "camber": 4e-5 * fy,
        "wheel_centre_lateral": 6.1e-4 * fy,
        "aligning_torque": 30.0 * fy,
        "actuator_2": np.linspace(0, 1, fy.size),
    }
    notes = ["synthetic: made by the test suite", "static wheel load 4500 N"]
    p = write_kc_test(tmp_path / "rig_run.csv", "lateral_force", channels, notes=notes,
                      units={"actuator_2": "V"})
    first = p.read_bytes()
    text = first.decode("utf-8")
    assert text.startswith("# load_case: lateral_force\n# synthetic: made by the test suite\n")
    assert "\nlateral_force [N],toe [deg],camber [deg],wheel_centre_lateral [mm]," \
           "aligning_torque [N*mm],actuator_2 [V]\n" in text
    assert "\r" not in text and "-0.000000" not in text

    t = read_kc_test(p)
    assert t.load_case == "lateral_force" and t.input_channel == "lateral_force"
    assert list(t.channels) == ["lateral_force", "toe", "camber", "wheel_centre_lateral",
                                "aligning_torque", "actuator_2"]
    for k, v in channels.items():
        assert np.allclose(t.channels[k], v, rtol=0, atol=5e-7), k
    assert np.array_equal(t.input, t.channels["lateral_force"]) and t.steps == fy.size
    assert t.notes == notes and t.source == str(p)
    assert t.units == {"lateral_force": "N", "toe": "deg", "camber": "deg",
                       "wheel_centre_lateral": "mm", "aligning_torque": "N*mm",
                       "actuator_2": "V"}
    assert t.unknown_channels == ("actuator_2",)
    assert len(t.warnings) == 1 and "actuator_2 [V]" in t.warnings[0]
    # three branches: 0 -> +2000, +2000 -> -2000, -2000 -> 0, sharing the turning points
    assert [(b.start, b.stop) for b in t.branches] == [(0, 21), (20, 61), (60, 81)]
    assert t.input[t.branches[1]][0] == 2000 and t.input[t.branches[1]][-1] == -2000

    # deterministic: the same data, and the data read back, give the same bytes
    write_kc_test(p, "lateral_force", channels, notes=notes, units={"actuator_2": "V"})
    assert p.read_bytes() == first
    write_kc_test(p, t.load_case, t.channels, notes=t.notes, units=t.units)
    assert p.read_bytes() == first


@pytest.mark.parametrize("case", list(LOAD_CASES))
def test_every_load_case_round_trips(tmp_path, case):
    spec = LOAD_CASES[case]
    x = np.linspace(1000.0, 7500.0, 14) if case == "vertical_force" else sweep(90.0, 9)
    channels = {spec.input: x, **{c: 0.01 * x for c in spec.required}}
    t = read_kc_test(write_kc_test(tmp_path / f"{case}.csv", case, channels))
    assert t.load_case == case and t.input_channel == spec.input
    assert set(t.channels) == {spec.input, *spec.required} and t.warnings == []


# ------------------------------------------------------------------------- unit conversion


@pytest.mark.parametrize("column,cell,channel,expected", [
    ("lateral_force [kN]", "1.5", "lateral_force", 1500.0),
    ("lateral_force [N]", "1.5", "lateral_force", 1.5),
    ("toe [rad]", "0.01", "toe", math.degrees(0.01)),
    ("toe [°]", "0.25", "toe", 0.25),
    ("toe [degrees]", "0.25", "toe", 0.25),
    ("wheel_centre_lateral [m]", "0.0012", "wheel_centre_lateral", 1.2),
    ("wheel_centre_lateral [cm]", "0.12", "wheel_centre_lateral", 1.2),
    ("aligning_torque [N*m]", "2.5", "aligning_torque", 2500.0),
    ("aligning_torque [Nm]", "2.5", "aligning_torque", 2500.0),
    ("aligning_torque [N m]", "2.5", "aligning_torque", 2500.0),
    ("aligning_torque [N·m]", "2.5", "aligning_torque", 2500.0),
    ("aligning_torque [kN*m]", "0.25", "aligning_torque", 250000.0),
    ("aligning_torque [Nmm]", "2.5", "aligning_torque", 2.5),
])
def test_unit_conversion(tmp_path, column, cell, channel, expected):
    header = {"lateral_force": "lateral_force [kN]", "toe": "toe [deg]", channel: column}
    row1 = {"lateral_force": "2", "toe": "0", channel: cell}
    p = put(tmp_path, "lateral_force.csv", f"{','.join(header.values())}\n"
            f"{','.join('0' for _ in header)}\n{','.join(row1.values())}\n")
    t = read_kc_test(p)
    assert t.channels[channel][1] == pytest.approx(expected, rel=1e-12)
    assert t.channels[channel][0] == 0.0
    assert t.units[channel] == CHANNELS[channel].unit == next(iter(UNITS[CHANNELS[channel]
                                                                         .quantity]))


def test_header_names_are_normalised_and_bom_accepted(tmp_path):
    p = tmp_path / "x_parallel_travel.csv"
    p.write_bytes("\ufeffWheel Travel [mm], Toe [deg] ,wheel-centre-lateral [mm]\r\n"
                  "0,0,0\r\n90,0.1,1\r\n-90,-0.1,-1\r\n\r\n".encode())
    t = read_kc_test(p)
    assert t.load_case == "parallel_travel"  # from the file name
    assert list(t.channels) == ["wheel_travel", "toe", "wheel_centre_lateral"]
    assert t.notes == [] and t.warnings == []


# --------------------------------------------------------------------------- load case


def test_load_case_from_comment_or_file_name(tmp_path):
    body = "lateral_force [N],toe [deg]\n0,0\n100,0.01\n"
    assert read_kc_test(put(tmp_path, "run7.csv", "# load_case: lateral_force\n" + body)) \
        .load_case == "lateral_force"
    assert read_kc_test(put(tmp_path, "fl_lateral_force.csv", body)).load_case \
        == "lateral_force"
    fails(put(tmp_path, "run8.csv", body), "cannot tell the load case", "# load_case:")
    fails(put(tmp_path, "run9.csv", "# load_case: cornering\n" + body),
          "line 1", "unknown load case 'cornering'", "parallel_travel")
    fails(put(tmp_path, "vertical_force.csv", "# load_case: lateral_force\n" + body),
          "contradicts the file name", "'vertical_force'")
    fails(put(tmp_path, "run10.csv", "# load_case: lateral_force\n# load_case: lateral_force\n"
              + body), "line 2", "second '# load_case:'")


# ---------------------------------------------------------------------------- errors


def test_missing_required_channel(tmp_path):
    p = put(tmp_path, "parallel_travel.csv",
            "# rig: test\nwheel_travel [mm],camber [deg]\n0,0\n90,1\n")
    fails(p, "load case 'parallel_travel'", "'toe [deg]'", "wheel_travel [mm], camber [deg]")


def test_wrong_input_column(tmp_path):
    p = put(tmp_path, "parallel_travel.csv", "toe [deg],wheel_travel [mm]\n0,0\n0.1,90\n")
    fails(p, "input channel 'wheel_travel [mm]' as the first column", "'toe [deg]'")


@pytest.mark.parametrize("column,fragments", [
    ("toe [mm]", ("column 2 'toe [mm]'", "unit 'mm' is not a unit of angle",
                  "'toe [deg]'", "deg, rad")),
    ("toe [N]", ("column 2 'toe [N]'", "unit 'N' is not a unit of angle")),
    ("toe", ("column 2 'toe'", "no unit", "'toe [deg]'")),
    ("toe []", ("column 2 'toe []'", "no unit")),
    ("toe (deg)", ("column 2 'toe (deg)'", "square brackets", "'toe [deg]'")),
    ("toe [deg] [rad]", ("column 2 'toe [deg] [rad]'", "malformed column name")),
])
def test_bad_unit(tmp_path, column, fragments):
    p = put(tmp_path, "lateral_force.csv", f"lateral_force [N],{column}\n0,0\n10,1\n")
    fails(p, *fragments)
    p = put(tmp_path, "lateral_force.csv", "lateral_force [deg],toe [deg]\n0,0\n10,1\n")
    fails(p, "column 1 'lateral_force [deg]'", "not a unit of force", "N, kN")


@pytest.mark.parametrize("cell,fragment", [
    ("abc", "'abc' is not a number"),
    ("", "empty cell"),
    ("nan", "'nan' is not a finite number"),
    ("1,5", "4 cells, the header has 3 columns"),
])
def test_bad_cell(tmp_path, cell, fragment):
    p = put(tmp_path, "lateral_force.csv",
            "# two comment lines\n# before the header\n"
            f"lateral_force [N],toe [deg],camber [deg]\n0,0,0\n100,{cell},0\n200,0,0\n")
    msg = fails(p, "line 5", fragment)
    if "cells" not in fragment:
        assert "(data row 2), column 'toe [deg]'" in msg


def test_other_malformed_files(tmp_path):
    fails(put(tmp_path, "lateral_force.csv", "# only comments\n\n"), "no header row")
    fails(put(tmp_path, "lateral_force.csv", "lateral_force [N];toe [deg]\n0;0\n"),
          "line 1", "separated by ';'")
    fails(put(tmp_path, "lateral_force.csv", "lateral_force [N],toe [deg],toe [rad]\n0,0,0\n"),
          "column 3 'toe [rad]'", "appears twice", "column 2")
    fails(put(tmp_path, "lateral_force.csv", "lateral_force [N],toe [deg],\n0,0,\n"),
          "column 3", "empty column name")
    fails(put(tmp_path, "lateral_force.csv", "lateral_force [N],toe [deg]\n0,0\n# late\n1,0\n"),
          "line 3", "only before the header")
    fails(put(tmp_path, "lateral_force.csv", "lateral_force [N],toe [deg]\n0,0\n"),
          "1 data row(s)", "at least 2")
    fails(put(tmp_path, "lateral_force.csv", "lateral_force [N],toe [deg]\n5,0\n5,1\n"),
          "column 'lateral_force [N]'", "constant")
    bad = tmp_path / "lateral_force.csv"
    bad.write_bytes(b"lateral_force [N],toe [\xb0]\n0,0\n1,1\n")  # latin-1 degree sign
    fails(bad, "not UTF-8")
    fails(tmp_path / "absent_lateral_force.csv", "cannot read")


# ------------------------------------------------------------------ monotonic branches


def file_with_input(tmp_path, x):
    rows = "\n".join(f"{float(v)!r},0" for v in x)
    return put(tmp_path, "lateral_force.csv", f"lateral_force [N],toe [deg]\n{rows}\n")


def test_loading_and_unloading_accepted(tmp_path):
    for x in (np.linspace(0, 2000, 11),                      # one branch
              np.r_[np.linspace(1000, 7500, 14), np.linspace(7500, 1000, 14)[1:]],  # two
              sweep(2000.0)):                                 # three
        t = read_kc_test(file_with_input(tmp_path, x))
        assert len(t.branches) == len(monotonic_branches(x)) + 1 <= MAX_BRANCHES


def test_back_step_is_rejected_and_jitter_accepted(tmp_path):
    x = sweep(2000.0)  # range 4000 N: the tolerance is 40 N
    back = x.copy()
    back[5] = back[4] - 50.0  # a 50 N back-step on the loading branch (line 7 of the file)
    msg = fails(file_with_input(tmp_path, back), "column 'lateral_force [N]'", "not monotonic",
                "reverses at lines 6, 7, 22, 62", "5 monotonic branches", "at most 3")
    assert "1% of the input range" in msg
    jitter = x.copy()
    jitter[5] = jitter[4] - 30.0  # a 30 N back-step: jitter
    assert len(read_kc_test(file_with_input(tmp_path, jitter)).branches) == 3
    # the tolerance is a parameter
    with pytest.raises(MeasurementError, match="reversals up to 0.5%"):
        read_kc_test(file_with_input(tmp_path, jitter), jitter_tolerance=0.005)


@given(legs=st.integers(1, 5), data=st.data())
@settings(max_examples=100, deadline=None)
def test_branches_found_through_jitter(legs, data):
    # piecewise-linear sweep through alternating waypoints, each leg >= 20 % of the range, plus
    # noise below half the jitter tolerance: exactly legs - 1 turning points, each within one
    # sample of a true waypoint
    lengths = data.draw(st.lists(st.floats(0.2, 1.0), min_size=legs, max_size=legs))
    sign = data.draw(st.sampled_from([1.0, -1.0]))
    way = [0.0]
    for k, length in enumerate(lengths):
        way.append(way[-1] + sign * (-1) ** k * length)
    pieces = [np.linspace(a, b, 25)[1:] for a, b in zip(way[:-1], way[1:])]
    x = np.r_[0.0, *pieces]
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    x = x + rng.uniform(-0.004, 0.004, x.size) * np.ptp(x)
    turns = monotonic_branches(x, 0.01)
    assert len(turns) == legs - 1
    for k, i in enumerate(turns, start=1):
        assert abs(i - 24 * k) <= 1


# --------------------------------------------------------------------------------- writer


def test_writer_checks(tmp_path):
    p = tmp_path / "w.csv"
    x = sweep(90.0, 5)
    with pytest.raises(MeasurementError, match="unknown load case 'bump'"):
        write_kc_test(p, "bump", {"wheel_travel": x, "toe": x})
    with pytest.raises(MeasurementError, match="needs channel.*toe"):
        write_kc_test(p, "parallel_travel", {"wheel_travel": x})
    with pytest.raises(MeasurementError, match="'toe' has 3 values"):
        write_kc_test(p, "parallel_travel", {"wheel_travel": x, "toe": [0.0, 1.0, 2.0]})
    with pytest.raises(MeasurementError, match="not monotonic"):
        write_kc_test(p, "parallel_travel", {"wheel_travel": np.r_[x, x], "toe": np.r_[x, x]})
    with pytest.raises(MeasurementError, match="convert the values"):
        write_kc_test(p, "parallel_travel", {"wheel_travel": x, "toe": x}, units={"toe": "rad"})
    with pytest.raises(MeasurementError, match="channel name 'Toe Angle'"):
        write_kc_test(p, "parallel_travel", {"wheel_travel": x, "toe": x, "Toe Angle": x})
    with pytest.raises(MeasurementError, match="read as the load case"):
        write_kc_test(p, "parallel_travel", {"wheel_travel": x, "toe": x},
                      notes=["load_case: lateral_force"])
    assert not p.exists()
