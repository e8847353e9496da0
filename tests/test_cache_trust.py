"""A results folder from someone else never runs code (elastokin.studies.cache): an entry
is unpickled only once its HMAC under this user's secret key is verified; a foreign, altered,
planted or broken entry is one warning naming it, and the result is recomputed.

Every attack plants a pickle whose ``__reduce__`` creates a marker file: the marker must
never appear. The tests' secret key lives in their own XDG_CACHE_HOME (conftest)."""

import contextlib
import json
import os
import pickle
import re
import shutil
import stat
import warnings
from pathlib import Path

import pytest
from click.testing import CliRunner

from elastokin.cli import main
from elastokin.studies import cache as cache_module
from elastokin.studies.cache import (
    CACHE_FORMAT,
    MAGIC,
    CacheWarning,
    ResultCache,
    content_key,
    key_file,
)

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"
TRAVEL = ROOT / "configs" / "rigs" / "travel_only.yaml"
#: every result the K&C job caches (checked against the source below)
KINDS = ["geometry", "models", "motion_geometry", "stiffness_fit"]
#: what `elastokin kc` caches on the case study (no motion plan: no motion_geometry entry;
#: that one is read by the same ResultCache.get, test_a_planted_entry_never_runs)
KC_KINDS = [k for k in KINDS if k != "motion_geometry"]


class Plant:
    """Unpickling this creates ``marker``: code run from the entry."""

    def __init__(self, marker: Path):
        self.marker = str(marker)

    def __reduce__(self):
        return (open, (self.marker, "w"))


def planted_pickle(marker: Path) -> bytes:
    return pickle.dumps(Plant(marker))


def split(entry: bytes) -> tuple[list[bytes], bytes]:
    end = entry.index(b"\n")
    return entry[:end].split(b" "), entry[end + 1:]


def forged(genuine: bytes, payload: bytes, mac: bytes | None = None) -> bytes:
    """``genuine``'s first line (its name and content key) over another payload (its size
    fixed), with its own signature or ``mac``."""
    fields, _ = split(genuine)
    fields[4] = str(len(payload)).encode()
    if mac is not None:
        fields[5] = mac
    return b" ".join(fields) + b"\n" + payload


ATTACKS = {
    # the case: a plain pickle where an entry belongs
    "plain pickle": lambda genuine, marker: planted_pickle(marker),
    # a genuine first line over a planted payload
    "payload swapped": lambda genuine, marker: forged(genuine, planted_pickle(marker)),
    # signed, but with a key the attacker made (as if another user's elastokin wrote it)
    "attacker's key": lambda genuine, marker: forged(
        genuine, planted_pickle(marker),
        cache_module._signature(b"k" * 32, split(genuine)[0][2].decode(),
                                split(genuine)[0][3].decode(),
                                planted_pickle(marker)).encode()),
}


def test_every_cached_result_kind_is_covered():
    """The names the K&C job caches are the ones these tests plant entries for."""
    source = "".join((ROOT / "elastokin" / "studies" / name).read_text()
                     for name in ("kc_job.py", "identification.py"))
    found = re.findall(r'cache\.(?:get|put)\("(\w+)"|cached_step\(cache, "(\w+)"', source)
    assert sorted({a or b for a, b in found}) == KINDS


def _genuine(tmp_path: Path, name: str, key: str, value=None) -> bytes:
    ResultCache(None, tmp_path / "made").put(name, key, value or {"J1": 1.35})
    return (tmp_path / "made" / f"{name}.pkl").read_bytes()


@pytest.mark.parametrize("attack", sorted(ATTACKS))
@pytest.mark.parametrize("name", KINDS)
def test_a_planted_entry_never_runs(tmp_path, name, attack):
    key = content_key(name, "inputs")
    marker = tmp_path / "marker"
    folder = tmp_path / ".cache"
    folder.mkdir()
    (folder / f"{name}.pkl").write_bytes(ATTACKS[attack](_genuine(tmp_path, name, key),
                                                         marker))
    cache = ResultCache(folder, None)
    with pytest.warns(CacheWarning) as caught:
        assert cache.get(name, key) is None
    assert not marker.exists()
    assert len(caught) == 1 and str(folder / f"{name}.pkl") in str(caught[0].message)
    assert cache.reused == []


def test_a_genuine_entry_round_trips_and_another_inputs_entry_is_silently_stale(tmp_path):
    genuine = _genuine(tmp_path, "models", "k1", {"toe": [0.1, 0.2]})
    (tmp_path / ".cache").mkdir()
    (tmp_path / ".cache" / "models.pkl").write_bytes(genuine)
    assert genuine.startswith(MAGIC + f" {CACHE_FORMAT} models k1 ".encode())
    cache = ResultCache(tmp_path / ".cache", None)
    with _no_warning():
        assert cache.get("models", "k2") is None  # inputs changed: no warning
    assert cache.get("models", "k1") == {"toe": [0.1, 0.2]} and cache.reused == ["models"]


@contextlib.contextmanager
def _no_warning():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield
    assert [str(w.message) for w in caught] == []


def test_another_users_entry_is_foreign(tmp_path, monkeypatch):
    """An entry signed by another user (another XDG_CACHE_HOME: another secret key) is not
    read, with one warning saying who may have written it."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "colleague"))
    genuine = _genuine(tmp_path, "geometry", "k")
    monkeypatch.undo()
    (tmp_path / ".cache").mkdir()
    (tmp_path / ".cache" / "geometry.pkl").write_bytes(genuine)
    with pytest.warns(CacheWarning, match="another user or on another machine"):
        assert ResultCache(tmp_path / ".cache", None).get("geometry", "k") is None


def test_the_key_file_is_the_users_alone(tmp_path, monkeypatch):
    """Made on first use with mode 0600 in $XDG_CACHE_HOME/elastokin, 64 hex digits."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    _genuine(tmp_path, "geometry", "k")
    path = key_file()
    assert path == tmp_path / "xdg" / "elastokin" / "cache-key"
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    assert re.fullmatch(r"[0-9a-f]{64}\n", path.read_text())


# ------------------------------------------------------------------- bad inputs: the entries
def _entry_case(tmp_path, make) -> tuple[ResultCache, Path, list[str]]:
    """An entry made by ``make(path, genuine)``; returns the warnings of reading it."""
    genuine = _genuine(tmp_path, "models", "k")
    folder = tmp_path / "res" / ".cache"
    folder.mkdir(parents=True)
    path = folder / "models.pkl"
    make(path, genuine)
    cache = ResultCache(folder, None)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert cache.get("models", "k") is None
    return cache, path, [str(w.message) for w in caught]


def _outside(tmp_path: Path, genuine: bytes) -> Path:
    """A genuine entry outside the results folder: following a link to it would reuse it."""
    (tmp_path / "elsewhere").mkdir(exist_ok=True)
    (tmp_path / "elsewhere" / "models.pkl").write_bytes(genuine)
    return tmp_path / "elsewhere" / "models.pkl"


def _fifo(path, genuine):
    os.mkfifo(path)  # reading it would block: never opened for a blocking read


BROKEN_ENTRIES = {
    "a folder": (lambda p, g: p.mkdir(), "a folder, not a file"),
    "empty": (lambda p, g: p.write_bytes(b""), "empty"),
    "truncated": (lambda p, g: p.write_bytes(g[:-10]), "truncated or extended"),
    "bytes appended": (lambda p, g: p.write_bytes(g + b"\0"), "truncated or extended"),
    "first line cut": (lambda p, g: p.write_bytes(g[:40]), "not an elastokin cache entry"),
    "an older format": (lambda p, g: p.write_bytes(g.replace(
        f" {CACHE_FORMAT} ".encode(), f" {CACHE_FORMAT - 1} ".encode(), 1)),
        f"cache format '{CACHE_FORMAT - 1}' (this elastokin reads {CACHE_FORMAT})"),
    "another entry's file": (lambda p, g: p.write_bytes(g.replace(b" models ", b" geometry ",
                                                                  1)),
                             "an entry for 'geometry', not 'models'"),
    "a text file": (lambda p, g: p.write_text("results of mine\n"),
                    "not an elastokin cache entry"),
    "binary garbage": (lambda p, g: p.write_bytes(bytes(range(256)) * 4),
                       "not an elastokin cache entry"),
    "a FIFO": (_fifo, "not a file"),
}


@pytest.mark.parametrize("case", sorted(BROKEN_ENTRIES))
def test_a_broken_entry_is_one_warning_naming_it(tmp_path, case):
    make, expected = BROKEN_ENTRIES[case]
    cache, path, messages = _entry_case(tmp_path, make)
    assert messages == [f"{path}: cache entry ignored ({messages[0].split('(', 1)[1]}"]
    assert expected in messages[0] and messages[0].endswith("; recomputing")
    assert cache.reused == []


def test_an_entry_linking_outside_is_not_followed(tmp_path):
    """A symbolic link to a (genuine) entry outside the results folder: not followed."""
    cache, path, messages = _entry_case(
        tmp_path, lambda p, g: p.symlink_to(_outside(tmp_path, g)))
    assert len(messages) == 1 and "a symbolic link" in messages[0]
    assert str(path) in messages[0]


def test_a_cache_folder_linking_outside_is_not_followed(tmp_path):
    """The .cache folder itself a link to a folder of genuine entries elsewhere: not
    followed, one warning for the folder (not one per entry)."""
    outside = _outside(tmp_path, _genuine(tmp_path, "models", "k")).parent
    (tmp_path / "res").mkdir()
    (tmp_path / "res" / ".cache").symlink_to(outside)
    cache = ResultCache(tmp_path / "res" / ".cache", None)
    with pytest.warns(CacheWarning, match="symbolic link") as caught:
        assert cache.get("models", "k") is None and cache.get("geometry", "k") is None
    assert len(caught) == 1


def test_a_huge_entry_is_refused_unread(tmp_path):
    """Larger than any entry elastokin writes (a sparse file: nothing is read)."""
    def huge(path, genuine):
        with open(path, "wb") as fh:
            fh.truncate(cache_module.MAX_ENTRY_BYTES + 1)
    cache, path, messages = _entry_case(tmp_path, huge)
    assert len(messages) == 1 and "more than any entry elastokin writes" in messages[0]


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0,
                    reason="root reads files whatever their mode")
def test_an_unreadable_entry_is_one_warning(tmp_path):
    cache, path, messages = _entry_case(
        tmp_path, lambda p, g: (p.write_bytes(g), p.chmod(0)))
    assert len(messages) == 1 and "cannot be read (Permission denied)" in messages[0]


# ------------------------------------------------------------------ bad inputs: the key file
def _with_key(tmp_path, monkeypatch, make) -> list[str]:
    """The warnings of a cache that reads and writes with the key file ``make`` leaves."""
    genuine = _genuine(tmp_path, "models", "k")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    key = tmp_path / "xdg" / "elastokin" / "cache-key"
    key.parent.mkdir(parents=True)
    make(key)
    (tmp_path / ".cache").mkdir()
    (tmp_path / ".cache" / "models.pkl").write_bytes(genuine)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        cache = ResultCache(tmp_path / ".cache", tmp_path / "new")
        assert cache.get("models", "k") is None
        cache.put("models", "k", {"J1": 1.0})
        assert cache.get("geometry", "k") is None
    assert not (tmp_path / "new").exists()  # nothing signed with an unusable key
    return [str(w.message) for w in caught]


KEY_FILES = {
    "corrupt": (lambda k: (k.write_text("not a key\n"), k.chmod(0o600)), "not a key"),
    "empty": (lambda k: (k.write_bytes(b""), k.chmod(0o600)), "not a key"),
    "readable by others": (lambda k: (k.write_text("ab" * 32), k.chmod(0o644)), "mode 0644"),
    "a folder": (lambda k: k.mkdir(), "not a file"),
    "a symbolic link": (lambda k: k.symlink_to(k.parent / "elsewhere"), "symbolic link"),
}


@pytest.mark.parametrize("case", sorted(KEY_FILES))
def test_an_unusable_key_file_is_one_warning_and_no_cache(tmp_path, monkeypatch, case):
    make, expected = KEY_FILES[case]
    messages = _with_key(tmp_path, monkeypatch, make)
    assert len(messages) == 1, messages
    assert messages[0].startswith(f"{tmp_path / 'xdg' / 'elastokin' / 'cache-key'}: cache key "
                                  "unusable (")
    assert expected in messages[0] and "the cache is not used" in messages[0]


def test_a_missing_key_file_is_made_and_old_entries_are_foreign(tmp_path, monkeypatch):
    """The key deleted (or a new machine): a new key; entries of the old one are foreign
    (one warning) and recomputed."""
    genuine = _genuine(tmp_path, "models", "k")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "fresh"))
    (tmp_path / ".cache").mkdir()
    (tmp_path / ".cache" / "models.pkl").write_bytes(genuine)
    with pytest.warns(CacheWarning, match="signature") as caught:
        assert ResultCache(tmp_path / ".cache", None).get("models", "k") is None
    assert len(caught) == 1 and key_file().is_file()


# ------------------------------------------------------- the command, on every cached result
@pytest.fixture(scope="module")
def clean_run(tmp_path_factory, coarse_travel) -> Path:
    """`elastokin kc` on the case study with parallel travel only (identification, four
    models, the stiffness fit): about 3 s."""
    out = tmp_path_factory.mktemp("clean") / "res"
    result = CliRunner().invoke(main, ["kc", "--config", str(CASE), "--rig", str(coarse_travel),
                                       "--out", str(out), "--quiet"])
    assert result.exit_code == 0, result.output
    return out


def comparable(out: Path) -> dict:
    summary = json.loads((out / "summary.json").read_text())
    for volatile in ("warnings", "reused_from_cache"):
        summary.pop(volatile)
    return summary


@pytest.mark.slow
@pytest.mark.parametrize("name,attack", zip(KC_KINDS, sorted(ATTACKS)))
def test_kc_into_a_folder_with_a_planted_entry_never_runs_it(clean_run, coarse_travel,
                                                             tmp_path, name, attack):
    """For every cached result (each with another attack): `elastokin kc` without --refit
    into a results folder holding an entry crafted to run code prints one warning naming
    it, recomputes that result and gives the clean run's results; the code never runs."""
    out = tmp_path / "res"
    shutil.copytree(clean_run, out)
    marker = tmp_path / "marker"
    entry = out / ".cache" / f"{name}.pkl"
    entry.write_bytes(ATTACKS[attack](entry.read_bytes(), marker))
    result = CliRunner().invoke(main, ["kc", "--config", str(CASE), "--rig", str(coarse_travel),
                                       "--out", str(out), "--quiet"])
    assert result.exit_code == 0, result.output
    assert not marker.exists()
    ignored = [line for line in result.output.splitlines() if "cache entry ignored" in line]
    assert ignored == [line for line in ignored if line.startswith(
        f"elastokin: warning: {entry}: cache entry ignored (")] and len(ignored) == 1
    assert (out / "kc.csv").read_bytes() == (clean_run / "kc.csv").read_bytes()
    assert comparable(out) == comparable(clean_run)
    reused = json.loads((out / "summary.json").read_text())["reused_from_cache"]
    assert name not in reused and reused  # the others were reused
    assert split((out / ".cache" / f"{name}.pkl").read_bytes())[0][0] == MAGIC  # rewritten


def test_a_cache_that_is_a_file_is_one_warning(tmp_path):
    (tmp_path / ".cache").write_text("not a folder\n")
    cache = ResultCache(tmp_path / ".cache", None)
    with pytest.warns(CacheWarning, match="not a folder") as caught:
        assert cache.get("models", "k") is None and cache.get("geometry", "k") is None
    assert len(caught) == 1 and str(tmp_path / ".cache") in str(caught[0].message)
