"""``elastokin import-adams`` and ``elastokin export-adams`` (ADAMS/Car files, see docs/adams.md).

Units at every interface: mm, N, N*mm, deg; ADAMS files are converted on reading and written in
mm, newton, degrees. Frames: ADAMS/Car's global frame (X rearward, Y right, Z up) in the ADAMS
files, the config's ``frame`` in elastokin configs. ``--out`` is checked before anything is
read; input errors end in one line on stderr and exit code 1; warnings are printed once each as
``elastokin: warning: ...`` lines.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path

import click

from elastokin.cli.common import (
    Output,
    WarningLog,
    check_writable,
    data_hint,
    data_option,
    fail,
    one_line_errors,
)
from elastokin.errors import ConfigError, ElastokinError


def _bushing_option(values: tuple[str, ...]) -> dict[str, Path]:
    out = {}
    for v in values:
        name, sep, file = v.partition("=")
        if not sep or not name.strip() or not file.strip():
            raise ConfigError(f"--bushing {v!r}: expected NAME=FILE.bus (an elastokin bushing "
                              "name and a bushing property file)")
        if name.strip() in out:
            raise ConfigError(f"--bushing: bushing '{name.strip()}' is given twice")
        out[name.strip()] = Path(file.strip())
    return out


def _sha(path: Path) -> str:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()[:12]
    except OSError:
        return "unreadable"


@click.command("import-adams")
@click.option("--hardpoints", "hardpoints_path", default=None,
              type=click.Path(path_type=Path),
              help="ADAMS/Car hardpoint table: a TeimOrbit file (.sub, .asy or table) with "
                   "{hardpoint_name symmetry x_value y_value z_value}, or an ADAMS/Car "
                   "database folder (or one of its .tbl folders) holding one subsystem file "
                   "or the mapping's subsystems.")
@click.option("--assembly", "assembly_path", default=None,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Instead of --hardpoints: an ADAMS/Car assembly (.asy); its suspension, "
                   "anti-roll bar and steering subsystems are read.")
@click.option("--subsystem", "subsystem_paths", multiple=True, metavar="FILE.sub",
              type=click.Path(dir_okay=False, path_type=Path),
              help="An axle's anti-roll bar or steering subsystem file (its MAJOR_ROLE says "
                   "which; repeatable).")
@click.option("--mapping", "mapping_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Mapping file (YAML, docs/adams.md): elastokin hardpoint -> ADAMS "
                   "hardpoint and side; optionally elastokin bushing -> .bus file; an axle's "
                   "anti_roll_bar and steering sections.")
@click.option("--template", "template_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="elastokin config whose topology, parts and laws are kept.")
@click.option("--bushing", "bushings", multiple=True, metavar="NAME=FILE.bus",
              help="Bushing property file (.bus or XML) for an elastokin bushing (repeatable; "
                   "overrides the mapping file's 'bushings').")
@click.option("--out", "out_path", required=True,
              type=click.Path(path_type=Path), metavar="FILE",
              help="The new elastokin config (YAML); written only when it is valid.")
def import_adams(hardpoints_path: Path | None, assembly_path: Path | None,
                 subsystem_paths: tuple[Path, ...], mapping_path: Path, template_path: Path,
                 bushings: tuple[str, ...], out_path: Path) -> None:
    """Build an elastokin config from ADAMS/Car files: the template config with its hardpoints
    from an ADAMS hardpoint table (converted from the ADAMS frame, X rearward / Y right / Z up,
    to the template's frame) and the stiffness of the named bushings from .bus files; for an
    axle template also the other side, the anti-roll bar and the steering rack ratio."""
    from elastokin.config.loading import read_yaml, suspension_from_dict
    from elastokin.config.variants import relabelled
    from elastokin.formats.adams.car import read_bushing
    from elastokin.formats.adams.database import input_roots
    from elastokin.formats.adams.importing import import_adams_axle, subsystem_files
    from elastokin.formats.adams.mapping import read_mapping
    from elastokin.formats.config_yaml import dump_config

    with WarningLog() as log:
        with one_line_errors():
            _check_out_file(out_path)  # before anything is read
            if (hardpoints_path is None) == (assembly_path is None):
                raise ConfigError("import-adams: give --hardpoints (a subsystem file or "
                                  "database) or --assembly (an .asy file), not both")
            template, _ = read_yaml(template_path)
            bus_files = _bushing_option(bushings)
            # what the files name must lie in the databases and folders typed here
            roots = input_roots([hardpoints_path, assembly_path, *subsystem_paths,
                                 mapping_path])
            mapping = read_mapping(mapping_path, roots)
            minor = mapping.subsystem.get("minor_role") or _position(template)
            files = subsystem_files(mapping, hardpoints_path, assembly_path, subsystem_paths,
                                    minor, roots)
            cfg, warnings, read = import_adams_axle(template, files, mapping_path, bus_files,
                                                    f"template {template_path}", roots)
            _keep_data_folders(cfg, template_path, out_path)
            # the new config must be valid; an error names the template it was made from
            new = suspension_from_dict(cfg, f"{out_path} (the template {template_path} with "
                                            "the ADAMS hardpoints and bushings)")
            hint = data_hint(out_path, relabelled(new, str(out_path)))
            subs = [f for f in (files.suspension, files.anti_roll_bar, files.steering) if f]
            sources = [*(f"subsystem {f} (sha256 {_sha(f)})" for f in subs),
                       f"mapping {mapping_path} (sha256 {_sha(mapping_path)})",
                       f"template {template_path} (sha256 {_sha(template_path)})",
                       *(_file_note(f, read_bushing) for f in dict.fromkeys(read))]
            text = dump_config(cfg, _import_header(sources, cfg["frame"]))
        try:
            _write_atomically(out_path, text)
        except OSError as exc:
            fail(f"--out {out_path}: cannot write ({exc.strerror or exc})")
    log.echo(warnings)
    click.echo(f"wrote {out_path}" + (f"; {hint}" if hint else ""))


def _position(template: dict) -> str | None:
    """The template's axle position (front, rear): the minor role of its subsystems."""
    axle = template.get("axle") if isinstance(template, dict) else None
    vehicle = axle.get("vehicle") if isinstance(axle, dict) else None
    return vehicle.get("position", "front") if isinstance(vehicle, dict) else None


def _file_note(path: Path, read_bushing) -> str:
    """A source line of the header: a curve file, or a bushing file with its interpolation
    note."""
    if path.suffix.lower() == ".crv":
        return f"curve {path} (sha256 {_sha(path)})"
    return f"bushing {path} (sha256 {_sha(path)}); {read_bushing(path).interpolation_note()}"


def _check_out_file(out_path: Path) -> None:
    if out_path.is_dir():
        raise ElastokinError(f"--out {out_path}: is a folder; expected the file name of the new "
                             "config")
    check_writable(out_path)


def _keep_data_folders(cfg: dict, template_path: Path, out_path: Path) -> None:
    """The template's CMM / K&C test folders as the new config names them
    (:func:`~elastokin.config.loading.relocated_folder`)."""
    from elastokin.config.loading import relocated_folder

    for key in ("measurements", "kc_test"):
        m = cfg.get(key)
        if isinstance(m, dict):
            m["folder"] = relocated_folder(m.get("folder", "."), template_path.parent,
                                           out_path.parent)


def _import_header(sources: list[str], frame: dict) -> str:
    return "\n".join(
        ["elastokin config imported from ADAMS/Car files by elastokin import-adams:",
         *(f"  {s}" for s in sources),
         "Units: lengths mm, forces N, torques N*mm, angles deg; hardpoints converted from "
         "the ADAMS/Car",
         f"frame (X rearward, Y right, Z up) to this config's frame (x {frame['x']}, "
         f"y {frame['y']}, z up)."])


def _write_atomically(out_path: Path, text: str) -> None:
    out_path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{out_path.name}.", dir=out_path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(text)
        os.chmod(tmp, 0o644)
        os.replace(tmp, out_path)
    except OSError:
        Path(tmp).unlink(missing_ok=True)
        raise


def _export_output(out_dir: Path):
    """The Output of export-adams: a folder holding an earlier export (its mapping.yaml, or
    the hardpoints.tbl of an export before the database layout) is replaced as a whole."""
    old = (out_dir / "hardpoints.tbl").is_file() and not (out_dir / "mapping.yaml").exists()
    return Output(out_dir, marker="hardpoints.tbl" if old else "mapping.yaml")


@click.command("export-adams")
@click.option("--config", "config_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="elastokin config (e.g. identified.yaml written by 'elastokin identify').")
@click.option("--out", "out_dir", required=True,
              type=click.Path(path_type=Path), metavar="DATABASE.cdb",
              help="Folder written as an ADAMS/Car database (subsystems.tbl, bushings.tbl, "
                   "springs.tbl, mapping.yaml); replaced as a whole when the export succeeds.")
@click.option("--mapping", "mapping_path", default=None,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Mapping file (YAML, docs/adams.md): the template's hardpoint names, bushing "
                   "and spring usages, and 'subsystem: {template, major_role, minor_role}'.")
@click.option("--template-name", default=None, metavar="MDIDS_PATH",
              help="The subsystem's TEMPLATE_NAME (e.g. "
                   "mdids://acar_shared/templates.tbl/_double_wishbone.tpl); overrides the "
                   "mapping file.")
@click.option("--major-role", default=None, help="MAJOR_ROLE (default: suspension).")
@click.option("--minor-role", default=None,
              help="MINOR_ROLE (default: front, or an axle's vehicle.position).")
@click.option("--database", default=None, metavar="ALIAS",
              show_default="the --out folder's name without .cdb",
              help="Database alias of the mdids:// paths in the subsystem file.")
@click.option("--identified", is_flag=True,
              help="Identify the geometry from the config's CMM measurements first and export "
                   "the identified model.")
@click.option("--kc", "kc_csv", default=None, type=click.Path(dir_okay=False, path_type=Path),
              help="An elastokin kc.csv of this config to write with ADAMS-style channel "
                   "names (kc_adams.csv).")
@click.option("--range-mm", default=10.0, show_default=True, type=float,
              help="Half-range of the tables written for linear translational rates (mm).")
@click.option("--range-deg", default=10.0, show_default=True, type=float,
              help="Half-range of the tables written for linear rotational rates (deg).")
@data_option
def export_adams(config_path: Path, out_dir: Path, mapping_path: Path | None,
                 template_name: str | None, major_role: str | None, minor_role: str | None,
                 database: str | None, identified: bool, kc_csv: Path | None,
                 range_mm: float, range_deg: float) -> None:
    """Write a suspension as an ADAMS/Car database: subsystems.tbl/<name>.sub (template and
    roles, hardpoints in the ADAMS frame with the template's names, bushing and spring
    assemblies), bushings.tbl/*.bus, springs.tbl/*.spr (mm, newton, deg), and mapping.yaml
    (for import-adams). An axle: its left/right pairs, and its anti-roll bar and steering
    subsystems (bar rate, rack_ratio) with an assembly (assemblies.tbl/<name>.asy)."""
    from elastokin.config.loading import load_suspension, suspension_from_dict
    from elastokin.formats.adams.export import export_adams as write_files
    from elastokin.formats.adams.export import subsystem_spec
    from elastokin.formats.adams.kc import write_adams_kc_csv
    from elastokin.formats.adams.mapping import read_mapping

    output = _export_output(out_dir)
    warnings: list[str] = []
    with WarningLog() as log, one_line_errors():
        output.check()  # before any computation
        mapping = read_mapping(mapping_path) if mapping_path is not None else None
        s = load_suspension(config_path)
        if identified:
            if s.measurements is None:
                raise ConfigError(f"{config_path}: --identified needs a 'measurements' "
                                  "section")
            from elastokin.studies.identification import identify_geometry

            ident = identify_geometry(s)
            s = suspension_from_dict(ident.identified_config, f"{config_path} (identified)",
                                     s.sha256)
        # an axle: both corners (left/right pairs), the anti-roll bar and the steering
        preload, springs = None, None
        if (s.design.balance_bushing_preloads and s.bushings) or s.design.balance_spring:
            from elastokin.mbs.design import design_state

            state = design_state(s)
            preload, springs = state.bushing_preload, state.spring_force_N
        spec = subsystem_spec(s, mapping, database, template_name, major_role, minor_role,
                              warnings, out_dir.name.removesuffix(".cdb"))
        with output as tmp:
            files = write_files(s, tmp, preload, range_mm, range_deg, spring_force=springs,
                                mapping=mapping, spec=spec, warnings=warnings)
            if kc_csv is not None:
                write_adams_kc_csv(kc_csv, tmp / "kc_adams.csv", s.frame)
                files.append(tmp / "kc_adams.csv")
            names = [f.relative_to(tmp).as_posix() for f in files]
    log.echo(warnings)
    click.echo(f"wrote {len(names)} files in {out_dir}/: " + ", ".join(names))
