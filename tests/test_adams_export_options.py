"""Export writes only what import reads (docs/adams.md, "elastokin export-adams"): every option
of ``export-adams`` gives a database that ``import-adams`` reads back onto a template whose
hardpoints and bushings were all changed, giving the exported hardpoints exactly and the laws to
1e-12, with the option's effect in the files; roles outside ADAMS/Car's role names, template
names that are not identifiers, names that ADAMS/Car files cannot carry are refused before
anything is written, naming the option or the mapping key."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.loading import load_suspension, read_yaml, suspension_from_dict

from .suspension_checks import assert_same_bushings, scrambled

DATA = Path(__file__).parent / "data"
WISHBONE = DATA / "double_wishbone.yaml"
MAPPING = DATA / "adams" / "double_wishbone_mapping.yaml"
CASE = Path(__file__).parents[1] / "configs" / "pseudo_mcpherson.yaml"


def kc_csv(tmp_path: Path) -> Path:
    path = tmp_path / "kc.csv"
    path.write_text("model,load_case,step,branch,toe_deg,wheel_centre_y_mm\n"
                    "initial,parallel_travel,1,stroke,0.25,780.0\n")
    return path


#: option -> (its arguments, the file of the database and the text it must hold)
OPTIONS = {
    "defaults": ([], "subsystems.tbl/*.sub",
                 "TEMPLATE_NAME  =  'mdids://out/templates.tbl/_generic_double_wishbone"),
    "template bare": (["--template-name", "_double_wishbone"], "subsystems.tbl/*.sub",
                      "'mdids://acar_shared/templates.tbl/_double_wishbone.tpl'"),
    "template path": (["--template-name", "mdids://my_db/templates.tbl/_dw2.tpl"],
                      "subsystems.tbl/*.sub", "'mdids://my_db/templates.tbl/_dw2.tpl'"),
    "major role": (["--major-role", "Suspension"], "subsystems.tbl/*.sub",
                   "MAJOR_ROLE     =  'suspension'"),
    "minor role rear": (["--minor-role", "rear"], "subsystems.tbl/*.sub",
                        "MINOR_ROLE     =  'rear'"),
    "minor role any": (["--minor-role", "any"], "subsystems.tbl/*.sub",
                       "MINOR_ROLE     =  'any'"),
    "database": (["--database", "front_db"], "subsystems.tbl/*.sub",
                 "'mdids://front_db/bushings.tbl/lca_bushing.bus'"),
    "ranges": (["--range-mm", "4", "--range-deg", "25"], "bushings.tbl/lca_bushing.bus",
               "-4.0"),
    "mapping": (["--mapping", str(MAPPING)], "subsystems.tbl/*.sub", "'wheel_center"),
    "kc": (["--kc", "{kc}"], "kc_adams.csv", "toe_angle"),
    "identified": (["--identified"], "bushings.tbl/J1.bus", "(identified)"),
}


@pytest.mark.parametrize("option", OPTIONS)
def test_every_export_option_reads_back(tmp_path, option):
    args, pattern, text = OPTIONS[option]
    args = [a.replace("{kc}", str(kc_csv(tmp_path))) for a in args]
    config = CASE if option == "identified" else WISHBONE
    out = tmp_path / "out"
    runner = CliRunner()
    r = runner.invoke(main, ["export-adams", "--config", str(config), "--out", str(out), *args])
    assert r.exit_code == 0, r.output
    (written,) = out.glob(pattern)
    assert text in written.read_text()
    data = read_yaml(config)[0]
    if option == "identified":  # the identified corner is what was exported
        from elastokin.identification.geometric import identify

        data = identify(load_suspension(config)).identified_config
    template = tmp_path / "template.yaml"
    template.write_text(yaml.safe_dump(scrambled(data), sort_keys=False))
    r = runner.invoke(main, ["import-adams", "--hardpoints", str(out), "--mapping",
                             str(out / "mapping.yaml"), "--template", str(template), "--out",
                             str(tmp_path / "back.yaml")])
    assert r.exit_code == 0, r.output
    back = load_suspension(tmp_path / "back.yaml")
    original = suspension_from_dict(data, "original.yaml")
    points = read_yaml(tmp_path / "back.yaml")[0]["hardpoints"]
    assert points.keys() == data["hardpoints"].keys()
    for name, xyz in data["hardpoints"].items():  # (pytest >= 9.2: no approx of nested dicts)
        np.testing.assert_allclose(points[name], xyz, rtol=0,
                                   atol=1e-9 if option == "identified" else 0.0, err_msg=name)
    assert_same_bushings(original, back, np.linspace(-20.0, 20.0, 81))


@pytest.mark.parametrize("args, words", [
    (["--template-name", "_dw'x"], "export-adams --template-name: template \"_dw'x\": "
                                   "expected a template name (an identifier"),
    (["--template-name", "mdids://db/templates.tbl/dw 2.tpl"], "--template-name: template"),
    (["--template-name", "mdids://db/bushings.tbl/_dw.tpl"], "--template-name: template"),
    (["--major-role", "body"], "export-adams --major-role: 'body' is not the major role of a "
                               "suspension subsystem (expected 'suspension'; ADAMS/Car's: "
                               "suspension, antirollbar, steering, wheel, body"),
    (["--major-role", "chassis"], "--major-role: 'chassis' is not"),
    (["--minor-role", "middle"], "export-adams --minor-role: 'middle' is not a minor role "
                                 "(expected front, rear, trailer, any"),
    (["--database", "my db"], "export-adams --database: 'my db' is not a name ADAMS/Car files "
                              "can carry"),
])
def test_export_options_ADAMS_cannot_read_are_refused(tmp_path, args, words):
    out = tmp_path / "out"
    r = CliRunner().invoke(main, ["export-adams", "--config", str(WISHBONE), "--out", str(out),
                                  *args])
    assert r.exit_code == 1 and r.output.count("\n") == 1, r.output
    assert words in r.output
    assert not out.exists()


@pytest.mark.parametrize("key, value, words", [
    ("subsystem", {"template": "_double'wishbone"}, "key 'subsystem.template': template"),
    ("subsystem", {"minor_role": "Front axle"}, "key 'subsystem.minor_role': 'Front axle' is "
                                                "not a minor role"),
    ("subsystem", {"major_role": "steering"}, "key 'subsystem.major_role': 'steering' is not "
                                              "the major role of a suspension subsystem"),
    ("subsystem", {"name": "front susp"}, "key 'subsystem.name': 'front susp' is not a name"),
    ("bushings", {"lca_bushing": {"usage": "lca bushing"}}, "key 'bushings.lca_bushing.usage'"),
    ("springs", {"coil": "coil'spring"}, "key 'springs.coil.usage'"),
])
def test_mapping_names_ADAMS_cannot_read_are_refused(tmp_path, key, value, words):
    data = yaml.safe_load(MAPPING.read_text())
    data.pop("bushings")
    data[key] = value
    mapping = tmp_path / "map.yaml"
    mapping.write_text(yaml.safe_dump(data))
    out = tmp_path / "out"
    r = CliRunner().invoke(main, ["export-adams", "--config", str(WISHBONE), "--out", str(out),
                                  "--mapping", str(mapping)])
    assert r.exit_code == 1 and r.output.count("\n") == 1, r.output
    assert f"{mapping}: {words}" in r.output
    assert not out.exists()
