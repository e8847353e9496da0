"""Command line: a thin layer over :mod:`elastokin.study`, :mod:`elastokin.results` and
:mod:`elastokin.plotting`. Errors in the input end in one line on stderr and exit code 1."""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

import click

from . import __version__
from .errors import ElastokinError


def _fail(message: str) -> None:
    click.echo(f"elastokin: error: {message}", err=True)
    sys.exit(1)


class _Output:
    """Write results into a temporary folder beside ``out`` and move it into place only when
    everything succeeded: a failed run leaves no partial results."""

    def __init__(self, out: Path):
        self.out = out

    def __enter__(self) -> Path:
        out = self.out
        if out.exists() and not out.is_dir():
            raise ElastokinError(f"--out {out}: exists and is not a folder")
        if out.is_dir() and any(out.iterdir()) and not (out / "summary.json").exists():
            raise ElastokinError(f"--out {out}: folder is not empty and holds no elastokin "
                                 "results (summary.json); choose another folder")
        out.parent.mkdir(parents=True, exist_ok=True)
        self.tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
        self.tmp.chmod(0o755)
        return self.tmp

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is not None:
            shutil.rmtree(self.tmp, ignore_errors=True)
            return
        if self.out.exists():
            shutil.rmtree(self.out)
        self.tmp.rename(self.out)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="elastokin")
def main() -> None:
    """elastokin: suspension elastokinematics on Exudyn (units mm, N, N*mm, deg)."""


@main.command()
@click.option("--config", "config_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Suspension config file (YAML, see README 'Config reference').")
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path),
              default=None, show_default="results/<config name>",
              help="Folder for kc.csv, summary.json and the charts; replaced as a whole when "
                   "the run succeeds, untouched when it fails.")
@click.option("--quiet", is_flag=True, help="No progress bar, no result table.")
def kc(config_path: Path, out_dir: Path | None, quiet: bool) -> None:
    """Run the virtual K&C rig: static equilibrium under the design wheel load and parallel
    wheel travel, for the initial model (and its kinematic counterpart).

    Writes kc.csv (one row per model, load case and step; units in column names),
    summary.json (steer amplitude, bump steer, Table-3 style bushing deflections, provenance)
    and steer_vs_travel.png/.svg.
    """
    from tqdm import tqdm

    from .config import load_suspension
    from .model import EXUDYN_VERSION
    from .plotting import steer_vs_travel
    from .results import provenance, summary_dict, write_kc_csv, write_summary
    from .study import model_variants, run_vertical_kc

    out_dir = out_dir or Path("results") / config_path.stem
    try:
        suspension = load_suspension(config_path)
        stages = 3 + 2 * len(model_variants(suspension))
        with tqdm(total=stages, disable=quiet, file=sys.stderr, leave=False,
                  bar_format="{desc:<45} {bar} {n_fmt}/{total_fmt} [{elapsed}]") as bar:
            def progress(msg: str) -> None:
                bar.set_description_str(msg)
                bar.update(1)
            run = run_vertical_kc(suspension, progress)
            progress("writing results")
            with _Output(out_dir) as tmp:
                prov = provenance(run, EXUDYN_VERSION)
                sweeps = [sw for m in run.models.values() for sw in m.sweeps]
                write_kc_csv(tmp / "kc.csv", sweeps, prov)
                files = ["kc.csv", "summary.json"]
                files += [p.name for p in steer_vs_travel(
                    [sw for sw in sweeps if sw.load_case == "parallel_travel"], tmp, prov)]
                summary = summary_dict(run, EXUDYN_VERSION, files)
                write_summary(tmp / "summary.json", summary)
    except ElastokinError as exc:
        _fail(str(exc))
    if not quiet:
        click.echo(_report(summary, out_dir))


def _report(summary: dict, out_dir: Path) -> str:
    lines = [f"elastokin {summary['elastokin_version']} (exudyn {summary['exudyn_version']}), "
             f"config {summary['config_file']} sha256 {summary['config_sha256'][:12]}", ""]
    st = summary["static"]
    residual = st["wheel_assembly_force_residual_N"]
    lines.append(f"Static equilibrium under {st['wheel_load_N']:g} N wheel load "
                 f"(force residual on the wheel assembly {residual:.1e} N)")
    lines.append(f"  {'bushing':<10}{'radial mm':>11}{'axial mm':>10}{'torsion deg':>13}"
                 f"   reference {st['reference_source']}")
    for name, b in st["bushings"].items():
        ref = b.get("reference", {})
        ref_txt = ", ".join(f"{k} {v:g}" for k, v in ref.items())
        lines.append(f"  {name:<10}{b['radial_mm']:>11.3f}{b['axial_mm']:>10.3f}"
                     f"{b['torsion_deg']:>13.4f}   {ref_txt}")
    lines.append("")
    lines.append(f"  {'model':<20}{'steer amplitude deg':>21}{'bump steer deg/m':>18}")
    for label, m in summary["models"].items():
        lines.append(f"  {label:<20}{m['steer_amplitude_deg']:>21.4f}"
                     f"{m['bump_steer_deg_per_m']:>18.3f}")
    refs = summary["reference"]["steer_amplitude_deg"]
    if refs:
        lines.append("  reference steer amplitude (deg): "
                     + ", ".join(f"{k} {v:g}" for k, v in refs.items()))
    lines.append("")
    lines.append(f"Results in {out_dir}/: " + ", ".join(summary["files"]))
    return "\n".join(lines)


if __name__ == "__main__":  # pragma: no cover
    main()
