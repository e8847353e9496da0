"""The ``elastokin`` command group: every command is registered here."""

from __future__ import annotations

import click

from elastokin.cli.adams import export_adams, import_adams
from elastokin.cli.doe import doe
from elastokin.cli.kc import identify, kc, synthesize
from elastokin.version import __version__


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="elastokin")
def main() -> None:
    """elastokin: suspension elastokinematics on Exudyn (units mm, N, N*mm, deg)."""



for command in (kc, identify, synthesize, doe, import_adams, export_adams):
    main.add_command(command)

if __name__ == "__main__":  # pragma: no cover
    main()
