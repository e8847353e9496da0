"""What every command shares: the one-line error exit, the output folder that is replaced
only when a run succeeded, and the ``--rig`` option."""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

import click

from elastokin.errors import ElastokinError


def fail(message: str) -> None:
    click.echo(f"elastokin: error: {message}", err=True)
    sys.exit(1)


class Output:
    """Write results into a temporary folder beside ``out`` and move it into place only when
    everything succeeded: a failed run leaves no partial results."""

    def __init__(self, out: Path, marker: str = "summary.json"):
        self.out = out
        self.marker = marker  # a file that says the folder holds elastokin results

    def __enter__(self) -> Path:
        out = self.out
        if out.exists() and not out.is_dir():
            raise ElastokinError(f"--out {out}: exists and is not a folder")
        if out.is_dir() and any(out.iterdir()) and not (out / self.marker).exists():
            raise ElastokinError(f"--out {out}: folder is not empty and holds no elastokin "
                                 f"results ({self.marker}); choose another folder")
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


#: ``--rig FILE`` of the commands that run the rig's load cases (kc, doe)
rig_option = click.option(
    "--rig", "rig_path", type=click.Path(dir_okay=False, path_type=Path), default=None,
    show_default="the config's rig section",
    help="Rig file (YAML): the load cases to run instead of the config's 'rig' section "
         "(README 'Rig files'; e.g. configs/rigs/paper_fig9.yaml).")
