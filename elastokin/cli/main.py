"""The ``elastokin`` command group: every command is registered here. Command-line usage
errors (unknown option or command, invalid choice, missing option) end in one line on stderr,
like every other error, with click's exit code 2."""

from __future__ import annotations

import click

from elastokin.cli.adams import export_adams, import_adams
from elastokin.cli.design import optimize, sensitivity
from elastokin.cli.doe import doe
from elastokin.cli.kc import identify, kc, synthesize
from elastokin.cli.view import view
from elastokin.version import __version__


class UsageErrorLine(click.ClickException):
    """A click usage error shown as one line: ``elastokin: error: <what> (see '<command>
    --help')``."""

    def __init__(self, error: click.ClickException):
        ctx = getattr(error, "ctx", None)
        hint = f" (see '{ctx.command_path} --help')" if ctx is not None else ""
        super().__init__(" ".join(error.format_message().split()) + hint)
        self.exit_code = error.exit_code

    def show(self, file=None) -> None:
        click.echo(f"elastokin: error: {self.format_message()}", err=True)


class Group(click.Group):
    """The command group, with usage errors on one line."""

    def make_context(self, *args, **kwargs) -> click.Context:
        try:
            return super().make_context(*args, **kwargs)
        except click.ClickException as exc:
            raise UsageErrorLine(exc) from exc

    def invoke(self, ctx: click.Context):
        try:
            return super().invoke(ctx)
        except click.ClickException as exc:  # a sub-command's options
            raise UsageErrorLine(exc) from exc


@click.group("elastokin", cls=Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="elastokin")
def main() -> None:
    """elastokin: suspension elastokinematics on Exudyn (units mm, N, N*mm, deg)."""


for command in (kc, identify, synthesize, doe, optimize, sensitivity, import_adams,
                export_adams, view):
    main.add_command(command)

if __name__ == "__main__":  # pragma: no cover
    main()
