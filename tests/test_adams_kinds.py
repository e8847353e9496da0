"""ADAMS/Car files of the shipped axle kinds (issue 25): each exports as ADAMS/Car keeps it and
imports back onto a template whose every hardpoint and bushing rate was changed, giving back
the hardpoints to the bit, the laws to 1e-12 and the axle section unchanged. Items kept once
on an axle (a Panhard rod, a Watt's linkage, a planar guide) are ADAMS/Car's ``single`` rows
and blocks; the items on both sides (a solid axle's springs) ``left/right`` ones."""

from pathlib import Path

import numpy as np
import pytest

from elastokin.config.loading import read_yaml, suspension_from_dict
from elastokin.formats.adams import car as adams_car
from elastokin.formats.adams.assemblies import read_bushing_assemblies, read_spring_assemblies
from elastokin.formats.adams.export import export_adams, subsystem_spec
from elastokin.formats.adams.importing import import_adams_axle, subsystem_files
from elastokin.formats.adams.mapping import read_mapping
from elastokin.mbs.design import design_state

from .suspension_checks import assert_same_bushings, scrambled

CONFIGS = Path(__file__).resolve().parents[1] / "configs"
#: the kind's config and the ADAMS/Car template its subsystem names (docs/adams.md, "Kinds")
KINDS = {"multilink_axle.yaml": "_multi_link",
         "semi_trailing_arm_axle.yaml": "_semi_trailing_arm",
         "solid_axle_panhard.yaml": "_solid_axle",
         "solid_axle_watt.yaml": "_solid_axle",
         "double_wishbone_rear_axle.yaml": "_double_wishbone"}
#: ADAMS/Car symmetry of hardpoints and bushings that are not left/right pairs
SINGLE = {"solid_axle_panhard.yaml": {"axle_centre", "panhard_chassis", "panhard_axle",
                                      "panhard_chassis_bushing", "panhard_axle_bushing"},
          "solid_axle_watt.yaml": {"drawbar_front", "watt_upper_chassis", "watt_upper_centre",
                                   "watt_lower_chassis", "watt_lower_centre", "watt_pivot"}}


@pytest.mark.parametrize("name", KINDS)
def test_round_trip(tmp_path, name):
    data = read_yaml(CONFIGS / name)[0]
    s = suspension_from_dict(data, name)
    state = design_state(s)
    db = tmp_path / "kind.cdb"
    spec = subsystem_spec(s, None, "kind", template=KINDS[name])
    export_adams(s, db, state.bushing_preload, spring_force=state.spring_force_N, spec=spec,
                 timestamp="2024/01/01,00:00:00")
    mapping = read_mapping(db / "mapping.yaml")
    assert mapping.subsystem["template"] == \
        f"mdids://acar_shared/templates.tbl/{KINDS[name]}.tpl"
    sub = next(p for p in (db / "subsystems.tbl").glob("*.sub") if "antiroll" not in p.name)
    points = adams_car.read_hardpoints(sub)
    bushings = read_bushing_assemblies(sub)
    single = SINGLE.get(name, set())
    for n, p in points.items():
        assert p.symmetry == ("single" if n in single else "left/right"), n
    for n, sides in bushings.items():
        assert set(sides) == ({"single"} if n in single else {"left", "right"}), n
    assert set(read_spring_assemblies(sub)["coil"]) == {"left", "right"}
    cfg, warnings, _ = import_adams_axle(scrambled(data), subsystem_files(mapping, db),
                                         db / "mapping.yaml")
    assert warnings == []
    assert cfg["hardpoints"] == data["hardpoints"]  # ISO -> ADAMS -> ISO, to the bit
    assert cfg["axle"] == data["axle"]
    assert_same_bushings(s, suspension_from_dict(cfg, "imported.yaml"),
                         np.linspace(-20.0, 20.0, 81))
