"""Paths that one input file names on behalf of another stay inside the folders the user gave
(elastokin.config.confined; README "Which paths may point anywhere"; docs/adams.md "Paths
inside the database"): every path kind an ADAMS/Car database, a mapping file or a config can
name (``mdids://db/..``, ``<db>/..``, relative ``..``, ``\\`` separators, absolute, a link) is
refused with the file, line or key and the path, and the file outside is never opened:
``open`` and ``os.open`` are watched, and the outside file is a valid bushing file that the
import would otherwise take."""

from __future__ import annotations

import builtins
import contextlib
import io
import os
import shutil
import threading
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli.common import data_hint
from elastokin.cli.main import main
from elastokin.config.confined import data_folders
from elastokin.config.loading import load_suspension, read_yaml
from elastokin.errors import ConfigError
from elastokin.formats.adams.car import import_adams, read_hardpoints
from elastokin.formats.adams.importing import subsystem_files
from elastokin.formats.adams.mapping import read_mapping
from elastokin.formats.cmm_parts import measurement_paths
from elastokin.formats.kc_test_sweeps import read_test_sweeps
from elastokin.identification.geometric import identify

DATA = Path(__file__).parent / "data"
ADAMS = DATA / "adams"
WISHBONE = DATA / "double_wishbone.yaml"
CASE = Path(__file__).parents[1] / "configs" / "pseudo_mcpherson.yaml"
MARKER = "TOP-SECRET-7f3a"  # in every outside file: never in a message


@contextlib.contextmanager
def watching_opens():
    """Every file opened inside the block (builtins/io ``open``, ``os.open``: so
    ``Path.read_bytes`` too), resolved."""
    seen: list[Path] = []
    real_open, real_os_open = builtins.open, os.open

    def record(file):
        if isinstance(file, (str, bytes, os.PathLike)):
            seen.append(Path(os.fsdecode(file)).resolve())

    def watched_open(file, *args, **kwargs):
        record(file)
        return real_open(file, *args, **kwargs)

    def watched_os_open(path, *args, **kwargs):
        record(path)
        return real_os_open(path, *args, **kwargs)

    builtins.open = io.open = watched_open
    os.open = watched_os_open
    try:
        yield seen
    finally:
        builtins.open = io.open = real_open
        os.open = real_os_open


def never_opened(opened: list[Path], outside: Path) -> None:
    touched = [p for p in opened if p.is_relative_to(outside.resolve())]
    assert not touched, touched


def outside_folder(tmp_path: Path) -> Path:
    """A folder beside the database with a valid bushing file, subsystem and CSV in it."""
    out = tmp_path / "outside"
    out.mkdir()
    bus = (ADAMS / "bushing_mm_newton_deg.bus").read_text()
    (out / "secret.bus").write_text(f"$ {MARKER}\n{bus}")
    (out / "front.sub").write_text(f"$ {MARKER}\n{(ADAMS / 'double_wishbone.sub').read_text()}")
    (out / "secret.csv").write_text(f"{MARKER}\n")
    return out


def database(tmp_path: Path, property_file: str) -> tuple[Path, Path, Path]:
    """``db.cdb`` holding the double wishbone subsystem (its bushing's PROPERTY_FILE as given),
    a bushing file and a mapping that takes the bushing by its USAGE."""
    db = tmp_path / "db.cdb"
    (db / "subsystems.tbl").mkdir(parents=True)
    (db / "bushings.tbl").mkdir()
    shutil.copy(ADAMS / "bushing_mm_newton_deg.bus", db / "bushings.tbl" / "lca.bus")
    text = (ADAMS / "double_wishbone.sub").read_text().replace(
        "'mdids://elastokin_tests/bushings.tbl/bushing_mm_newton_deg.bus'",
        f"'{property_file}'")
    sub = db / "subsystems.tbl" / "front.sub"
    sub.write_text(text)
    mapping = yaml.safe_load((ADAMS / "double_wishbone_mapping.yaml").read_text())
    mapping["bushings"] = {"lca_bushing": {"usage": "lca_bushing"}}
    (db / "mapping.yaml").write_text(yaml.safe_dump(mapping))
    return db, sub, db / "mapping.yaml"


def property_line(sub: Path) -> int:
    return next(i for i, ln in enumerate(sub.read_text().splitlines(), start=1)
                if "PROPERTY_FILE" in ln)


# ----------------------------------------------------------------------------------------------
# ADAMS/Car databases


PATH_KINDS = {
    "mdids ..": "mdids://db/../outside/secret.bus",
    "alias ..": "<db>/../outside/secret.bus",
    "relative ..": "../../outside/secret.bus",
    "backslashes": "..\\..\\outside\\secret.bus",
    "absolute": "{outside}/secret.bus",
    "link out": "mdids://db/bushings.tbl/link.bus",
    "table link": "mdids://db/linked.tbl/secret.bus",
}


@pytest.mark.parametrize("kind", PATH_KINDS)
def test_property_file_outside_the_database_is_refused_unopened(tmp_path, kind):
    outside = outside_folder(tmp_path)
    reference = PATH_KINDS[kind].format(outside=outside)
    db, sub, mapping = database(tmp_path, reference)
    (db / "bushings.tbl" / "link.bus").symlink_to(outside / "secret.bus")
    (db / "linked.tbl").symlink_to(outside, target_is_directory=True)
    with watching_opens() as opened, pytest.raises(ConfigError) as exc:
        import_adams(read_yaml(WISHBONE)[0], db, mapping)
    msg = str(exc.value)
    assert msg.startswith(f"{sub}, line {property_line(sub)}, block [BUSHING_ASSEMBLY] USAGE "
                          "'lca_bushing' (left/right): PROPERTY_FILE "), msg
    assert repr(reference) in msg and str((outside / "secret.bus").resolve()) in msg
    assert f"outside the ADAMS/Car databases and folders given ({db}" in msg
    assert MARKER not in msg and "\n" not in msg
    never_opened(opened, outside)


def test_assembly_naming_a_subsystem_outside(tmp_path):
    outside = outside_folder(tmp_path)
    db, _, mapping = database(tmp_path, "mdids://db/bushings.tbl/lca.bus")
    asy = db / "assemblies.tbl" / "front.asy"
    asy.parent.mkdir()
    asy.write_text("[MDI_HEADER]\n FILE_TYPE = 'asy'\n[SUBSYSTEM]\n"
                   " USAGE = 'mdids://db/../outside/front.sub'\n")
    with watching_opens() as opened, pytest.raises(
            ConfigError, match=rf"^{asy}, line 4, block \[SUBSYSTEM\]: the subsystem file "
                               r"\(USAGE\) 'mdids://db/\.\./outside/front\.sub' leads to "
                               ".*outside the ADAMS/Car databases"):
        subsystem_files(read_mapping(mapping), assembly=asy)
    never_opened(opened, outside)


def test_subsystem_file_linked_out_of_the_database(tmp_path):
    outside = outside_folder(tmp_path)
    db = tmp_path / "db.cdb"
    (db / "subsystems.tbl").mkdir(parents=True)
    (db / "subsystems.tbl" / "front.sub").symlink_to(outside / "front.sub")
    with watching_opens() as opened, pytest.raises(
            ConfigError, match="subsystem file 'front.sub' leads to .*outside the database"):
        read_hardpoints(db)
    never_opened(opened, outside)


@pytest.mark.parametrize("key, value, use", [
    ("bushings", {"lca_bushing": "../outside/secret.bus"},
     lambda db, mapping: import_adams(read_yaml(WISHBONE)[0], db, mapping)),
    ("bushings", {"lca_bushing": {"file": "{outside}/secret.bus", "usage": "lca_bushing"}},
     lambda db, mapping: read_mapping(mapping).bushing_file("lca_bushing")),
    ("steering", {"subsystem": {"name": "../../outside/front"}},
     lambda db, mapping: subsystem_files(read_mapping(mapping), hardpoints=db)),
    ("anti_roll_bar", {"curve": "../../../../../../../../etc/passwd"},
     lambda db, mapping: read_mapping(mapping).anti_roll_bar.curve_file()),
], ids=["bushing file relative", "bushing file absolute", "subsystem name", "curve"])
def test_mapping_file_paths_outside(tmp_path, key, value, use):
    outside = outside_folder(tmp_path)
    db, sub, mapping = database(tmp_path, "mdids://db/bushings.tbl/lca.bus")
    data = yaml.safe_load(mapping.read_text())
    data[key] = yaml.safe_load(yaml.safe_dump(value).replace("{outside}", str(outside)))
    mapping.write_text(yaml.safe_dump(data))
    with watching_opens() as opened, pytest.raises(ConfigError) as exc:
        use(db, mapping)
    msg = str(exc.value)
    assert msg.startswith(f"{mapping}: key '{key}.") and "leads to" in msg, msg
    assert f"outside the mapping file's folder {db}" in msg or \
        f"outside the ADAMS/Car databases and folders given ({db})" in msg
    never_opened(opened, outside)


def test_fifo_in_the_database_is_refused_not_read(tmp_path):
    """Opening a FIFO for reading blocks until someone writes: the import must refuse it
    before (the call runs in a thread that is given 30 s)."""
    db, sub, mapping = database(tmp_path, "mdids://db/bushings.tbl/pipe.bus")
    os.mkfifo(db / "bushings.tbl" / "pipe.bus")
    result: list = []
    worker = threading.Thread(target=lambda: result.append(_error_of(
        import_adams, read_yaml(WISHBONE)[0], db, mapping)), daemon=True)
    worker.start()
    worker.join(30)
    assert result, "import-adams opened the FIFO"
    assert "PROPERTY_FILE 'mdids://db/bushings.tbl/pipe.bus'" in result[0]
    assert "is not a regular file" in result[0]


def _error_of(fn, *args) -> str:
    try:
        fn(*args)
    except ConfigError as exc:
        return str(exc)
    return "no error"


def test_cli_names_file_line_usage_and_path_without_content(tmp_path):
    outside = outside_folder(tmp_path)
    db, sub, mapping = database(tmp_path, "mdids://db/../outside/secret.bus")
    with watching_opens() as opened:
        r = CliRunner().invoke(main, ["import-adams", "--hardpoints", str(db), "--mapping",
                                      str(mapping), "--template", str(WISHBONE), "--out",
                                      str(tmp_path / "new.yaml")])
    assert r.exit_code == 1 and r.output.count("\n") == 1, r.output
    assert f"{sub}, line {property_line(sub)}" in r.output and "USAGE 'lca_bushing'" in r.output
    assert "'mdids://db/../outside/secret.bus'" in r.output and MARKER not in r.output
    never_opened(opened, outside)
    assert not (tmp_path / "new.yaml").exists()


def test_paths_typed_or_inside_what_was_given_are_read(tmp_path):
    """A bushing file typed on the command line may be anywhere; a mapping in another folder
    may name files of the database given with it; any mdids:// alias is the database."""
    outside = outside_folder(tmp_path)
    db, _, _ = database(tmp_path, "mdids://acar_shared/bushings.tbl/lca.bus")
    maps = tmp_path / "maps"
    maps.mkdir()
    data = yaml.safe_load((ADAMS / "double_wishbone_mapping.yaml").read_text())
    data["bushings"] = {"lca_bushing": "../db.cdb/bushings.tbl/lca.bus"}
    (maps / "front.yaml").write_text(yaml.safe_dump(data))
    cfg, _ = import_adams(read_yaml(WISHBONE)[0], db, maps / "front.yaml")
    assert cfg["connections"]["lca_bushing"]["stiffness"]["x"]["load"][-1] == 12000.0
    r = CliRunner().invoke(main, ["import-adams", "--hardpoints", str(db), "--mapping",
                                  str(db / "mapping.yaml"), "--template", str(WISHBONE),
                                  "--bushing", f"lca_bushing={outside / 'secret.bus'}",
                                  "--out", str(tmp_path / "new.yaml")])
    assert r.exit_code == 0, r.output


def test_missing_property_file_names_the_subsystem_and_usage(tmp_path):
    db, sub, mapping = database(tmp_path, "mdids://front_db/bushings.tbl/gone.bus")
    with pytest.raises(ConfigError) as exc:
        import_adams(read_yaml(WISHBONE)[0], db, mapping)
    assert str(exc.value) == (
        f"{sub}, line {property_line(sub)}, block [BUSHING_ASSEMBLY] USAGE 'lca_bushing' "
        "(left/right): PROPERTY_FILE 'mdids://front_db/bushings.tbl/gone.bus' does not exist ("
        f"{db}/bushings.tbl/gone.bus (alias 'front_db' taken as the database that holds "
        f"front.sub: {db}; elastokin does not read .acar.cfg))")


# ----------------------------------------------------------------------------------------------
# A config's data: CMM files, K&C test files, what synthesize writes


def project(tmp_path: Path, monkeypatch, edit) -> Path:
    """The case study's config in ``tmp_path/proj/cfg`` with its CMM files in ``cfg/meas`` and
    one K&C test file in ``proj/kc`` (beside the config's folder: read with ``--data``), run
    from ``tmp_path`` (the working folder, which holds the outside folder too); then
    ``edit(data, outside)``."""
    outside = outside_folder(tmp_path)
    cfg = tmp_path / "proj" / "cfg" / "case.yaml"
    shutil.copytree(CASE.parent / "pseudo_mcpherson_measurements", cfg.parent / "meas")
    (tmp_path / "proj" / "kc").mkdir()
    shutil.copy(CASE.parent / "pseudo_mcpherson_kc_test" / "parallel_travel.csv",
                tmp_path / "proj" / "kc")
    data = read_yaml(CASE)[0]
    data["measurements"]["folder"] = "meas"
    data["kc_test"].update(folder="../kc", files={})
    edit(data, outside)
    cfg.write_text(yaml.safe_dump(data, sort_keys=False))
    monkeypatch.chdir(tmp_path)  # the working folder gives no access: only --data does
    return cfg


def _set(path: str, value):
    def edit(data, outside):
        *keys, last = path.split(".")
        here = data
        for k in keys:
            here = here[k]
        here[last] = value.format(outside=outside)
    return edit


#: config key -> the value that leads out ({outside}: the outside folder), the step reading it
CONFIG_PATHS = {
    "measurements.folder": ("../../outside", identify),
    "measurements.parts.body.file": ("../../../outside/secret.igs", identify),
    "measurements.assembly.file": ("{outside}/assembly.igs", identify),
    "measurements.truth": ("meas/../../../../outside/truth.yaml", identify),
    "kc_test.folder": ("{outside}", read_test_sweeps),
    "kc_test.files.parallel_travel": ("../../outside/secret.csv", read_test_sweeps),
}


@pytest.mark.parametrize("key", CONFIG_PATHS)
def test_config_data_paths_outside_its_folders(tmp_path, monkeypatch, key):
    value, step = CONFIG_PATHS[key]
    if key.startswith("kc_test.files"):
        edit = lambda data, outside: data["kc_test"]["files"].update(  # noqa: E731
            parallel_travel=value)
    else:
        edit = _set(key, value)
    cfg = project(tmp_path, monkeypatch, edit)
    with watching_opens() as opened, pytest.raises(ConfigError) as exc, \
            data_folders([tmp_path / "proj" / "kc"]):
        step(load_suspension(cfg))
    msg = str(exc.value)
    assert msg.startswith(f"{cfg}: key '{key}': ") and "outside the config's folder and the " \
        "folders given" in msg and "--data FOLDER" in msg, msg
    never_opened(opened, tmp_path / "outside")


def test_config_kc_test_file_linked_out(tmp_path, monkeypatch):
    cfg = project(tmp_path, monkeypatch, lambda data, outside: None)
    (tmp_path / "proj" / "kc" / "vertical_force.csv").symlink_to(
        tmp_path / "outside" / "secret.csv")
    with watching_opens() as opened, pytest.raises(
            ConfigError, match=r"key 'kc_test.folder': file 'vertical_force.csv' leads to "
                               r".*outside/secret.csv, outside"), \
            data_folders([tmp_path / "proj" / "kc"]):
        read_test_sweeps(load_suspension(cfg))
    never_opened(opened, tmp_path / "outside")


def test_config_data_inside_its_folders_is_read(tmp_path, monkeypatch):
    """Data beside the config are read; data beside its folder only with ``--data`` (not
    because the working folder holds them); a config written into a results folder
    (``identify``: ``../../kc``) reads them with ``--data`` too."""
    cfg = project(tmp_path, monkeypatch, lambda data, outside: None)
    s = load_suspension(cfg)
    assert set(measurement_paths(s)) == {*s.measurements.parts, "assembly", "truth"}
    with pytest.raises(ConfigError, match=r"key 'kc_test.folder': folder '../kc' leads to "
                                          r".*proj/kc, outside the config's folder \("):
        read_test_sweeps(s)
    with data_folders([tmp_path / "proj" / "kc"]):
        assert read_test_sweeps(s)[1] == [str(tmp_path / "proj" / "cfg" / "../kc" /
                                              "parallel_travel.csv")]
    results = tmp_path / "proj" / "results" / "ident"
    results.mkdir(parents=True)
    data = read_yaml(cfg)[0]
    data["kc_test"]["folder"] = "../../kc"
    (results / "identified.yaml").write_text(yaml.safe_dump(data))
    with data_folders([tmp_path / "proj"]):
        assert len(read_test_sweeps(load_suspension(results / "identified.yaml"))[1]) == 1


def test_a_written_config_says_and_takes_its_data_folders(tmp_path, monkeypatch):
    """A config written into a results folder (as `identify` writes it: ``../../kc``) is
    printed with the ``--data`` folder it needs; `kc` refuses it without, runs it with."""
    cfg = project(tmp_path, monkeypatch, lambda data, outside: None)
    written = tmp_path / "proj" / "results" / "ident" / "identified.yaml"
    written.parent.mkdir(parents=True)
    data = read_yaml(cfg)[0]
    del data["measurements"]
    data["kc_test"].update(folder="../../kc", stiffness_identification={"enabled": False})
    written.write_text(yaml.safe_dump(data))
    assert data_hint(written, load_suspension(cfg), ("kc_test",)) == (
        f"its data lie outside its folder: elastokin kc --config {written} --data "
        f"{tmp_path / 'proj' / 'kc'}")
    assert data_hint(cfg.parent / "x.yaml", load_suspension(cfg), ("measurements",)) is None
    args = ["kc", "--config", str(written), "--out", str(tmp_path / "kc"), "--quiet",
            "--models", "initial", "--rig", str(CASE.parent / "rigs" / "travel_only.yaml")]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 1 and "key 'kc_test.folder'" in r.output and "--data FOLDER" in \
        r.output, r.output
    r = CliRunner().invoke(main, [*args, "--data", str(tmp_path / "proj" / "kc")])
    assert r.exit_code == 0, r.output


def test_synthesize_writes_nothing_outside(tmp_path, monkeypatch):
    cfg = project(tmp_path, monkeypatch, _set("measurements.folder", "{outside}/cmm"))
    (tmp_path / "outside" / "cmm").mkdir()
    before = sorted(p.name for p in (tmp_path / "outside").iterdir())
    r = CliRunner().invoke(main, ["synthesize", "--config", str(cfg), "--only", "cmm"])
    assert r.exit_code == 1 and "key 'measurements.folder'" in r.output, r.output
    assert sorted(p.name for p in (tmp_path / "outside").iterdir()) == before
    r = CliRunner().invoke(main, ["synthesize", "--config", str(cfg), "--only", "cmm", "--out",
                                  str(tmp_path / "typed")])
    assert r.exit_code == 0, r.output  # a folder typed on the command line: anywhere
    assert (tmp_path / "typed" / "assembly.igs").is_file()
