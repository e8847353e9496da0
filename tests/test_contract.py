"""One contract over every model variant and every load case (as scikit-learn's
``parametrize_with_checks``): a new variant is tested by adding one line to ``VARIANTS``.

Each (variant, load case) pair checks the same invariants: the sweep has the drive's step count
and branch labels, every column has a unit in the channel table, the zero-input steps are the
static state, a repeated run gives identical numbers, the suspension is not mutated, results
pickle (for dask); and, on the nominal pseudo-McPherson and the double wishbone, toe, camber and
travel do not depend on the side (left/right mirror) or on the frame (ISO 8855 or ADAMS/Car).
The rig is each config's in few, large steps, so that the whole contract runs in seconds. The
shipped axle kinds (multi-link, semi-trailing arm, solid axles, the HMMWV's rear double
wishbone, the push-rod axle) are variants too; the solid axle with a Panhard rod (one shared
part carrying both wheels, items on both sides) and the push-rod axle (a heave spring joining
the two sides' rockers) are mirrored and turned into the other frame as well.
"""

from __future__ import annotations

import copy
import dataclasses
import pickle
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from elastokin.config.loading import read_yaml, suspension_from_dict
from elastokin.config.variants import DesignState, ModelVariant, kinematic
from elastokin.mbs.design import build_model, design_state
from elastokin.rig.channels import LOAD_CASES, channel
from elastokin.rig.load_cases import drives, run_drive, run_drive_sides, static_equilibrium

from .conftest import CASE

DW = Path(__file__).parent / "data" / "double_wishbone.yaml"
CONFIGS = Path(__file__).resolve().parents[1] / "configs"
TWIST_BEAM = CONFIGS / "twist_beam_axle.yaml"
#: the shipped axle kinds of issue 25 (tests/test_kinds.py checks their results)
KINDS = {"multilink": CONFIGS / "multilink_axle.yaml",
         "semi_trailing_arm": CONFIGS / "semi_trailing_arm_axle.yaml",
         "solid_axle_panhard": CONFIGS / "solid_axle_panhard.yaml",
         "solid_axle_watt": CONFIGS / "solid_axle_watt.yaml",
         "double_wishbone_rear": CONFIGS / "double_wishbone_rear_axle.yaml",
         "fsae_pushrod": CONFIGS / "fsae_pushrod_axle.yaml"}


def coarse_rig(data: dict) -> dict:
    """The config's rig (its ranges: each suspension has its own) in few, large steps."""
    from elastokin.config.schema.rig import RigSpec

    rig = RigSpec.model_validate(data.get("rig") or {}).model_dump()
    travel, vertical = rig["parallel_travel"], rig["vertical_force"]
    travel["step_mm"] = (travel["bump_mm"] - travel["rebound_mm"]) / 8
    if vertical is not None:
        vertical["step_N"] = (vertical["max_N"] - vertical["min_N"]) / 8
    for case in ("lateral_force", "longitudinal_force_patch", "longitudinal_force_centre"):
        if rig[case] is not None:
            rig[case]["step_N"] = rig[case]["amplitude_N"] / 4
    if rig["aligning_torque"] is not None:
        rig["aligning_torque"]["step_Nmm"] = rig["aligning_torque"]["amplitude_Nmm"] / 4
    return rig


def nominal_data(path: Path = CASE) -> dict:
    data = copy.deepcopy(read_yaml(path)[0])
    data.pop("measurements", None)
    data.pop("kc_test", None)
    data["rig"] = coarse_rig(data)
    return data


def with_coarse_rig(data: dict) -> dict:
    return {**data, "rig": coarse_rig(data)}


def nominal(path: Path = CASE):
    return suspension_from_dict(nominal_data(path), str(path))


# ------------------------------------------------------------------------- the variants
def _identified():
    from elastokin.studies.identification import identified_suspension, identify_geometry

    ident = identify_geometry(suspension_from_dict(
        with_coarse_rig(read_yaml(CASE)[0]), str(CASE)), verify=False)
    return ModelVariant("identified", identified_suspension(ident))


def _as_built():
    from elastokin.synthetic.virtual_cmm import as_built, clearance_shifts

    s = suspension_from_dict(with_coarse_rig(read_yaml(CASE)[0]), str(CASE))
    ab = as_built(s, clearance_shifts(s, np.random.default_rng(7)))
    return ModelVariant("as_built", ab.suspension,
                        DesignState(ab.spring_force_N, ab.bushing_preload))


def _fitted_stiffness():
    from elastokin.identification.stiffness import with_stiffness

    s = nominal()
    values = {"J1": {"translation_scale": 1.3, "translation_cubic": 0.01},
              "J4": {"rotation_scale": 0.8}}
    return ModelVariant("fitted_stiffness", with_stiffness(s, values), design_state(s))


def _friction():
    from elastokin.synthetic.real_suspension import real_suspension_variant

    variant = real_suspension_variant(suspension_from_dict(
        with_coarse_rig(read_yaml(CASE)[0]), str(CASE)))
    # one solver step per rig step (the shipped 4 follow the slip more finely): the contract's
    # invariants do not depend on it, and the friction model solves step by step (slow)
    return dataclasses.replace(variant, friction=dataclasses.replace(variant.friction,
                                                                     substeps=1))


def _imported_from_adams(tmp_path_factory=None):
    import tempfile

    from click.testing import CliRunner

    from elastokin.cli.main import main

    folder = Path(tempfile.mkdtemp(prefix="elastokin-contract-"))
    config = folder / "nominal.yaml"
    import yaml

    config.write_text(yaml.safe_dump(nominal_data()))
    out = folder / "adams"
    result = CliRunner().invoke(main, ["export-adams", "--config", str(config), "--out",
                                       str(out)])
    assert result.exit_code == 0, result.output
    imported = folder / "imported.yaml"
    result = CliRunner().invoke(main, [
        "import-adams", "--hardpoints", str(next(out.glob("*.tbl"))), "--mapping",
        str(out / "mapping.yaml"), "--template", str(config), "--out", str(imported)])
    assert result.exit_code == 0, result.output
    from elastokin.config.loading import load_suspension

    return ModelVariant("imported_from_adams", load_suspension(imported))


VARIANTS = {
    "nominal": lambda: ModelVariant("nominal", nominal()),
    "kinematic": lambda: ModelVariant("kinematic", kinematic(nominal())),
    "identified": _identified,
    "as_built": _as_built,
    "fitted_stiffness": _fitted_stiffness,
    "friction": _friction,
    "imported_from_adams": _imported_from_adams,
    "double_wishbone": lambda: ModelVariant("double_wishbone", nominal(DW)),
    "twist_beam": lambda: ModelVariant("twist_beam", nominal(TWIST_BEAM)),
    **{name: (lambda name=name, path=path: ModelVariant(name, nominal(path)))
       for name, path in KINDS.items()},
}
_BUILT: dict[str, tuple] = {}


def built(name: str):
    """(variant, model, pickled suspension before any run), built once per session."""
    if name not in _BUILT:
        v = VARIANTS[name]()
        _BUILT[name] = (v, build_model(v), pickle.dumps(v.suspension))
    return _BUILT[name]


PAIRS = [(v, case) for v in VARIANTS for case, spec in LOAD_CASES.items() if spec.corner]


@pytest.mark.parametrize("name, case", PAIRS)
def test_contract(name, case):
    variant, model, before = built(name)
    drive = next((d for d in drives(variant.suspension, kinematic=variant.kinematic)
                  if d.load_case == case), None)
    if drive is None:
        assert variant.kinematic and not LOAD_CASES[case].vertical, (name, case)
        return  # a kinematic model runs the vertical cases only (documented)
    sweep = run_drive(model, name, drive)
    # step count and branch labels: the drive's
    assert sweep.steps == drive.inputs.size
    assert list(sweep.columns["branch"]) == list(drive.branch)
    assert sweep.model == name and sweep.load_case == case
    # a unit on every column (the channel table knows each one)
    for col, values in sweep.columns.items():
        if col == "branch":
            continue
        ch = channel(col)
        assert ch is not None and ch.unit, col
        assert len(values) == sweep.steps, col
    # zero input (the design wheel load alone) is the static state: the wheel centre there is
    # the static equilibrium's (1e-5 mm: the Newton tolerance, 1e-8 of a ~4 kN residual, over
    # a ~20 N/mm wheel rate is 2e-6 mm; 2.5e-6 measured). Not for the friction model, whose
    # state there depends on the path (hysteresis: 0.19 mm measured under vertical force)
    static = static_equilibrium(model).state.wheel_centre_mm
    x = sweep.columns[drive.input_column]
    zero = np.flatnonzero(x == 0.0) if case != "vertical_force" else np.flatnonzero(
        np.isclose(x, variant.suspension.design.wheel_load_N))
    if case != "parallel_travel" and zero.size and variant.friction is None:
        centre = np.array([sweep.columns[f"wheel_centre_{a}_mm"][zero[-1]] for a in "xyz"])
        assert np.linalg.norm(centre - static) < 1e-5, (name, case, centre - static)
    # repeated runs are identical, bit for bit
    again = run_drive(model, name, drive)
    for col, values in sweep.columns.items():
        assert np.array_equal(values, again.columns[col], equal_nan=col != "branch"), col
    # the suspension is not mutated; results pickle (dask ships them between processes)
    assert pickle.dumps(variant.suspension) == before
    back = pickle.loads(pickle.dumps(sweep))
    assert back.columns.keys() == sweep.columns.keys()


# ------------------------------------------------------------------------- mirror and frame
def _transform_config(data: dict, M: np.ndarray, side: str | None, frame: dict | None) -> dict:
    """The config with every point and direction mapped by M (3x3, det +-1); bushing frames
    kept right-handed (for a mirror, y column flipped); side and frame replaced."""
    d = copy.deepcopy(data)
    d["hardpoints"] = {k: (M @ np.asarray(v, float)).tolist()
                       for k, v in d["hardpoints"].items()}
    flip = np.diag([1.0, np.linalg.det(M), 1.0])

    def vec(v):
        return v if isinstance(v, dict) else (M @ np.asarray(v, float)).tolist()

    for c in d["connections"].values():
        for key in ("axis", "radial", "torsion_axis"):
            if key in c:
                c[key] = vec(c[key])
        for key in ("at",):
            if isinstance(c.get(key), list) and c[key] and not isinstance(c[key][0], str):
                c[key] = vec(c[key])
        if "euler_zxz_deg" in c:
            B = Rotation.from_euler("ZXZ", c["euler_zxz_deg"], degrees=True).as_matrix()
            c["euler_zxz_deg"] = Rotation.from_matrix(M @ B @ flip).as_euler(
                "ZXZ", degrees=True).tolist()
    d["wheel"]["spin_axis"] = vec(d["wheel"]["spin_axis"])
    if side and side != d["side"]:  # an item across the car names the other side's copies
        old, new = (f"_{other}" for other in (side, d["side"]))
        for section in ("springs", "dampers"):
            for item in (d.get(section) or {}).values():
                for key in ("parts", "seats", "points"):
                    if key in item:
                        item[key] = [new.join(p.rsplit(old, 1)) if isinstance(p, str)
                                     and p.endswith(old) else p for p in item[key]]
    if side:
        d["side"] = side
    if frame:
        d["frame"] = frame
    return d


def _vehicle_columns(data: dict):
    """Every load case's sweeps by (load case, wheel side)."""
    s = suspension_from_dict(data, "mirror.yaml")
    model = build_model(s)
    return {(d.load_case, sw.side): sw for d in drives(s)
            for sw in run_drive_sides(model, "m", d)}


@pytest.fixture(scope="module", params=[CASE, DW, KINDS["solid_axle_panhard"],
                                        KINDS["fsae_pushrod"]],
                ids=["pseudo_mcpherson", "double_wishbone", "solid_axle_panhard",
                     "fsae_pushrod"])
def mirror_sets(request):
    data = nominal_data(request.param)
    if request.param == KINDS["fsae_pushrod"]:  # its axle cases in few steps too
        travel = {"rebound_mm": -25.0, "bump_mm": 25.0, "step_mm": 12.5}
        data["rig"].update(opposite_travel=travel, single_wheel_travel=travel,
                           roll_vertical_force={"amplitude_deg": 1.5, "step_deg": 0.75},
                           steering={"amplitude_deg": 180.0, "step_deg": 90.0})
    other_side = "right" if data["side"] == "left" else "left"
    mirror = np.diag([1.0, -1.0, 1.0])
    turn = np.diag([-1.0, -1.0, 1.0])  # ISO 8855 <-> ADAMS/Car: x and y reversed
    other_frame = ({"x": "forward", "y": "left", "z": "up"} if data["frame"]["x"] == "rearward"
                   else {"x": "rearward", "y": "right", "z": "up"})
    return {"original": _vehicle_columns(data),
            "mirrored": _vehicle_columns(_transform_config(data, mirror, other_side, None)),
            "other_frame": _vehicle_columns(_transform_config(data, turn, None, other_frame)),
            # one Panhard rod across the car: its mirror image is another axle
            "asymmetric": request.param == KINDS["solid_axle_panhard"]}


@pytest.mark.parametrize("which", ["mirrored", "other_frame"])
def test_side_and_frame_invariance(mirror_sets, which):
    """Per-wheel quantities (toe, camber, travel) and vehicle-axis quantities (longitudinal)
    are the same in the other frame, and on the mirrored config: a mirrored axle is the same
    axle (every wheel, every load case, its right corner now the config's); a mirrored corner
    is the other side's corner, whose lateral quantities in the vehicle's axes flip sign (the
    mirror of a lateral force or aligning torque to the vehicle's left is one to its right:
    those cases are compared in the other frame only). So is an asymmetric axle's mirror (the
    Panhard rod's chassis end on the other side): each wheel is the original's other wheel,
    mirrored, in the corner load cases. 1e-7: Newton tolerance of each solve."""
    a, b = mirror_sets["original"], mirror_sets[which]
    axle = {side for _, side in a} == {"left", "right"}
    other_wheel = which == "mirrored" and (not axle or mirror_sets["asymmetric"])
    sign = -1.0 if other_wheel else 1.0
    for (case, side), sw in a.items():
        if other_wheel and (case in ("lateral_force", "aligning_torque")
                            or not LOAD_CASES[case].corner):
            continue
        mirrored_side = "right" if not axle else {"left": "right", "right": "left"}[side]
        other = b[(case, mirrored_side if other_wheel else side)]
        for col in ("toe_deg", "camber_deg", "wheel_travel_mm", "wheel_centre_longitudinal_mm"):
            np.testing.assert_allclose(other.columns[col], sw.columns[col], atol=1e-7,
                                       err_msg=f"{case} {side} {col}")
        np.testing.assert_allclose(other.columns["wheel_centre_lateral_mm"],
                                   sign * sw.columns["wheel_centre_lateral_mm"], atol=1e-7,
                                   err_msg=f"{case} {side} lateral")
