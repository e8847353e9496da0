"""A killed run leaves nothing behind (elastokin.cli.staging): the next run into the same
results folder removes the staging folders of runs that ended, never a live run's; the move
lock's file is removed by its holder, so lock files do not pile up."""

import hashlib
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from elastokin.cli import main, staging
from elastokin.cli.common import Output

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"
DW = ROOT / "tests" / "data" / "double_wishbone.yaml"
TRAVEL = ROOT / "configs" / "rigs" / "travel_only.yaml"


def snapshot(folder: Path) -> dict[str, bytes | None]:
    return {str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else None)
            for p in sorted(folder.rglob("*"))}


def beside(out: Path) -> list[str]:
    """What lies beside the results folder, but the results folder."""
    return sorted(p.name for p in out.parent.iterdir() if p.name != out.name)


def kc(out: Path, *extra: str):
    return CliRunner().invoke(main, ["kc", "--config", str(DW), "--rig", str(TRAVEL), "--out",
                                     str(out), "--quiet", *extra])


def test_kill_9_during_kc_leaves_nothing_behind(tmp_path):
    """`kill -9` of `elastokin kc` while it computes: the earlier results are intact, its
    staging folder stays (nothing can run at a kill -9); the next run removes it, with one
    warning naming it and the dead run, and leaves no lock file anywhere."""
    out = tmp_path / "res"
    assert kc(out).exit_code == 0
    before = snapshot(out)
    proc = subprocess.Popen(
        [sys.executable, "-c", "import sys; from elastokin.cli import main; sys.exit(main())",
         "kc", "--config", str(CASE), "--rig", str(TRAVEL), "--out", str(out), "--quiet",
         "--refit"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    while not [p for p in tmp_path.glob(f".res.*/{staging.OWNER}") if p.stat().st_size]:
        assert proc.poll() is None and time.monotonic() < deadline
        time.sleep(0.01)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    assert snapshot(out) == before
    left = beside(out)
    assert len(left) == 1 and left[0].startswith(".res.")  # the killed run's staging folder
    owner = json.loads((tmp_path / left[0] / staging.OWNER).read_text())
    assert owner["pid"] == proc.pid and owner["results"] == "res"
    result = kc(out)
    assert result.exit_code == 0, result.output
    warnings = [line for line in result.output.splitlines() if "removed" in line]
    assert warnings == [f"elastokin: warning: removed {tmp_path / left[0]}: the run (pid "
                        f"{proc.pid} on {owner['host']}, started {owner['started']}) that "
                        "left it has ended"]
    assert beside(out) == []
    assert json.loads((out / "summary.json").read_text())["reused_from_cache"] == ["models"]


def test_lock_files_do_not_pile_up(tmp_path):
    """Several runs into one folder, one after the other and three at once: no lock file
    beside the results afterwards, none in the temporary folder (where elastokin kept one
    per results folder for good)."""
    out = tmp_path / "res"
    old_style = Path(tempfile.gettempdir()) / (
        "elastokin-results-" + hashlib.sha256(os.path.abspath(out).encode()).hexdigest()[:16]
        + ".lock")

    def run(tag: str) -> None:
        with Output(out) as tmp:
            (tmp / "summary.json").write_text(tag)

    for k in range(5):
        run(str(k))
    threads = [threading.Thread(target=run, args=(f"t{i}",)) for i in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert beside(out) == [] and not old_style.exists()
    assert (out / "summary.json").read_text() in {"t0", "t1", "t2"}


def test_a_waiter_on_a_removed_lock_file_tries_again(tmp_path, monkeypatch):
    """The race that keeps lock files from being removed elsewhere: a run opens the lock file,
    the holder removes it and releases it, the run then locks a file no longer in the folder.
    It must see that and lock the file the path names now."""
    out = tmp_path / "res"
    held = staging.move_lock(out)
    held.__enter__()
    real_open, opened = os.open, []

    def open_then_release(path, flags, mode=0o777, **kwargs):
        fd = real_open(path, flags, mode, **kwargs)
        if str(path).endswith(".res.lock"):
            opened.append(os.fstat(fd).st_ino)
            if len(opened) == 1:
                held.__exit__(None, None, None)  # removes the file this run just opened
        return fd

    monkeypatch.setattr(staging.os, "open", open_then_release)
    with staging.move_lock(out):
        assert len(opened) == 2  # the first file was gone: locked again, on the new one
        assert (tmp_path / ".res.lock").stat().st_ino == opened[1]
    assert not (tmp_path / ".res.lock").exists()


def test_a_live_runs_staging_folder_is_never_removed(tmp_path):
    """A run that starts and finishes while another writes into the same results folder
    leaves the other's staging folder alone (its owner holds the lock on its owner file)."""
    out = tmp_path / "res"
    first = Output(out)
    tmp = first.__enter__()
    (tmp / "summary.json").write_text("first")
    with Output(out) as second:
        (second / "summary.json").write_text("second")
    assert tmp.is_dir() and (out / "summary.json").read_text() == "second"
    first.__exit__(None, None, None)
    assert (out / "summary.json").read_text() == "first" and beside(out) == []


def _dead_owner(folder: Path, results: str, **info) -> None:
    """``folder`` with the owner file of a run that ended (nobody holds its lock)."""
    folder.mkdir()
    record = {"results": results, "pid": 1, "host": "elsewhere", "started": "then", **info}
    (folder / staging.OWNER).write_text(json.dumps(record))


def test_results_moved_aside_by_a_killed_run_come_back(tmp_path):
    """A run killed between moving the earlier results aside and moving its own in: the
    next run gives the earlier results back (then replaces them as usual)."""
    out = tmp_path / "res"
    aside = tmp_path / ".res.old.abcd1234"
    _dead_owner(aside, "res")
    (aside / "previous").mkdir()
    (aside / "previous" / "summary.json").write_text("earlier")
    with pytest.warns(staging.StagingWarning, match="they are back in") as caught:
        first = Output(out)
        first.__enter__()
    assert (out / "summary.json").read_text() == "earlier" and str(aside) in str(
        caught[0].message)
    first.__exit__(RuntimeError, RuntimeError("the run failed"), None)
    assert (out / "summary.json").read_text() == "earlier" and beside(out) == []


def test_only_this_results_folders_stale_staging_folders_are_removed(tmp_path):
    """Beside `res`: another results folder's staging folder, a staging folder of `res.old`
    (named like `res`'s moved-aside folder), a user's hidden files, and staging folders
    without an owner file (an older elastokin's): only `res`'s dead one goes, and an
    ownerless one once it has not changed for a day."""
    out = tmp_path / "res"
    _dead_owner(tmp_path / ".res.dead1234", "res")
    _dead_owner(tmp_path / ".res2.dead1234", "res2")
    _dead_owner(tmp_path / ".res.old.dead1234", "res.old")
    (tmp_path / ".res.notes").write_text("mine")
    (tmp_path / ".res.keep_me_").mkdir()  # recent, no owner: maybe a live older elastokin
    old = tmp_path / ".res.oldstuff"
    old.mkdir()
    day_ago = time.time() - 2 * staging.UNOWNED_AFTER_S
    os.utime(old, (day_ago, day_ago))
    with pytest.warns(staging.StagingWarning) as caught:
        with Output(out) as tmp:
            (tmp / "summary.json").write_text("new")
    assert beside(out) == [".res.keep_me_", ".res.notes", ".res.old.dead1234", ".res2.dead1234"]
    assert sorted(str(w.message).split(":")[0] for w in caught) == [
        f"removed {tmp_path / '.res.dead1234'}", f"removed {old}"]


def test_a_dead_owner_is_told_from_its_record_where_files_cannot_be_locked():
    """Without file locks (some network file systems) the owner's record decides: gone when
    its pid is not running, or runs another process (pid reuse: another start time), or the
    machine has rebooted since; a run on another host is never taken for dead."""
    here = {"host": staging.socket.gethostname(), "boot_id": staging._boot_id()}
    me = {**here, "pid": os.getpid(), "start_ticks": staging._proc_start(os.getpid())}
    assert not staging.process_gone(me)
    assert staging.process_gone({**me, "start_ticks": "1"})  # the pid, now another process's
    assert staging.process_gone({**me, "boot_id": "another boot"})
    assert not staging.process_gone({**me, "host": "another-host", "pid": 2 ** 22 + 1})
    ended = subprocess.Popen([sys.executable, "-c", "pass"])
    ended.wait()
    assert staging.process_gone({**here, "pid": ended.pid, "start_ticks": None})


def test_a_linked_results_folder_is_replaced_where_it_points(tmp_path):
    """`--out` a symbolic link to a results folder (the user's own choice): the results are
    replaced in the folder it points to, the link kept (it used to be replaced by a folder,
    the linked folder keeping the old results)."""
    target = tmp_path / "shared" / "res"
    target.parent.mkdir()
    assert kc(target).exit_code == 0
    link = tmp_path / "res_link"
    link.symlink_to(target)
    (target / "kc.csv").write_text("old\n")
    result = kc(link)
    assert result.exit_code == 0, result.output
    assert link.is_symlink() and (target / "kc.csv").read_text() != "old\n"
    assert beside(target) == [] and sorted(p.name for p in tmp_path.iterdir()) == [
        "res_link", "shared"]


@pytest.mark.parametrize("where", [".", ".."])
def test_the_current_folder_as_out_is_refused_before_computing(tmp_path, monkeypatch, where):
    """`--out .` (or a folder above): it would be replaced as a whole, under the user's
    feet; one line naming it and what to give instead (was 'Device or resource busy' after
    the whole computation)."""
    (tmp_path / "here").mkdir()
    monkeypatch.chdir(tmp_path / "here")
    result = kc(Path(where))
    assert result.exit_code == 1
    assert result.output.strip() == (
        f"elastokin: error: --out {where}: the current folder or one above it, which a run "
        f"would replace as a whole; name a folder inside it, e.g. {Path(where) / 'results'}")
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["here"]


def test_a_folder_where_the_lock_file_goes_is_named(tmp_path):
    """Something that is not a lock file at `.NAME.lock` (here a folder): one line naming it,
    the earlier results untouched."""
    out = tmp_path / "res"
    out.mkdir()
    (out / "summary.json").write_text("earlier")
    (tmp_path / ".res.lock").mkdir()
    result = kc(out)
    assert result.exit_code == 1
    assert result.output.strip() == (f"elastokin: error: --out {out}: cannot write (lock file "
                                     f"{tmp_path / '.res.lock'}: Is a directory)")
    assert (out / "summary.json").read_text() == "earlier" and beside(out) == [".res.lock"]
