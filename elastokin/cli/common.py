"""What every command shares: the one-line error exit, the output checked before any
computation and replaced only when a run succeeded (its staging folders and move lock:
:mod:`elastokin.cli.staging`), the Python warnings of a run as one line each, the progress
bar and the ``--rig`` option."""

from __future__ import annotations

import contextlib
import errno
import functools
import os
import shutil
import sys
import tempfile
import warnings
from collections.abc import Iterable
from pathlib import Path

import click

from elastokin.cli.staging import OWNER, claim, move_lock, release, remove_stale
from elastokin.errors import ElastokinError


def fail(message: str) -> None:
    click.echo(f"elastokin: error: {message}", err=True)
    sys.exit(1)


def os_error(exc: OSError) -> str:
    """An OS error as the rest of one error line: the file it names and the reason."""
    reason = exc.strerror or str(exc)
    return f"{exc.filename}: {reason}" if exc.filename else reason


@contextlib.contextmanager
def one_line_errors():
    """A command's body: an :class:`~elastokin.errors.ElastokinError` (bad input, no
    convergence, ...) or an OS error (a file that cannot be read or written) ends the command
    with its one error line and exit code 1, never a traceback."""
    try:
        yield
    except ElastokinError as exc:
        fail(str(exc))
    except OSError as exc:
        fail(os_error(exc))


def cannot_write(option: str, path: Path, reason: str) -> ElastokinError:
    return ElastokinError(f"{option} {path}: cannot write ({reason})")


def check_writable(path: Path, option: str = "--out") -> None:
    """Refuse, before any computation, an output ``path`` (a file or a folder, created or
    replaced) whose folder cannot be written: the nearest existing folder at or above its
    parent (and ``path`` itself when it is a folder) must be a folder in which a file can be
    created. Probed by creating and deleting a file, since permissions alone do not tell (root,
    read-only file systems)."""
    try:
        existing = Path(os.path.abspath(path)).parent
        while not existing.exists():
            existing = existing.parent
        if not existing.is_dir():
            raise cannot_write(option, path, f"{os.strerror(errno.ENOTDIR)}: {existing}")
        for folder in [existing] + ([path] if path.is_dir() else []):
            try:
                fd, probe = tempfile.mkstemp(prefix=".elastokin-probe-", dir=folder)
                os.close(fd)
                os.unlink(probe)
            except FileNotFoundError:
                if folder == path:
                    # another run replaced the folder meanwhile (moved aside with the probe
                    # in it, its own moved in): the parent, probed first, is what counts
                    continue
                raise
    except OSError as exc:
        raise cannot_write(option, path, exc.strerror or str(exc)) from exc


class Output:
    """Write results into a staging folder beside ``out`` and move it into place only when
    everything succeeded: a failed run leaves no partial results and the previous ones
    untouched; a killed run's staging folder is removed by the next run into ``out``
    (:mod:`elastokin.cli.staging`). :meth:`check` refuses an unusable ``out`` before any
    computation."""

    def __init__(self, out: Path, marker: str | tuple[str, ...] = "summary.json",
                 option: str = "--out"):
        self.out = out  # as given: named in messages
        # a link the user gave: the results replace the folder it points to, not the link
        self.target = Path(os.path.realpath(out)) if out.is_symlink() else out
        # a file (any of them) that says the folder holds elastokin results
        self.markers = (marker,) if isinstance(marker, str) else tuple(marker)
        self.option = option
        self.owner: int | None = None  # the staging folder's locked owner file

    def check(self) -> None:
        """Not a file, not a foreign non-empty folder, and its folder writable."""
        out, opt = self.out, self.option
        if Path.cwd().is_relative_to(os.path.realpath(out)):
            raise ElastokinError(f"{opt} {out}: the current folder or one above it, which a "
                                 "run would replace as a whole; name a folder inside it, e.g. "
                                 f"{out / 'results'}")
        if out.exists() and not out.is_dir():
            raise ElastokinError(f"{opt} {out}: exists and is not a folder")
        if out.is_dir() and any(out.iterdir()) and not any(
                (out / m).exists() for m in self.markers):
            raise ElastokinError(f"{opt} {out}: folder is not empty and holds no elastokin "
                                 f"results ({' or '.join(self.markers)}); choose another "
                                 "folder")
        check_writable(out, opt)

    def __enter__(self) -> Path:
        self.check()
        out = self.target
        try:
            out.parent.mkdir(parents=True, exist_ok=True)
            with move_lock(out):  # not while another run moves its results in
                self.check()
                remove_stale(out)  # staging folders of runs that ended
                self.tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
                self.owner = claim(self.tmp, out)
            self.tmp.chmod(0o755)
        except OSError as exc:
            raise cannot_write(self.option, self.out, exc.strerror or str(exc)) from exc
        return self.tmp

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            self._finish(exc_type, exc)
        finally:
            release(self.owner)

    def _finish(self, exc_type, exc) -> None:
        if exc_type is not None:
            shutil.rmtree(self.tmp, ignore_errors=True)
            if isinstance(exc, OSError) and isinstance(exc.filename, str) and \
                    Path(exc.filename).is_relative_to(self.tmp):
                raise cannot_write(self.option, self.out, exc.strerror or str(exc)) from exc
            return
        old, old_owner = None, None
        try:
            with move_lock(self.target):
                (self.tmp / OWNER).unlink(missing_ok=True)  # not into the results
                old, old_owner = self._move_into_place()
        except OSError as exc:
            shutil.rmtree(self.tmp, ignore_errors=True)
            raise cannot_write(self.option, self.out, exc.strerror or str(exc)) from exc
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
            release(old_owner)

    def _move_into_place(self) -> tuple[Path | None, int | None]:
        """Move the earlier results aside (returns the folder they are in, None without, and
        its owner file) and the new ones into place; when the new cannot move in, the earlier
        ones move back (their folder kept if even that fails, so that they are never lost)."""
        old, owner = None, None
        try:
            if self.target.exists():
                old = Path(tempfile.mkdtemp(prefix=f".{self.target.name}.old.",
                                            dir=self.target.parent))
                owner = claim(old, self.target)
                self.target.rename(old / "previous")
            self.tmp.rename(self.target)
        except OSError:
            if old is not None:
                if (old / "previous").exists():
                    (old / "previous").rename(self.target)
                shutil.rmtree(old, ignore_errors=True)  # empty: the earlier results are back
            release(owner)
            raise
        return old, owner


def _one_line(message) -> str:
    return " ".join(str(message).split())


class WarningLog:
    """The Python warnings issued while a command runs (:class:`warnings.catch_warnings`),
    as readable one-line messages, each distinct message once, in the order issued. Warnings
    meant for developers (deprecations, unclosed resources) are dropped."""

    def __enter__(self) -> WarningLog:
        self._catch = warnings.catch_warnings(record=True)
        self._caught = self._catch.__enter__()
        warnings.simplefilter("always")
        for category in (DeprecationWarning, PendingDeprecationWarning, ResourceWarning):
            warnings.simplefilter("ignore", category)
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self._catch.__exit__(exc_type, exc, tb)

    @property
    def messages(self) -> list[str]:
        out: dict[str, None] = {}
        for w in self._caught:
            text = _one_line(w.message)
            if not w.category.__module__.startswith("elastokin"):
                text = f"{w.category.__name__}: {text}"  # numpy, scipy, ...
            out[text] = None
        return list(out)

    def echo(self, first: Iterable[str] = ()) -> None:
        """Print ``first`` (warnings the command collected itself), then every caught
        warning, each distinct message once, as ``elastokin: warning: <message>``."""
        for text in dict.fromkeys([*map(_one_line, first), *self.messages]):
            click.echo(f"elastokin: warning: {text}", err=True)


#: ``--rig FILE`` of the commands that run the rig's load cases (kc, doe)
rig_option = click.option(
    "--rig", "rig_path", type=click.Path(dir_okay=False, path_type=Path), default=None,
    show_default="the config's rig section",
    help="Rig file (YAML): the load cases to run instead of the config's 'rig' section "
         "(README 'Rig files'; e.g. configs/rigs/paper_fig9.yaml).")


#: model runs the progress bar expects of a stiffness fit (the case study takes 6)
FIT_RUNS_EXPECTED = 7


@contextlib.contextmanager
def progress_bar(stages: int, quiet: bool = False):
    """A progress bar on stderr (elapsed time and an estimate of what is left) as a
    function ``progress(message)`` that shows the message and counts one stage; more stages
    than expected (a fit taking more model runs) extend the bar. Shown only on a terminal
    (not when stderr is piped or a file), never with ``quiet``."""
    from tqdm import tqdm

    with tqdm(total=max(stages, 1), disable=True if quiet else None, file=sys.stderr,
              leave=False,
              bar_format="{desc:<56} {bar} {n_fmt}/{total_fmt} [{elapsed}<{remaining}]"
              ) as bar:
        def progress(msg: str) -> None:
            if bar.n + 1 >= bar.total:
                bar.total = bar.n + 2
            bar.set_description_str(msg)
            bar.update(1)
        yield progress


def kc_stages(suspension, chosen: list[str]) -> int:
    """The stages ``elastokin kc`` reports for a config and the models ``chosen``: loading,
    each model's build and load cases, the identifications, the stiffness fit's model runs,
    writing."""
    from elastokin.studies.kc_job import fits_stiffness, model_labels

    s = suspension
    labels = [m for m in model_labels(s) if m in chosen]
    fit = fits_stiffness(s) and "identified_stiffness" in chosen
    return (3 + 2 * len(labels) + (s.measurements is not None) + (s.motion is not None)
            + (2 + FIT_RUNS_EXPECTED) * fit)


def data_option(command):
    """``--data FOLDER`` (repeatable) on a command that reads a config's data: the command
    runs with those folders allowed besides the config's own
    (:func:`elastokin.config.confined.data_folders`)."""

    @functools.wraps(command)
    def run(*args, data_typed: tuple[Path, ...] = (), **kwargs):
        from elastokin.config.confined import data_folders

        with data_folders(data_typed):
            return command(*args, **kwargs)

    return click.option(
        "--data", "data_typed", multiple=True, metavar="FOLDER",
        type=click.Path(file_okay=False, path_type=Path),
        help="A folder the config's data (CMM, motion and K&C test files) may also lie in, "
             "besides the config's own folder (repeatable; README 'Which paths may point "
             "anywhere'). E.g. --data configs for a config that identify wrote.")(run)


def data_hint(written: Path, suspension,
              sections: tuple[str, ...] = ("measurements", "motion", "kc_test")) -> str | None:
    """How to run the config ``written`` (by identify or import-adams) that names the data
    folders of ``suspension``'s ``sections`` as they are: the ``--data`` folders it needs,
    None when its data lie in its own folder."""
    from elastokin.config.confined import Roots, resolved

    own = Roots.of([written.parent], "")
    folders = [Path(suspension.source).parent / getattr(suspension, section).folder
               for section in sections if getattr(suspension, section, None) is not None]
    outside = list(dict.fromkeys(os.path.normpath(f) for f in folders
                                 if not own.hold(resolved(f))))
    if not outside:
        return None
    return (f"its data lie outside its folder: elastokin kc --config {written} "
            + " ".join(f"--data {f}" for f in outside))
