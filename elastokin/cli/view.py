"""``elastokin view``: the 3D view of a config as a page (plotly, offline), at the design
position without solving (a config with errors shows what resolved and lists the errors), or
animated through one solved load case."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import click

from elastokin.cli.common import (
    WarningLog,
    check_writable,
    fail,
    one_line_errors,
    rig_option,
)


@click.command()
@click.argument("config_path", metavar="CONFIG",
                type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--out", "out_path", type=click.Path(dir_okay=False, path_type=Path),
              metavar="FILE", default=None, show_default="results/<config name>.view.html",
              help="The page to write (HTML, self-contained: opens without a network).")
@click.option("--load-case", "load_case", default=None, metavar="NAME",
              help="Solve this load case of the rig (e.g. parallel_travel, steering) and "
                   "animate it; the config must then be free of errors.")
@rig_option
def view(config_path: Path, out_path: Path | None, load_case: str | None,
         rig_path: Path | None) -> None:
    """Write an interactive 3D view of CONFIG: every part, joint, bushing, spring, stop and
    wheel at the design position (nothing solved: about a second), with the steering axes,
    instant centres and roll centre; open it in a browser. A config with errors still shows
    what resolved, and lists the errors beside it (the command then exits 1). With
    --load-case, the config's model is solved through that load case and the page animates
    it (slider and play button). Units mm, config frame."""
    from elastokin.config.draft import draft_of, draft_suspension
    from elastokin.report.view3d import model_view, write_view_page

    out_path = out_path or Path("results") / f"{config_path.stem}.view.html"
    with WarningLog() as log, one_line_errors():
        check_writable(out_path)
        if load_case is None:
            draft = draft_suspension(config_path)
            views = [design_view(draft)]
        else:
            from elastokin.config.loading import load_suspension_with_rig
            from elastokin.studies.view import load_case_sweeps

            s = load_suspension_with_rig(config_path, rig_path)
            draft = draft_of(s)
            mv = model_view(s.label, s, {load_case: load_case_sweeps(s, load_case)})
            mv.frames = mv.frames[1:] + mv.frames[:1]  # the load case first
            views = [mv]
        notes = [f"{draft.source}: {views[0].scene.frame_text}; mm. elastokin view."]
        _write(out_path, lambda p: write_view_page(p, f"{draft.name} (3D view)", views,
                                                   list(draft.errors), notes))
    log.echo()
    click.echo(f"wrote {out_path}: open it in a browser")
    if draft.errors:
        for e in draft.errors:
            click.echo(f"elastokin: error: {e}", err=True)
        fail(f"{config_path}: {len(draft.errors)} error{'s' if len(draft.errors) > 1 else ''} "
             "in the config (listed in the page too; what they name is not drawn)")


def design_view(draft):
    """The design-position view of a config draft."""
    from elastokin.report.view3d import ModelView
    from elastokin.rig.scene import build_scene
    from elastokin.rig.scene_motion import design_frames

    scene = build_scene(draft)
    return ModelView("design", scene, [design_frames(scene, draft.suspension)])


def _write(path: Path, write) -> None:
    """``write(tmp)`` into a temporary file beside ``path``, then moved into place."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    os.close(fd)
    try:
        write(Path(tmp))
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
