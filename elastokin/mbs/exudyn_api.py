"""The one place Exudyn is imported: its console silenced, no GUI, and its errors turned into
one-line :class:`~elastokin.errors.SolverError` messages."""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Callable

from elastokin.errors import SolverError

os.environ.setdefault("EXUDYN_NO_GUI", "1")
import exudyn as exu  # noqa: E402

exu.config.printToConsole = False
EXUDYN_VERSION = exu.__version__


def exudyn_call(fn: Callable, what: str):
    """Call Exudyn, turning its errors into one-line :class:`SolverError` messages."""
    buf = io.StringIO()
    try:
        with contextlib.redirect_stdout(buf):
            return fn()
    except Exception as exc:  # Exudyn raises RuntimeError/ValueError with long traces
        lines = [ln.strip() for ln in str(exc).splitlines()]
        useful = [ln for ln in lines if ln and not ln.startswith(("At:", "/", "File", "<"))
                  and "check your Python code" not in ln]
        detail = "; ".join(useful[:2]) or type(exc).__name__
        raise SolverError(f"{what}: {detail}") from None
