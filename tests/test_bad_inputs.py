"""Bad input to every command and file format ends in one clear line (issue 15, items 4, 8, 15).

Every case runs one ``elastokin`` command (click's CliRunner) with one thing wrong: a config,
a rig file, a K&C test CSV, a CMM file (IGES/CSV), an ADAMS file (.sub/.tbl, .bus, mapping),
a command-line option or the output. Each must end with

* exit code 1 (2 for a command-line usage error, as click does),
* exactly one line of output, ``elastokin: error: ...``, no traceback,
* the file and the key, part, column or option at fault named in that line,
* earlier results in ``--out`` untouched: the folder (or file) is filled with a marker before
  the run, and nothing at all is written anywhere in the test's folder.

Inputs are the fast nominal model (the shipped config without its CMM measurements and K&C
test data, on a coarse travel-only rig) or small copies of the shipped data, so a case that
does compute is quick.
"""

from __future__ import annotations

import copy
import functools
import resource
import shutil
import signal
import traceback
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli import main
from elastokin.config.loading import read_yaml
from elastokin.formats.cmm import read_points, write_points

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"
MEASURED = CASE.parent / "pseudo_mcpherson_measurements"
ADAMS = Path(__file__).parent / "data" / "adams"
WISHBONE = Path(__file__).parent / "data" / "double_wishbone.yaml"
SUB = ADAMS / "double_wishbone.sub"
MAPPING = ADAMS / "double_wishbone_mapping.yaml"
BUS = ADAMS / "bushing_mm_newton_deg.bus"

#: parallel travel in 30 mm steps only: a case that computes is done in a few seconds
COARSE_RIG = {"parallel_travel": {"step_mm": 30}, "vertical_force": None,
              "lateral_force": None, "longitudinal_force_patch": None,
              "longitudinal_force_centre": None, "aligning_torque": None}
NO_OTHER_CASES = "".join(f"{k}: null\n" for k in list(COARSE_RIG)[1:])

MEMORY_LIMIT = 6 * 2**30  # bytes of address space for this module's test process
TIME_LIMIT_S = 60  # per case: a runaway case fails instead of hanging the run


# ------------------------------------------------------------------------------ limits
@pytest.fixture(scope="module", autouse=True)
def memory_limit():
    """Run this module under a 6 GiB address-space limit (RLIMIT_AS) so that a case whose
    check is missing (a huge step count, a runaway solve) fails with MemoryError instead of
    exhausting the machine; the previous limit is restored after the module. (Module scope,
    not session: the limit must not outlive this module's tests.)"""
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = MEMORY_LIMIT if hard == resource.RLIM_INFINITY else min(MEMORY_LIMIT, hard)
    if soft == resource.RLIM_INFINITY or soft > limit:
        resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    yield
    resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


class Runaway(Exception):
    pass


@pytest.fixture(autouse=True)
def time_limit():
    """A case still running after TIME_LIMIT_S fails (SIGALRM) instead of hanging."""
    def stop(signum, frame):
        raise Runaway(f"still running after {TIME_LIMIT_S} s")

    previous = signal.signal(signal.SIGALRM, stop)
    signal.alarm(TIME_LIMIT_S)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, previous)


# ------------------------------------------------------------------------------ inputs
@functools.cache
def _shipped() -> dict:
    return read_yaml(CASE)[0]


def nominal() -> dict:
    """The shipped config without measurements and K&C test data, on the coarse rig."""
    data = copy.deepcopy(_shipped())
    del data["measurements"]
    data.pop("kc_test", None)
    data["rig"] = copy.deepcopy(COARSE_RIG)
    return data


class Inputs:
    """Writes one case's input files into its tmp_path; every method returns the path."""

    def __init__(self, tmp: Path):
        self.tmp = tmp

    def file(self, name: str, content: str | bytes) -> str:
        path = self.tmp / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content)
        return str(path)

    def config(self, mutate: Callable[[dict], object] | None = None, text: str | None = None,
               name: str = "bad.yaml", data: dict | None = None) -> str:
        """The nominal config, mutated, or ``text`` as it is."""
        data = nominal() if data is None else data
        if mutate is not None:
            mutate(data)
        return self.file(name, text if text is not None else yaml.safe_dump(data,
                                                                            sort_keys=False))

    def measured(self, mutate: Callable[[dict], object] | None = None,
                 files: Callable[[Path], object] | None = None) -> str:
        """The shipped config with its CMM data (a copy in tmp_path, ``files`` applied to
        the folder), no K&C test data, the coarse rig."""
        folder = self.tmp / MEASURED.name
        shutil.copytree(MEASURED, folder)
        if files is not None:
            files(folder)
        data = copy.deepcopy(_shipped())
        data.pop("kc_test", None)
        data["rig"] = copy.deepcopy(COARSE_RIG)
        return self.config(mutate, data=data, name="measured.yaml")

    def kc_test(self, content: str | bytes, name: str = "lateral_force.csv",
                load_case: str = "lateral_force") -> str:
        """The nominal config with one K&C test file ``name`` holding ``content``."""
        self.file(name, content)

        def add(d):
            d["kc_test"] = {"folder": ".", "files": {load_case: name}}
        return self.config(add)


@dataclass(frozen=True)
class Bad:
    command: str
    args: Callable[[Inputs], list[str]]
    expected: tuple[str, ...]  # fragments of the error line
    code: int = 1
    out: bool = True  # give the command an --out holding earlier results


def case(name: str, command: str, args, expected, code: int = 1, out: bool = True,
         kind: str = ""):
    """One bad input: ``kind`` of input (config, rig file, ...) and ``name`` make its id."""
    return pytest.param(Bad(command, args, tuple(expected), code, out),
                        id=f"{command}, {kind}: {name}" if kind else f"{command}: {name}")


def _set(*keys_value):
    """A mutation setting a nested key: _set("connections", "J8", "type", "ball")."""
    *keys, last, value = keys_value

    def mutate(d):
        for k in keys:
            d = d[k]
        d[last] = value
    return mutate


def _del(*keys):
    def mutate(d):
        for k in keys[:-1]:
            d = d[k]
        del d[keys[-1]]
    return mutate


def _hanging_part(d):
    """A bracket on the knuckle by one ball joint, nothing else (no axle: one corner)."""
    d.pop("axle", None)
    d["parts"]["bracket"] = {}
    d["connections"]["bracket_ball"] = {"type": "spherical", "parts": ["knuckle", "bracket"],
                                        "at": "J6"}


def _rod_part(d):
    """The tie rod as a part between two ball joints (it spins about its own line)."""
    d.pop("axle", None)
    inner, outer = d["connections"].pop("tie_rod")["at"]
    d["parts"]["rod"] = {}
    d["connections"]["rod_inner"] = {"type": "spherical", "parts": ["body", "rod"], "at": inner}
    d["connections"]["rod_outer"] = {"type": "spherical", "parts": ["rod", "knuckle"],
                                     "at": outer}


def kc(name, expected, mutate=None, text=None):
    return case(name, "kc", lambda f: ["--config", f.config(mutate, text)],
                ["bad.yaml", *expected], kind="config")


# ------------------------------------------------------------------------------ configs
NOMINAL_TEXT = yaml.safe_dump(nominal(), sort_keys=False)


def _text(old: str, new: str) -> str:
    """The nominal config's YAML text with one edit (which must apply)."""
    assert old in NOMINAL_TEXT, old
    return NOMINAL_TEXT.replace(old, new, 1)


CONFIG_CASES = [
    kc("malformed YAML", ["line", "malformed YAML"], text="name: [unclosed\n"),
    kc("not a mapping", ["mapping"], text="- 1\n- 2\n"),
    kc("empty file", ["mapping"], text=""),
    case("missing config file", "kc", lambda f: ["--config", str(f.tmp / "none.yaml")],
         ["none.yaml", "cannot read config file"], kind="config"),
    kc("hardpoint not a vector", ["hardpoints.J1"], _set("hardpoints", "J1", "abc")),
    kc("hardpoint with 2 coordinates", ["hardpoints.J1"],
       _set("hardpoints", "J1", [1.0, 2.0])),
    kc("iterations not a number", ["solver.max_newton_iterations"],
       _set("solver", "max_newton_iterations", "many")),
    kc("wheel load a list", ["design.wheel_load_N"], _set("design", "wheel_load_N", [1, 2])),
    kc("unknown connection type", ["connections.J8", "ball"],
       _set("connections", "J8", "type", "ball")),
    kc("undefined hardpoint", ["J77", "hardpoints"], _set("connections", "J7", "at", "J77")),
    kc("undefined part", ["'hub'", "not defined"],
       _set("connections", "J7", "parts", ["rear_arm", "hub"])),
    kc("zero axis", ["connections.J4.radial", "zero"],
       _set("connections", "J4", "radial", [0.0, 0.0, 0.0])),
    kc("non-unit axis", ["wheel.spin_axis", "unit vector"],
       _set("wheel", "spin_axis", [0.0, -2.0, 0.0])),
    kc("under-constrained", ["under-constrained", "knuckle"], _del("connections", "tie_rod")),
    kc("over-constrained", ["over-constrained"], _set(
        "connections", "extra", {"type": "spherical", "parts": ["body", "knuckle"],
                                 "at": "J6"})),
    kc("no convergence", ["did not converge"], lambda d: d["solver"].update(
        max_newton_iterations=1, newton_tolerance=1e-14)),
    # a part nothing holds: named before "did not converge" (issue 24, item 7)
    kc("part hanging on one ball joint", ["nothing holds part", "'bracket' (3 free directions;"
                                          " its connections: bracket_ball)"], _hanging_part),
    kc("rod turning between two ball joints", ["'rod' (1 free direction", "'link' connection"],
       _rod_part),
    kc("unknown top-level key", ["colour"], _set("colour", "red")),
    kc("unknown spring seat", ["nope"],
       _set("springs", "coil", "seats", ["spring_upper_seat", "nope"])),
    kc("undefined wheel part", ["wheel.part", "hub"], _set("wheel", "part", "hub")),
    kc("bad frame axis", ["frame.x", "forward"], _set("frame", "x", "sideways")),
    kc("bad side", ["side", "left"], _set("side", "middle")),
    kc("unsupported format version", ["elastokin"], _set("elastokin", 2)),
    kc("balance an unknown spring", ["design.balance_spring", "nope"],
       _set("design", "balance_spring", "nope")),
    kc("bushing without stiffness", ["connections.J1", "stiffness"],
       _del("connections", "J1", "stiffness")),
    kc("negative stiffness", ["connections.J1.stiffness"],
       _set("connections", "J1", "stiffness", "x", -300)),
    kc("link with one point", ["connections.tie_rod"], _set("connections", "tie_rod", "at", "J3")),
    kc("misspelt spring rate", ["springs.coil", "rate_N_per_m"],
       lambda d: d["springs"]["coil"].update(rate_N_per_m=d["springs"]["coil"].pop(
           "rate_N_per_mm"))),
    kc("duplicate hardpoint key", ["J1"], text=_text(
        "hardpoints:\n", "hardpoints:\n  J1: [0.0, 0.0, 0.0]\n")),
    kc("NaN in a hardpoint", ["hardpoints.J1"], text=_text(
        "hardpoints:\n  J1:\n  - -294.7", "hardpoints:\n  J1:\n  - .nan")),
    case("a folder as config file", "kc", lambda f: [
        "--config", str(Path(f.file("folder.yaml/x", "")).parent)],
        ["--config", "folder.yaml", "is a directory"], code=2, kind="config"),
    case("missing kc_test file", "kc", lambda f: ["--config", f.config(_set(
        "kc_test", {"folder": ".", "files": {"lateral_force": "lateral_2024.csv"}}))],
        ["bad.yaml", "kc_test.files.lateral_force", "lateral_2024.csv"], kind="config"),
]


# ------------------------------------------------------------------------------ rig files
def rig(name, text, expected):
    return case(name, "kc", lambda f: ["--config", f.config(name="nominal.yaml"),
                                       "--rig", f.file("rig.yaml", text)],
                ["rig.yaml", *expected], kind="rig file")


RIG_CASES = [
    case("a folder as rig file", "kc", lambda f: [
        "--config", f.config(name="nominal.yaml"),
        "--rig", str(Path(f.file("rig.yaml/x", "")).parent)],
        ["--rig", "rig.yaml", "is a directory"], code=2, kind="rig file"),
    rig("negative amplitude", "lateral_force: {amplitude_N: -5}\n" + NO_OTHER_CASES.replace(
        "lateral_force: null\n", ""), ["lateral_force.amplitude_N", "greater than 0"]),
    rig("misspelt load case", "rig: {lateral_forse: null}\n", ["lateral_forse"]),
    rig("not a mapping", "- 1\n", ["mapping"]),
    rig("malformed YAML", "parallel_travel: {step_mm: 2\n", ["line"]),
    rig("stroke not a number", "parallel_travel: {bump_mm: ninety}\n" + NO_OTHER_CASES,
        ["parallel_travel.bump_mm"]),
    rig("zero step", "parallel_travel: {step_mm: 0}\n" + NO_OTHER_CASES,
        ["parallel_travel.step_mm"]),
    rig("rebound above bump", "parallel_travel: {rebound_mm: 50, bump_mm: -50}\n"
        + NO_OTHER_CASES, ["parallel_travel", "rebound_mm"]),
    case("missing rig file", "kc", lambda f: ["--config", f.config(name="nominal.yaml"),
                                              "--rig", str(f.tmp / "none_rig.yaml")],
         ["none_rig.yaml"], kind="rig file"),
    rig("infinite stroke", "parallel_travel: {bump_mm: .inf}\n" + NO_OTHER_CASES,
        ["parallel_travel.bump_mm"]),
    rig("tiny force step", "lateral_force: {amplitude_N: 2000, step_N: 0.001}\n"
        + NO_OTHER_CASES.replace("lateral_force: null\n", "") + "parallel_travel: {step_mm: 30}\n",
        ["lateral_force.step_N"]),
]


# ------------------------------------------------------------------------------ K&C test CSVs
def kct(name, content, expected, file="lateral_force.csv", load_case="lateral_force"):
    return case(name, "kc", lambda f: ["--config", f.kc_test(content, file, load_case)],
                [file, *expected], kind="K&C test CSV")


def _lateral(rows: str, header: str = "lateral_force [N],toe [deg]") -> str:
    return f"{header}\n{rows}"


def _zip_bytes() -> bytes:
    """An Excel workbook given instead of a CSV: a zip archive, binary."""
    import io
    import zipfile

    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("xl/worksheets/sheet1.xml", bytes(range(256)) * 8)
    return buf.getvalue()


def _kc_test_folder(f: Inputs) -> list[str]:
    (f.tmp / "lateral_force.csv").mkdir()
    return ["--config", f.config(_set("kc_test", {"folder": ".", "files": {
        "lateral_force": "lateral_force.csv"}}))]


KC_TEST_CASES = [
    kct("missing required channel", "wheel_travel [mm],camber [deg]\n0,0\n90,1\n",
        ["'toe [deg]'"], file="parallel_travel.csv", load_case="parallel_travel"),
    kct("wrong input column", "toe [deg],wheel_travel [mm]\n0,0\n0.1,90\n",
        ["input channel 'wheel_travel [mm]'"], file="parallel_travel.csv",
        load_case="parallel_travel"),
    kct("unit not an angle", _lateral("0,0\n10,1\n", "lateral_force [N],toe [mm]"),
        ["'toe [mm]'", "not a unit of angle"]),
    kct("no unit", _lateral("0,0\n10,1\n", "lateral_force [N],toe"), ["'toe'", "no unit"]),
    kct("force in degrees", _lateral("0,0\n10,1\n", "lateral_force [deg],toe [deg]"),
        ["'lateral_force [deg]'", "not a unit of force"]),
    kct("not a number", _lateral("0,0\n100,abc\n200,0\n"), ["line 3", "'abc' is not a number"]),
    kct("empty cell", _lateral("0,0\n100,\n200,0\n"), ["line 3", "empty cell"]),
    kct("nan cell", _lateral("0,0\n100,nan\n200,0\n"), ["'nan' is not a finite number"]),
    kct("semicolons", "lateral_force [N];toe [deg]\n0;0\n1;1\n", ["separated by ';'"]),
    kct("duplicate column", _lateral("0,0,0\n1,1,1\n",
                                     "lateral_force [N],toe [deg],toe [rad]"),
        ["'toe [rad]'", "appears twice"]),
    kct("only comments", "# only comments\n\n", ["no header row"]),
    kct("one data row", _lateral("0,0\n"), ["at least 2"]),
    kct("constant input", _lateral("5,0\n5,1\n"), ["lateral_force [N]", "constant"]),
    kct("not UTF-8", b"lateral_force [N],toe [\xb0]\n0,0\n1,1\n", ["not UTF-8"]),
    kct("not monotonic", _lateral("0,0\n1000,0\n2000,0\n500,0\n1500,0\n100,0\n1900,0\n"),
        ["not monotonic"]),
    kct("another load case", "# load_case: aligning_torque\naligning_torque [N*mm],toe [deg]\n"
        "0,0\n1,0.1\n2,0.2\n", ["load case 'aligning_torque'"]),
    case("a folder as K&C test file", "kc", lambda f: _kc_test_folder(f),
         ["lateral_force.csv"], kind="K&C test CSV"),
    kct("binary file (a zip)", _zip_bytes(), []),
]


# ------------------------------------------------------------------------------ CMM files
def cmm(name, expected, mutate=None, files=None):
    return case(name, "identify", lambda f: ["--config", f.measured(mutate, files)],
                expected, kind="CMM")


def _corrupt(folder):
    (folder / "rear_arm.igs").write_bytes(b"\x00\xff garbage" * 50)


def _truncate(folder):
    lines = (folder / "rear_arm.igs").read_text().splitlines(keepends=True)
    (folder / "rear_arm.igs").write_text("".join(lines[: len(lines) * 2 // 3]))


def _two_marks(folder):
    path = folder / "assembly.igs"
    pts = read_points(path)
    keep = {k: v for k, v in pts.points.items() if not k.startswith("RA")}
    keep.update([(k, v) for k, v in pts.points.items() if k.startswith("RA")][:2])
    write_points(path, keep, {})


def _two_wrong_marks(folder):
    path = folder / "assembly.igs"
    pts = read_points(path)
    ra = [k for k in pts.order if k.startswith("RA")]
    pts.points[ra[0]] = pts.points[ra[0]] + [9.0, 0, 0]
    pts.points[ra[1]] = pts.points[ra[1]] + [0, 0, -11.0]
    write_points(path, pts.points, {})


def _csv_part(text):
    def files(folder):
        (folder / "body.csv").write_text(text)
    return files


def _body_csv(d):
    d["measurements"]["parts"]["body"]["file"] = "body.csv"


CMM_CASES = [
    cmm("unreadable IGES", ["rear_arm.igs", "unreadable IGES"], files=_corrupt),
    cmm("empty IGES", ["rear_arm.igs"],
        files=lambda folder: (folder / "rear_arm.igs").write_bytes(b"")),
    cmm("missing part file", ["knuckle.igs"],
        files=lambda folder: (folder / "knuckle.igs").unlink()),
    cmm("fewer than 3 marks", ["assembly.igs", "rear_arm", "at least 3"], files=_two_marks),
    cmm("no mark permutation", ["assembly.igs", "rear_arm", "match no"],
        files=_two_wrong_marks),
    cmm("CSV without z column", ["body.csv", "z_mm"], mutate=_body_csv,
        files=_csv_part("label,kind,x_mm,y_mm\nM1,point,1,2\n")),
    cmm("CSV cell not a number", ["body.csv", "line 2", "column y_mm"], mutate=_body_csv,
        files=_csv_part("label,kind,x_mm,y_mm,z_mm,x2_mm,y2_mm,z2_mm\nM1,point,1,two,3,,,\n")),
    cmm("sleeve side not given", ["measured.yaml", "J1", "inner"],
        mutate=_del("measurements", "joints", "J1", "inner")),
    cmm("part without a measurement", ["measured.yaml", "strut_rod"],
        mutate=_del("measurements", "parts", "strut_rod")),
    cmm("missing measurement folder", ["nowhere"],
        mutate=_set("measurements", "folder", "nowhere")),
    cmm("a folder as IGES file", ["rear_arm.igs"], files=lambda folder: (
        (folder / "rear_arm.igs").unlink(), (folder / "rear_arm.igs").mkdir())),
    cmm("truncated IGES", ["rear_arm.igs"], files=_truncate),
]


# ------------------------------------------------------------------------------ ADAMS files
def _marked_line(path: Path) -> int:
    return next(i for i, ln in enumerate(path.read_text().splitlines(), start=1)
                if "$ error" in ln)


def imp(name, expected, hardpoints=None, mapping=None, template=None, bushings=(), code=1):
    """import-adams with the double wishbone's files, one of them replaced: each of
    ``hardpoints``, ``mapping``, ``template`` is a callable (Inputs -> path) or None."""
    def args(f):
        out = ["--hardpoints", hardpoints(f) if hardpoints else str(SUB),
               "--mapping", mapping(f) if mapping else str(MAPPING),
               "--template", template(f) if template else str(WISHBONE)]
        for b in bushings:
            out += ["--bushing", b(f) if callable(b) else b]
        return out
    return case(name, "import-adams", args, expected, code=code, kind="ADAMS")


def _mapping(content):
    return lambda f: f.file("m.yaml", content if isinstance(content, str)
                            else yaml.safe_dump(content))


def _bus(name, block):
    path = ADAMS / f"malformed_{name}.bus"
    return imp(f"malformed .bus: {name}",
               [path.name, f"line {_marked_line(path)}", f"block [{block}]"],
               bushings=[f"lca_bushing={path}"])


ADAMS_CASES = [
    _bus("unclosed_table", "FY_CURVE"),
    _bus("non_monotonic", "FZ_CURVE"),
    _bus("unknown_unit", "UNITS"),
    _bus("not_through_zero", "TX_CURVE"),
    _bus("empty_table", "TZ_CURVE"),
    imp(".bus without a curve block", ["no_ty.bus", "block [TY_CURVE] is missing"],
        bushings=[lambda f: "lca_bushing=" + f.file(
            "no_ty.bus", BUS.read_text().replace("[TY_CURVE]", "[TY_CURVE_OLD]"))]),
    imp("malformed hardpoint table", ["bad.sub", "line 3", "malformed block header"],
        hardpoints=lambda f: f.file("bad.sub", "[A]\n X = 1\n[B\n")),
    imp("hardpoint table row too long", ["bad.tbl", "line 3"],
        hardpoints=lambda f: f.file(
            "bad.tbl", "[HARDPOINT]\n{hardpoint_name symmetry x_value y_value z_value}\n"
                       " 'lca_front' 'left/right' 1 2 3 4\n")),
    imp("missing hardpoint table", ["none.sub"],
        hardpoints=lambda f: str(f.tmp / "none.sub")),
    imp("mapping: unknown elastokin hardpoint", ["m.yaml", "hardpoints.nope"],
        mapping=_mapping({"elastokin_adams_mapping": 1, "hardpoints": {"nope": "lca_front"}})),
    imp("mapping: unknown ADAMS hardpoint", ["m.yaml", "hardpoints.lca_front", "lca_fornt"],
        mapping=_mapping({"elastokin_adams_mapping": 1,
                          "hardpoints": {"lca_front": "lca_fornt"}})),
    imp("mapping: bad side", ["m.yaml", "hardpoints.lca_front.side"],
        mapping=_mapping({"elastokin_adams_mapping": 1,
                          "hardpoints": {"lca_front": {"adams": "x", "side": "up"}}})),
    imp("mapping: format version", ["m.yaml", "elastokin_adams_mapping"],
        mapping=_mapping({"elastokin_adams_mapping": 2,
                          "hardpoints": {"lca_front": "lca_front"}})),
    imp("mapping: unknown key", ["m.yaml", "colour"],
        mapping=_mapping({"elastokin_adams_mapping": 1, "hardpoints": {"a": "b"},
                          "colour": "red"})),
    imp("mapping: malformed YAML", ["m.yaml", "line"], mapping=_mapping("hardpoints: {a: [\n")),
    imp("--bushing without =", ["--bushing", "expected NAME=FILE.bus"],
        bushings=["lca_bushing.bus"]),
    imp("--bushing given twice", ["--bushing", "lca_bushing", "twice"],
        bushings=[f"lca_bushing={BUS}", f"lca_bushing={BUS}"]),
    imp("--bushing of an unknown bushing", ["nope"], bushings=[f"nope={BUS}"]),
    imp("--bushing file missing", ["none.bus"],
        bushings=[lambda f: f"lca_bushing={f.tmp / 'none.bus'}"]),
    imp("missing template", ["none.yaml"], template=lambda f: str(f.tmp / "none.yaml")),
    imp("template with an undefined part",
        ["tpl.yaml", "connections.lca_bushing.parts", "'hub'"],
        template=lambda f: f.config(_set("connections", "lca_bushing", "parts",
                                         ["body", "hub"]),
                                    data=read_yaml(WISHBONE)[0], name="tpl.yaml")),
    case("missing config", "export-adams", lambda f: ["--config", str(f.tmp / "none.yaml")],
         ["none.yaml", "cannot read config file"]),
    case("invalid config", "export-adams", lambda f: ["--config", f.config(_set(
        "connections", "J8", "type", "ball"))], ["bad.yaml", "connections.J8", "ball"]),
    case("--identified without measurements", "export-adams", lambda f: [
        "--config", f.config(), "--identified"], ["bad.yaml", "--identified", "measurements"]),
    case("--kc file missing", "export-adams", lambda f: [
        "--config", f.config(), "--kc", str(f.tmp / "none.csv")], ["none.csv"]),
    case("--kc a binary file", "export-adams", lambda f: [
        "--config", f.config(), "--kc", f.file("kc.csv", _zip_bytes())], ["kc.csv"]),
]


# ------------------------------------------------------------------------------ DOE, synthesize
def _doe_config(f: Inputs, mutate=None) -> str:
    """The nominal config with the shipped CMM section (absolute folder): a DOE input."""
    data = nominal()
    data["measurements"] = copy.deepcopy(_shipped()["measurements"])
    data["measurements"]["folder"] = str(MEASURED)
    return f.config(mutate, data=data, name="doe.yaml")


def _no_clearance(d):
    for jm in d["measurements"]["joints"].values():
        jm.pop("clearance", None)


OPTION_CASES = [
    case("--samples 0", "doe", lambda f: ["--config", _doe_config(f), "--samples", "0"],
         ["--samples", "at least 1, got 0"]),
    case("--samples 10^8", "doe", lambda f: ["--config", _doe_config(f), "--samples",
                                             "100000000"],
         ["--samples", "100,000,000 samples", "at most 1,000,000"]),
    case("--workers 0", "doe", lambda f: ["--config", _doe_config(f), "--samples", "2",
                                          "--workers", "0"], ["--workers", "at least 1"]),
    case("unknown --method", "doe", lambda f: ["--config", _doe_config(f), "--samples", "2",
                                               "--method", "grid"], ["--method", "'grid'"],
         code=2),
    case("unknown --load-cases", "doe", lambda f: ["--config", _doe_config(f), "--samples", "2",
                                                   "--load-cases", "everything"],
         ["--load-cases", "'everything'"], code=2),
    case("--samples not a number", "doe", lambda f: ["--config", _doe_config(f), "--samples",
                                                     "many"], ["--samples", "'many'"], code=2),
    case("no measurements", "doe", lambda f: ["--config", f.config(), "--samples", "2"],
         ["bad.yaml", "no 'measurements' section"]),
    case("no clearance", "doe", lambda f: ["--config", _doe_config(f, _no_clearance),
                                           "--samples", "2"],
         ["doe.yaml", "measurements.joints", "clearance"]),
    case("unreachable --scheduler", "doe", lambda f: [
        "--config", _doe_config(f), "--samples", "2", "--scheduler", "no-port"],
        ["--scheduler no-port", "cannot connect"]),
    case("no measurements", "synthesize", lambda f: ["--config", f.config()],
         ["bad.yaml", "no 'measurements' section"]),
    case("unknown --only", "synthesize", lambda f: ["--config", f.config(), "--only", "all"],
         ["--only", "'all'"], code=2),
    case("missing --config", "kc", lambda f: [],
         ["give --config (one suspension) or --vehicle (the whole car)"], code=2),
    case("vehicle file: a key misspelt", "kc", lambda f: ["--vehicle", f.file(
        "car.yaml", "elastokin: 1\nname: car\nunits: {}\nfront: {config: a.yaml}\n"
                    "rear: {config: a.yaml}\nwheelbase_m: 3.0\n")],
         ["car.yaml: unknown top-level key 'wheelbase_m' (did you mean 'wheelbase_mm'?)"]),
    case("vehicle file: an axle config outside its folder", "kc", lambda f: ["--vehicle", f.file(
        "car.yaml", "elastokin: 1\nname: car\nunits: {}\nfront: {config: ../a.yaml}\n"
                    "rear: {config: a.yaml}\nwheelbase_mm: 3000\ncg_height_mm: 500\n"
                    "mass_kg: 1500\nfront_mass_fraction: 0.5\nbrake_fraction_front: 0.6\n"
                    "drive_fraction_front: 1\n")],
         ["car.yaml: key 'front.config': axle config '../a.yaml' leads to", "--data FOLDER"]),
    case("unknown option", "kc", lambda f: ["--config", f.config(), "--colour"],
         ["--colour"], code=2),
    case("unknown command", "frobnicate", lambda f: [], ["frobnicate"], code=2, out=False),
]


# ------------------------------------------------------------------------------ outputs
#: a command's valid input: the output is the only thing wrong
VALID = {
    "kc": lambda f: ["--config", f.config(name="nominal.yaml")],
    "identify": lambda f: ["--config", f.measured()],
    "doe": lambda f: ["--config", _doe_config(f), "--samples", "1", "--workers", "1"],
    "export-adams": lambda f: ["--config", f.config(name="nominal.yaml")],
    "synthesize": lambda f: ["--config", _doe_config(f), "--only", "cmm"],
    "import-adams": lambda f: ["--hardpoints", str(SUB), "--mapping", str(MAPPING),
                               "--template", str(WISHBONE)],
}
FOLDER_COMMANDS = ["kc", "identify", "doe", "export-adams", "synthesize"]


def _with_out(command, out):
    def args(f):
        return [*VALID[command](f), "--out", out(f)]
    return args


def _a_file(f):
    return f.file("earlier.txt", "a file of mine\n")


def _foreign_folder(f):
    f.file("mine/notes.txt", "keep me\n")
    return str(f.tmp / "mine")


def _under_a_file(f):
    return str(Path(f.file("plain_file", "a file of mine\n")) / "sub")


OUTPUT_CASES = [
    *(case("a file as --out", c, _with_out(c, _a_file),
           ["--out", "earlier.txt", "exists and is not a folder"], out=False)
      for c in FOLDER_COMMANDS),
    case("a folder as --out", "import-adams", _with_out("import-adams", _foreign_folder),
         ["--out", "mine", "is a folder"], out=False),
    *(case("a foreign folder as --out", c, _with_out(c, _foreign_folder),
           ["--out", "mine", "not empty"], out=False)
      for c in ("kc", "identify", "doe", "export-adams")),
    *(case("--out under a file", c, _with_out(c, _under_a_file),
           ["--out", "plain_file/sub", "cannot write", "Not a directory"], out=False)
      for c in [*FOLDER_COMMANDS, "import-adams"]),
    case("--kc-test-out under a file", "synthesize", lambda f: [
        "--config", _doe_config(f), "--only", "kc-test", "--kc-test-out", _under_a_file(f)],
        ["--kc-test-out", "plain_file/sub", "cannot write"]),
]

CASES = [*CONFIG_CASES, *RIG_CASES, *KC_TEST_CASES, *CMM_CASES, *ADAMS_CASES, *OPTION_CASES,
         *OUTPUT_CASES]


# ------------------------------------------------------------------------------ the test
#: a file that tells each command its --out holds its earlier results
MARKER = {"kc": "summary.json", "identify": "identification.json", "doe": "doe.json",
          "export-adams": "hardpoints.tbl", "synthesize": None}
QUIET = {"kc", "identify", "doe"}


def earlier_results(command: str, tmp: Path) -> list[str]:
    """An --out holding earlier results of ``command`` (a marker file plus the file by which
    elastokin recognises its results); import-adams writes a file: an earlier config."""
    if command == "import-adams":
        (tmp / "earlier.yaml").write_text("# an earlier imported config\n")
        return ["--out", str(tmp / "earlier.yaml")]
    out = tmp / "earlier"
    out.mkdir()
    (out / "marker.txt").write_text("earlier results\n")
    if MARKER.get(command):
        (out / MARKER[command]).write_text('{"earlier": true}\n')
    return ["--out", str(out)]


def snapshot(tmp: Path) -> dict[str, bytes | None]:
    return {str(p.relative_to(tmp)): (p.read_bytes() if p.is_file() else None)
            for p in sorted(tmp.rglob("*"))}


@pytest.mark.parametrize("bad", CASES)
def test_bad_input_ends_in_one_clear_line(bad: Bad, tmp_path):
    inputs = Inputs(tmp_path / "in")
    inputs.tmp.mkdir()
    args = bad.args(inputs)
    if bad.out:
        args += earlier_results(bad.command, tmp_path)
    if bad.command in QUIET:
        args.append("--quiet")
    before = snapshot(tmp_path)
    result = CliRunner().invoke(main, [bad.command, *args])
    crash = ("" if result.exc_info is None or isinstance(result.exception, SystemExit)
             else "".join(traceback.format_exception(*result.exc_info)))
    assert not crash, crash
    message = result.output.strip()
    assert result.exit_code == bad.code, message
    assert message.startswith("elastokin: error: ") and "\n" not in message, message
    assert "Traceback" not in message
    for fragment in bad.expected:
        assert fragment in message, (fragment, message)
    # nothing written, nothing changed: earlier results (and every input) untouched
    assert snapshot(tmp_path) == before
    if bad.out and bad.command == "import-adams":
        assert (tmp_path / "earlier.yaml").read_text() == "# an earlier imported config\n"
    elif bad.out:
        assert (tmp_path / "earlier" / "marker.txt").read_text() == "earlier results\n"


def test_at_least_60_cases_over_every_command():
    assert len(CASES) >= 60
    commands = {p.values[0].command for p in CASES}
    assert {"kc", "identify", "synthesize", "doe", "import-adams", "export-adams"} <= commands


# ------------------------------------------------------------------------------ more outputs
@pytest.mark.parametrize("command", ["kc", "identify", "doe", "export-adams", "synthesize",
                                     "import-adams"])
def test_unwritable_folder_refused_before_computing(tmp_path, monkeypatch, command):
    """A folder in which no file can be created (the OS says so: read-only, no permission),
    simulated so that it fails for root too: one line, nothing written."""
    from elastokin.cli import common

    locked = tmp_path / "locked"
    locked.mkdir()
    real = common.tempfile.mkstemp

    def mkstemp(*args, dir=None, **kwargs):
        if dir is not None and Path(dir) == locked:
            raise PermissionError(13, "Permission denied", str(locked))
        return real(*args, dir=dir, **kwargs)

    monkeypatch.setattr(common.tempfile, "mkstemp", mkstemp)
    args = VALID[command](Inputs(tmp_path))
    out = locked / ("new.yaml" if command == "import-adams" else "res")
    before = snapshot(tmp_path)
    result = CliRunner().invoke(main, [command, *args, "--out", str(out)])
    assert result.exit_code == 1, result.output
    assert result.output.strip() == (f"elastokin: error: --out {out}: cannot write "
                                     "(Permission denied)")
    assert snapshot(tmp_path) == before


def test_failed_move_keeps_the_earlier_results(tmp_path, monkeypatch):
    """The new results cannot move into place (an OS error at the very end): the earlier
    results are back where they were and the error is one line."""
    from elastokin.cli import common

    config = Inputs(tmp_path).config(name="nominal.yaml")
    earlier_results("kc", tmp_path)
    before = snapshot(tmp_path / "earlier")
    real = Path.rename

    def rename(self, target):
        if self.name.startswith(".earlier.") and Path(target).name == "earlier":
            raise PermissionError(13, "Permission denied", str(self))
        return real(self, target)

    monkeypatch.setattr(common.Path, "rename", rename)
    result = CliRunner().invoke(main, ["kc", "--config", config, "--out",
                                       str(tmp_path / "earlier"), "--quiet"])
    assert result.exit_code == 1
    assert result.output.strip() == (f"elastokin: error: --out {tmp_path / 'earlier'}: cannot "
                                     "write (Permission denied)")
    assert snapshot(tmp_path / "earlier") == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["earlier", "nominal.yaml"]


# ------------------------------------------------------------------------------ warnings
def test_warnings_are_one_line_each_and_in_summary(tmp_path, monkeypatch):
    """Python warnings issued while `elastokin kc` runs: one readable line each on stderr (no
    source path, no warnings.warn line), each distinct message once, and in summary.json."""
    import json

    import numpy as np

    from elastokin.rig.steering import SteeringAxisWarning
    from elastokin.studies import kc_job

    real = kc_job.run_kc

    def run_kc(*args, **kwargs):
        for _ in range(3):
            warnings.warn(SteeringAxisWarning("nominal.yaml: steering axis undefined at 1 "
                                              "of 7 steps"), stacklevel=2)
            np.log(np.zeros(1))  # numpy: RuntimeWarning, divide by zero
        return real(*args, **kwargs)

    monkeypatch.setattr(kc_job, "run_kc", run_kc)
    config = Inputs(tmp_path).config(name="nominal.yaml")
    result = CliRunner().invoke(main, ["kc", "--config", config, "--out",
                                       str(tmp_path / "res"), "--quiet"])
    assert result.exit_code == 0, result.output
    lines = result.stderr.strip().splitlines()
    assert lines == [
        "elastokin: warning: nominal.yaml: steering axis undefined at 1 of 7 steps",
        "elastokin: warning: RuntimeWarning: divide by zero encountered in log"]
    summary = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert summary["warnings"] == [ln.removeprefix("elastokin: warning: ") for ln in lines]
    assert "warn(" not in result.output and ".py" not in result.output


def test_import_adams_warnings_printed_once(tmp_path):
    mapping = Inputs(tmp_path).file("m.yaml", yaml.safe_dump({
        "elastokin_adams_mapping": 1, "hardpoints": {"lca_front": "hpr_lca_front"}}))
    result = CliRunner().invoke(main, [
        "import-adams", "--hardpoints", str(SUB), "--mapping", mapping, "--template",
        str(WISHBONE), "--out", str(tmp_path / "new.yaml")])
    assert result.exit_code == 0, result.output
    warned = [ln for ln in result.stderr.splitlines() if ln.startswith("elastokin: warning: ")]
    assert any("takes the right point of 'lca_front'" in w for w in warned)
    assert len(warned) == len(set(warned)) == len(result.stderr.splitlines())
