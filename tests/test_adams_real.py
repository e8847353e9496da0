"""Real ADAMS files (not written by elastokin) read by elastokin's TeimOrbit reader: every one
reads (or is refused with a clear reason), hardpoints and values come out as an independent
line-by-line parse gives them, left/right blocks stay apart, and an imported real subsystem
exported again reads back to the same model.

Files: tests/data/adams/real/ (Adams Drill property files, MIT, see its SOURCES.md), and the
Adams/Car files of ../shared/adams_real/ beside the repository when it is there (no stated
licence: read in place, never copied; skipped when absent)."""

import copy
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

from elastokin.config.loading import read_yaml, suspension_from_dict
from elastokin.errors import ConfigError
from elastokin.formats.adams import car as adams_car
from elastokin.formats.adams import export as adams_export
from elastokin.formats.adams import teimorbit
from elastokin.formats.adams.assemblies import read_spring_assemblies
from elastokin.formats.adams.mapping import read_mapping

DATA = Path(__file__).parent / "data"
REAL = DATA / "adams" / "real"
SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "adams_real"
OURS = sorted(p for p in REAL.iterdir() if p.name != "SOURCES.md")
#: the shared files not also copied here
SHARED_FILES = sorted(p for p in SHARED.glob("*/*") if p.name != "SOURCE.txt"
                      and p.name not in {q.name for q in OURS}) if SHARED.is_dir() else []
FILES = OURS + SHARED_FILES
#: files that are not TeimOrbit files, and the reason they are refused
REFUSED = {"camelot_1_pull0_offset0.req": "comes before the first [BLOCK] header (expected "
                                          "[NAME]): not a TeimOrbit file? (its text is not "
                                          "shown)"}
FSAE = SHARED / "zbingf_fsae_front_susp_sub" / "fsae_front_susp.sub"
needs_shared = pytest.mark.skipif(not FSAE.is_file(), reason="../shared/adams_real is absent")


# ----------------------------------------------------------------------------------------------
# An independent parse: plain regular expressions over the lines, nothing shared with the reader


def _independent(path: Path) -> list[tuple[str, dict[str, object], list[list[str]]]]:
    """(block name, KEY -> value of its block-level and sub-block keys, last wins; table rows
    as token lists) for every block, by regular expressions alone."""
    blocks = []
    for raw in path.read_text(encoding="utf-8", errors="replace").splitlines():
        line = re.match(r"((?:[^'$]|'[^']*')*)", raw).group(1).strip()  # to an unquoted $
        m = re.fullmatch(r"\[\s*(.+?)\s*\]", line)
        if m:
            blocks.append((m.group(1).upper(), {}, []))
            continue
        if not line or not blocks or line.startswith(("(", "{")):
            continue
        m = re.fullmatch(r"(\w+)\s*=\s*(?:'([^']*)'|(\S+)).*", line)
        if m:
            blocks[-1][1][m.group(1).upper()] = (m.group(2).strip() if m.group(2) is not None
                                                 else _number(m.group(3)))
        else:
            blocks[-1][2].append(re.findall(r"'[^']*'|\S+", line))
    return blocks


def _number(text: str):
    try:
        return float(text.replace("D", "E").replace("d", "e"))
    except ValueError:
        return text


def _ours(path: Path) -> list[tuple[str, dict[str, object], int]]:
    f = teimorbit.read_teimorbit(path, convert=False)
    out = []
    for b in f.blocks:
        entries = {}
        for section in (b, *b.sub_blocks):
            entries.update({k: e.value for k, e in section.entries.items()})
        rows = sum(len(t.rows) + len(t.descriptions) for s in (b, *b.sub_blocks)
                   for t in s.tables)
        out.append((b.name, entries, rows))
    return out


# ----------------------------------------------------------------------------------------------
# Every real file


@pytest.mark.parametrize("path", FILES, ids=[p.name for p in FILES])
def test_every_real_file_reads_or_is_refused_with_its_reason(path):
    if path.name in REFUSED:
        with pytest.raises(ConfigError) as exc:
            teimorbit.read_teimorbit(path)
        msg = str(exc.value)
        assert REFUSED[path.name] in msg and msg.startswith(f"{path}, line 1: ") and \
            "\n" not in msg
        return
    f = teimorbit.read_teimorbit(path)
    assert f.blocks
    for w in f.warnings:  # tolerated things are named by file and line
        assert w.startswith(f"{path}, line ") and "\n" not in w


def test_count_of_real_files_read_and_refused():
    read, refused = [], []
    for path in FILES:
        try:
            teimorbit.read_teimorbit(path)
            read.append(path.name)
        except ConfigError as exc:
            refused.append((path.name, str(exc)))
    assert [name for name, _ in refused] == [n for n in REFUSED if n in {p.name for p in FILES}]
    assert len(read) == len(FILES) - len(refused) >= 5
    if SHARED_FILES:  # the measure of issue 16: 9 real files read, 1 refused (not TeimOrbit)
        assert (len(read), len(refused)) == (9, 1)


@pytest.mark.parametrize("path", [p for p in FILES if p.name not in REFUSED],
                         ids=[p.name for p in FILES if p.name not in REFUSED])
def test_values_as_an_independent_parse_gives_them(path):
    theirs = _independent(path)
    ours = _ours(path)
    assert [b for b, _, _ in ours] == [b for b, _, _ in theirs]
    for (name, entries, rows), (_, their_entries, their_rows) in zip(ours, theirs):
        assert entries == their_entries, name
        assert rows == len(their_rows), name


def test_tolerated_real_forms():
    """What MSC's own files do that a strict reader refused (issue 16)."""
    hol = teimorbit.read_teimorbit(REAL / "test_hole.hol")
    assert hol.units.time == "seconds" and hol.units.length == "foot"
    diameter = hol.block("DIAMETER").tables[0]
    assert diameter.rows == [(-1.0, 1.0835)]
    assert diameter.notes == {0: "<- use this format for constant values"}
    assert any("free text after the values" in w for w in hol.warnings)
    mot = teimorbit.read_teimorbit(REAL / "example_motor.mot")
    assert mot.block("3D").value("MAXFLOW") == 900.0
    ssf = teimorbit.read_teimorbit(REAL / "test_solver_settings_2.ssf")
    assert ssf.block("STATICS").value("TLIMIT") == 2.0  # the last value, with a warning
    assert any("TLIMIT is given again (first at line 19)" in w for w in ssf.warnings)
    evt = teimorbit.read_teimorbit(REAL / "test_event.evt")
    assert evt.units == teimorbit.Units("foot", "pound_force", "degrees", "pound_mass",
                                        "second")
    pdc = teimorbit.read_teimorbit(REAL / "test_pdc.pdc")
    assert pdc.block("ADAMS_DRILL_HEADER").value("MANUFACTURER") == ""
    blades = pdc.block("BLADES").tables[0]  # radius: a length column, foot -> mm
    assert blades.column("radius")[0] == pytest.approx(0.35 * 304.8)


# ----------------------------------------------------------------------------------------------
# The real Adams/Car subsystem and assemblies (../shared/adams_real)


@needs_shared
def test_real_subsystem_hardpoints_as_an_independent_parse_gives_them():
    points = adams_car.read_hardpoints(FSAE)
    rows = [r for b, _, rs in _independent(FSAE) if b == "HARDPOINT" for r in rs]
    assert len(points) == len(rows) == 17
    for name, sym, x, y, z in rows:
        hp = points[name.strip("'").strip()]
        assert hp.symmetry == sym.strip("'").strip()
        assert hp.position_mm == (float(x), float(y), float(z))
    assert points["wheel_center"].at("right").tolist() == [-512.0, 700.0, 155.2]


@needs_shared
def test_real_subsystem_left_and_right_spring_blocks_stay_apart():
    springs = read_spring_assemblies(FSAE)
    ride = springs["ride_spring"]
    assert ride["left"].values["USER_VALUE"] == 189.5
    assert ride["right"].values["USER_VALUE"] == 2000.0
    assert ride["left"].property_file == "mdids://fsae_2012/springs.tbl/msc_0001.spr"
    assert springs["ride_spring1"]["left"] is springs["ride_spring1"]["right"]
    assert set(springs["ride_spring5"]) == {"single"}


@needs_shared
@pytest.mark.parametrize("name", ["zbingf_asy_file_test_asy/asy_file_test.asy",
                                  "zbingf_fsae_full_vehicle_asy/fsae_full_vehicle.asy",
                                  "zbingf_MDI_Demo_Vehicle_asy/MDI_Demo_Vehicle.asy"])
def test_real_assembly_parameter_tables_with_description_rows(name):
    f = teimorbit.read_teimorbit(SHARED / name)
    (table,) = f.block("PARAMETER").tables
    assert table.columns == ("parameter_name", "symmetry", "type", "value")
    assert len(table.rows) == 8
    names = table.column("parameter_name")
    assert names[0] == "initial_engine_rpm" and table.rows[0][3] == 2000.0
    if "MDI_Demo" not in name:
        assert table.descriptions[names.index("rack_ratio")] == \
            "swa to rack displacement ratio in S.I. (rad/meter)"
    assert adams_car.read_hardpoints(SHARED / name)["upright_reference"].symmetry == \
        "left/right"


FSAE_MAPPING = {
    "elastokin_adams_mapping": 1,
    "subsystem": {"template": "mdids://fsae_2012/templates.tbl/_fsae_frontsusp.tpl",
                  "major_role": "suspension", "minor_role": "front"},
    "hardpoints": {"lca_front": "lca_front", "lca_rear": "lca_rear", "lca_outer": "lca_outer",
                   "uca_front": "uca_front", "uca_rear": "uca_rear", "uca_outer": "uca_outer",
                   "rack_end": "tierod_inner", "tierod_outer": "tierod_outer",
                   "wheel_centre": "wheel_center", "spring_lower": "prod_outboard",
                   "spring_upper": "damper_inboard"},
}


@needs_shared
def test_real_subsystem_import_export_reads_back_to_the_same_model(tmp_path):
    """Import the FSAE subsystem onto the double wishbone, export it with the same mapping
    (template names, template, roles), import the export back: the same model; the exported
    hardpoints are the real file's."""
    mapping = tmp_path / "fsae.yaml"
    mapping.write_text(yaml.safe_dump(FSAE_MAPPING))
    template = read_yaml(DATA / "double_wishbone.yaml")[0]
    cfg, _ = adams_car.import_adams(template, FSAE, mapping)
    s = suspension_from_dict(cfg, "imported.yaml")
    zero = {b.name: np.zeros(6) for b in s.bushings}
    adams_export.export_adams(s, tmp_path / "fsae.cdb", zero, mapping=read_mapping(mapping))
    (sub,) = (tmp_path / "fsae.cdb" / "subsystems.tbl").glob("*.sub")
    head = teimorbit.read_teimorbit(sub).block("SUBSYSTEM_HEADER")
    assert head.value("TEMPLATE_NAME") == FSAE_MAPPING["subsystem"]["template"]
    real, ours = adams_car.read_hardpoints(FSAE), adams_car.read_hardpoints(sub)
    for adams_name in FSAE_MAPPING["hardpoints"].values():
        assert ours[adams_name].position_mm == real[adams_name].position_mm, adams_name
    scrambled = copy.deepcopy(template)
    scrambled["hardpoints"] = {k: [v[0] + 3.0, v[1], v[2]] for k, v in
                               template["hardpoints"].items()}
    back, warnings = adams_car.import_adams(scrambled, tmp_path / "fsae.cdb",
                                            tmp_path / "fsae.cdb" / "mapping.yaml")
    assert back["hardpoints"] == cfg["hardpoints"]
    assert back["connections"]["lca_bushing"]["stiffness"]["rz"] == \
        cfg["connections"]["lca_bushing"]["stiffness"]["rz"]
    b0, b1 = s.bushings[0], suspension_from_dict(back, "back.yaml").bushings[0]
    x = np.linspace(-40.0, 40.0, 161)
    for law0, law1 in zip(b0.laws, b1.laws):
        np.testing.assert_allclose(law1(x), law0(x), rtol=1e-12, atol=1e-9)
