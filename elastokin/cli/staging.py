"""The hidden folders beside a command's results and the lock under which results move into
place (used by :class:`elastokin.cli.common.Output`).

A run writes its results into a staging folder beside them (``.NAME.xxxxxxxx``) and, when it
succeeds, moves the earlier results aside (into ``.NAME.old.xxxxxxxx``) and the new ones into
place. Each of these folders holds an owner file, ``.elastokin-owner.json`` (the pid, host and
start time of its process, the results folder it is for), which the process keeps locked
(``flock``) for as long as it uses the folder. The kernel drops that lock when the process
ends, however it ends (``kill -9``, a crash), so the next run into the same results folder
removes every such folder whose owner file it can lock: its run is gone. A lock, unlike a pid,
cannot be inherited by an unrelated process that got the dead owner's pid, and a run on
another host of a shared drive holds its lock there too. Where the file system cannot lock,
the recorded pid, host and process start time decide: a folder is removed only when its host
is this one and no process with that pid and start time is alive. A folder whose run died
while the earlier results were moved aside (its ``previous`` there, the results folder
missing) gives them back first. A folder without an owner file (an older elastokin's, or one
whose run was killed between making the folder and its owner file) is removed once it has not
changed for a day. Folders and owner files are made, and stale ones removed, under the move
lock, so no run sees another's folder before its owner file is locked.

The move lock is ``.NAME.lock`` beside the results folder. Its holder removes it while it still
holds it, then releases it; a run that was waiting on the removed file gets the lock on a file
no longer named ``.NAME.lock`` (the path is gone or names a newer file), sees that, and tries
again on the path's current file. So two runs never hold the lock at once and lock files never
pile up: at most one stays, left by a run killed while moving its results in, and the next run
uses and removes it. Without ``fcntl`` (Windows), or on a file system without ``flock``, the
lock is :mod:`filelock`'s (its file stays); without ``fcntl`` stale folders are left alone (no
way to tell a live owner).
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import re
import shutil
import socket
import time
import warnings
from datetime import UTC, datetime
from pathlib import Path

try:
    import fcntl
except ImportError:  # Windows
    fcntl = None

OWNER = ".elastokin-owner.json"
#: a staging folder without an owner file is removed once unchanged this long (s)
UNOWNED_AFTER_S = 86400.0
_CLOEXEC = getattr(os, "O_CLOEXEC", 0)
_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)


class StagingWarning(UserWarning):
    """A staging folder left by a run that ended was removed (or its results given back)."""


# -------------------------------------------------------------------------------- move lock
@contextlib.contextmanager
def move_lock(out: Path, timeout_s: float = 600.0):
    """Hold the lock on moving results into ``out`` (``out.parent`` must exist)."""
    path = out.parent / f".{out.name}.lock"
    try:
        fd = _acquire(path, timeout_s) if fcntl is not None else None
    except OSError as exc:
        if exc.errno not in (errno.ENOLCK, errno.EOPNOTSUPP, errno.ENOSYS):
            raise
        fd = None  # a file system without flock: filelock's own fallback
    if fd is None:
        from filelock import FileLock

        with FileLock(path, timeout=timeout_s):
            yield
        return
    try:
        yield
    finally:
        with contextlib.suppress(OSError):
            os.unlink(path)  # while still held: see the module's docstring
        os.close(fd)  # releases the lock


def _acquire(path: Path, timeout_s: float) -> int:
    """A descriptor of ``path`` locked by this process, ``path`` still naming it."""
    deadline = time.monotonic() + timeout_s
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | _CLOEXEC | _NOFOLLOW, 0o644)
        except OSError as exc:
            raise OSError(exc.errno, f"lock file {path}: {exc.strerror}") from exc
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            if time.monotonic() > deadline:
                raise TimeoutError(f"{path}: held by another elastokin run for over "
                                   f"{timeout_s:.0f} s") from None
            time.sleep(0.01)
            continue
        except OSError:
            os.close(fd)
            raise
        try:
            now = os.stat(path)
        except FileNotFoundError:
            now = None
        mine = os.fstat(fd)
        if now is not None and (now.st_dev, now.st_ino) == (mine.st_dev, mine.st_ino):
            return fd
        os.close(fd)  # its holder removed it before releasing: lock the current file


# ----------------------------------------------------------------------------- owner files
def _proc_start(pid: int) -> str | None:
    """The process's start time in clock ticks since boot (Linux /proc), or None."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
        return stat[stat.rindex(")") + 2:].split()[19]  # field 22 of proc(5)
    except (OSError, ValueError, IndexError):
        return None


def _boot_id() -> str | None:
    try:
        return Path("/proc/sys/kernel/random/boot_id").read_text().strip()
    except OSError:
        return None


def claim(folder: Path, out: Path) -> int:
    """Write ``folder``'s owner file and lock it: the descriptor returned holds the lock and
    stays open as long as the folder is in use (close it with :func:`release`)."""
    info = {"results": out.name, "pid": os.getpid(), "host": socket.gethostname(),
            "boot_id": _boot_id(), "start_ticks": _proc_start(os.getpid()),
            "started": datetime.now(UTC).isoformat(timespec="seconds")}
    fd = os.open(folder / OWNER, os.O_RDWR | os.O_CREAT | os.O_EXCL | _CLOEXEC, 0o644)
    if fcntl is not None:
        with contextlib.suppress(OSError):  # a file system without locks: the pid decides
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    os.write(fd, json.dumps(info).encode())
    return fd


def release(fd: int | None) -> None:
    if fd is not None:
        with contextlib.suppress(OSError):
            os.close(fd)


def _owner_gone(fd: int, info: dict) -> bool:
    """Whether the run owning the (open) owner file ``fd`` has ended."""
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return True  # nobody holds it: the owner is gone
    except BlockingIOError:
        return False
    except OSError:
        return process_gone(info)


def process_gone(info: dict) -> bool:
    """From an owner file's record only (file systems without locks): True when it was made
    on this host, since this boot, and no process with its pid and start time is alive."""
    if info.get("host") != socket.gethostname() or not isinstance(info.get("pid"), int):
        return False  # another host's run: no way to tell
    if info.get("boot_id") != _boot_id():
        return True  # made before this machine's last boot
    try:
        os.kill(info["pid"], 0)
    except ProcessLookupError:
        return True
    except OSError:
        pass  # alive, another user's
    return info.get("start_ticks") is not None and _proc_start(info["pid"]) != \
        info["start_ticks"]  # the pid is now another process's


# ---------------------------------------------------------------------------- stale folders
def remove_stale(out: Path) -> None:
    """Remove the staging folders beside ``out`` of runs that ended (module docstring), each
    with a :class:`StagingWarning`. Call under :func:`move_lock`."""
    if fcntl is None:
        return
    pattern = re.compile(rf"\.{re.escape(out.name)}\.(old\.)?[a-z0-9_]{{8}}")
    try:
        names = sorted(os.listdir(out.parent))
    except OSError:
        return
    for name in names:
        folder = out.parent / name
        if pattern.fullmatch(name) and folder.is_dir() and not folder.is_symlink():
            with contextlib.suppress(OSError):  # gone meanwhile, or cannot be given back
                _remove_if_stale(folder, out)


def _remove_if_stale(folder: Path, out: Path) -> None:
    try:
        fd = os.open(folder / OWNER, os.O_RDONLY | _NOFOLLOW | _CLOEXEC)
    except FileNotFoundError:
        if time.time() - folder.stat().st_mtime > UNOWNED_AFTER_S and (
                out.exists() or not (folder / "previous").exists()):
            _remove(folder, "a staging folder without an owner, unchanged for over a day")
        return
    except OSError:
        return  # not ours to judge (another user's, unreadable)
    try:
        try:
            info = json.loads(os.read(fd, 4096) or b"{}")
        except ValueError:
            info = {}
        info = info if isinstance(info, dict) else {}
        if info.get("results", out.name) != out.name or not _owner_gone(fd, info):
            return
        if not os.path.lexists(folder / OWNER):
            return  # its run removed it (the owner file first, then the lock) meanwhile
        who = (f"the run (pid {info.get('pid', '?')} on {info.get('host', '?')}, started "
               f"{info.get('started', '?')}) that left it has ended")
        previous = folder / "previous"
        if previous.is_dir() and not previous.is_symlink() and not os.path.lexists(out):
            previous.rename(out)
            who += f"; it had moved the earlier results aside: they are back in {out}"
        _remove(folder, who)
    finally:
        os.close(fd)


def _remove(folder: Path, why: str) -> None:
    shutil.rmtree(folder, ignore_errors=True)
    warnings.warn(StagingWarning(f"removed {folder}: {why}"), stacklevel=2)
