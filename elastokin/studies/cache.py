"""A cache of a K&C run's expensive results (the geometric identification ``geometry``, the
stiffness fit ``stiffness_fit``, every model's load cases ``models``), keyed by the content of
everything they depend on: the config (and rig) bytes, the CMM or K&C test files' bytes, the
elastokin and Exudyn versions. A result is reused only when every input is the same.

Entries live in the results folder (``results/<name>/.cache/<name>.pkl``): a run reads the
entries of the previous results and writes its own into the new folder, which replaces the old
one as a whole only when the run succeeded, so concurrent runs never see half-written entries.

**A results folder may come from anyone, so nothing in it may run code.** An entry is a pickle
(the run's own Python objects: suspensions, identification, sweeps), and unpickling runs
whatever code the bytes name. So every entry is signed: its first line is
``elastokin-cache FORMAT NAME KEY BYTES HMAC``, where HMAC is an HMAC-SHA256 of the format,
name, content key and pickle bytes under a secret key of this user
(``$XDG_CACHE_HOME/elastokin/cache-key``, default ``~/.cache/elastokin/cache-key``: 32 random
bytes, made on first use, mode 0600, refused when others may read it or it is not the user's).
The secret never lives in a results folder. An entry is unpickled only after its HMAC is
verified with :func:`hmac.compare_digest` on the bytes read, so an entry written by another
user, on another machine, or altered (a crafted pickle included) is never deserialised: it is
ignored with one warning naming it, and the result recomputed. Signing was chosen over a
data-only format (JSON and ``.npy``) because the cached results are rich objects (frozen
suspensions, identification results, sweeps of every model): a second serialisation of each
would have to follow every change to those types, and a slip in it would reuse a silently
different result; the signature keeps one serialisation and makes it trusted only where this
user's elastokin wrote it. The cost: a results folder copied from someone else, or to another
machine, recomputes once (with the warning) and is then cached under this user's key.

Entries are opened without following symbolic links, must be regular files of at most
:data:`MAX_ENTRY_BYTES`, and are read once: the bytes verified are the bytes unpickled.
"""

from __future__ import annotations

import hashlib
import hmac
import os
import pickle
import re
import secrets
import stat
import tempfile
import warnings
from pathlib import Path

from elastokin.version import __version__, code_sha256, exudyn_version

#: bumped when what an entry holds or its layout changes (5: signed entries; 6: every part's
#: pose in each sweep and the model's suspension in each ModelResult, for the 3D view; 7:
#: the beam parts' node poses in each sweep's poses)
CACHE_FORMAT = 7
#: the largest entry read (the case study's are under 4 MB): larger ones are refused unread
MAX_ENTRY_BYTES = 1 << 30
MAGIC = b"elastokin-cache"
_HEADER_MAX = 256  # bytes of the first line
_NAME = re.compile(r"[a-z_]{1,40}")
_HEX64 = re.compile(rb"[0-9a-f]{64}")
_TOKEN = re.compile(r"[0-9A-Za-z_.-]{1,128}")  # a content key (hexadecimal, or a test's)
_KEY_BYTES = 32


class CacheWarning(UserWarning):
    """A cache entry, or the user's cache key, was unusable and was ignored."""


class _Ignored(Exception):
    """Why an entry is not used (the rest of its warning)."""


def content_key(*parts) -> str:
    """SHA-256 of the parts (bytes, strings, files as their bytes), of the versions and of
    elastokin's own code (:func:`~elastokin.version.code_sha256`: a changed line of code is
    a changed input)."""
    h = hashlib.sha256(f"{CACHE_FORMAT} {__version__} {exudyn_version()} "
                       f"{code_sha256()}".encode())
    for part in parts:
        if isinstance(part, Path):
            h.update(str(part.name).encode())
            h.update(part.read_bytes() if part.is_file() else b"<missing>")
        elif isinstance(part, bytes):
            h.update(part)
        else:
            h.update(repr(part).encode())
        h.update(b"\0")
    return h.hexdigest()


# ------------------------------------------------------------------------------ the secret key
def key_file() -> Path:
    """Where this user's secret cache key lives: ``$XDG_CACHE_HOME/elastokin/cache-key``
    (an absolute XDG_CACHE_HOME only, as the XDG spec says), else ``~/.cache/elastokin/``."""
    base = os.environ.get("XDG_CACHE_HOME", "")
    root = Path(base) if os.path.isabs(base) else Path.home() / ".cache"
    return root / "elastokin" / "cache-key"


def _read_key(path: Path) -> bytes:
    """The key in ``path``; OSError or _Ignored (with the reason) when it is not usable."""
    if path.is_symlink():
        raise _Ignored("a symbolic link: not followed")
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0))
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise _Ignored("not a file")
        if hasattr(os, "getuid") and st.st_uid != os.getuid():
            raise _Ignored(f"owned by another user (uid {st.st_uid})")
        if os.name == "posix" and st.st_mode & 0o077:
            raise _Ignored(f"mode {stat.S_IMODE(st.st_mode):04o}: others may read it and sign "
                           "entries with it; it must be 0600")
        text = os.read(fd, 4 * _KEY_BYTES).strip()
    finally:
        os.close(fd)
    if len(text) != 2 * _KEY_BYTES or not _HEX64.fullmatch(text):
        raise _Ignored(f"not a key ({2 * _KEY_BYTES} hexadecimal digits expected)")
    return bytes.fromhex(text.decode())


def _make_key(path: Path) -> None:
    """A new random key in ``path`` (mode 0600); a key another process made first is kept
    (the new one is linked into place only where none exists)."""
    path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    fd, tmp = tempfile.mkstemp(prefix=".cache-key.", dir=path.parent)  # mode 0600
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(secrets.token_hex(_KEY_BYTES) + "\n")
        try:
            os.link(tmp, path)
        except FileExistsError:
            pass
    finally:
        os.unlink(tmp)


def user_key() -> bytes:
    """This user's secret cache key (made on first use). Raises _Ignored or OSError with the
    reason when the key file is not usable."""
    path = key_file()
    try:
        return _read_key(path)
    except FileNotFoundError:
        _make_key(path)
        return _read_key(path)


# ------------------------------------------------------------------------------- the entries
def _signature(secret: bytes, name: str, key: str, payload: bytes) -> str:
    message = b"%d\0%s\0%s\0" % (CACHE_FORMAT, name.encode(), key.encode())
    return hmac.new(secret, message + payload, hashlib.sha256).hexdigest()


def _read_entry(path: Path) -> bytes:
    """The bytes of the entry ``path``, read once, without following a symbolic link and
    without blocking on a FIFO or a device; _Ignored names what is wrong."""
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0) | \
        getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)
    if path.is_symlink():
        raise _Ignored(f"a symbolic link (to {os.readlink(path)}), not followed")
    try:
        fd = os.open(path, flags)
    except OSError as exc:
        raise _Ignored(f"cannot be read ({exc.strerror})") from exc
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise _Ignored("a folder, not a file" if stat.S_ISDIR(st.st_mode) else "not a file")
        if st.st_size > MAX_ENTRY_BYTES:
            raise _Ignored(f"{st.st_size} bytes, more than any entry elastokin writes "
                           f"({MAX_ENTRY_BYTES})")
        with os.fdopen(os.dup(fd), "rb") as fh:
            return fh.read(MAX_ENTRY_BYTES + 1)
    except OSError as exc:
        raise _Ignored(f"cannot be read ({exc.strerror})") from exc
    finally:
        os.close(fd)


def _verified_payload(data: bytes, name: str, secret: bytes) -> tuple[str, bytes]:
    """(content key, pickle bytes) of an entry whose signature is this user's; _Ignored
    otherwise. Nothing is deserialised here: the first line is split into plain fields."""
    if not data:
        raise _Ignored("empty")
    end = data.find(b"\n", 0, _HEADER_MAX)
    fields = data[:end].split(b" ") if end > 0 else []
    if not data.startswith(MAGIC + b" ") or len(fields) != 6:
        what = "a plain pickle, from an elastokin before signed entries or planted" \
            if data[:1] == b"\x80" else "not an elastokin cache entry"
        raise _Ignored(f"{what}: not read")
    _, fmt, entry_name, key, size, mac = fields
    if fmt != str(CACHE_FORMAT).encode():
        raise _Ignored(f"cache format {fmt.decode(errors='replace')!r} (this elastokin "
                       f"reads {CACHE_FORMAT}): not read")
    if entry_name != name.encode():
        raise _Ignored(f"an entry for {entry_name.decode(errors='replace')!r}, not {name!r}")
    payload = data[end + 1:]
    if not size.isdigit() or int(size) != len(payload):
        raise _Ignored(f"truncated or extended: {len(payload)} bytes after the first line, "
                       f"its first line says {size.decode(errors='replace')}")
    if not (_TOKEN.fullmatch(key.decode("ascii", "replace")) and _HEX64.fullmatch(mac)) or \
            not hmac.compare_digest(
            _signature(secret, name, key.decode(), payload).encode(), mac):
        raise _Ignored("its signature is not this user's key's (written by another user or "
                       "on another machine, or altered): not read")
    return key.decode(), payload


class ResultCache:
    """Results read from ``source`` (a previous run's ``.cache`` folder, if any) and written to
    ``target``; ``enabled`` False ignores what is stored (``--refit``) but still writes.
    Every problem is one :class:`CacheWarning` naming the entry (or the folder, or the key
    file), and the result is recomputed."""

    def __init__(self, source: Path | None, target: Path | None, enabled: bool = True):
        self.source, self.target, self.enabled = source, target, enabled
        self.reused: list[str] = []
        self._secret: bytes | None = None
        self._checked: dict[str, bool] = {}  # "key", "source": usable (warned once if not)

    def _key(self) -> bytes | None:
        """The user's secret key (None, with one warning per cache, when it is unusable)."""
        if "key" not in self._checked:
            try:
                self._secret = user_key()
            except _Ignored as exc:
                _warn(key_file(), f"cache key unusable ({exc}; delete it: elastokin makes a "
                      "new one): the cache is not used")
            except (OSError, RuntimeError) as exc:  # RuntimeError: no home folder
                reason = getattr(exc, "strerror", None) or str(exc)
                _warn(getattr(exc, "filename", None) or "cache key",
                      f"cache key unusable ({reason}): the cache is not used")
            self._checked["key"] = self._secret is not None
        return self._secret

    def _source_usable(self) -> bool:
        """A folder (not a symbolic link: a results folder never sends elastokin elsewhere)."""
        if "source" not in self._checked:
            src = self.source
            ok = src is not None and os.path.lexists(src)
            if ok and (src.is_symlink() or not src.is_dir()):
                _warn(src, "cache folder ignored (a symbolic link or not a folder: not "
                      "followed); recomputing")
                ok = False
            self._checked["source"] = ok
        return self._checked["source"]

    def get(self, name: str, key: str):
        """The stored value of ``name`` when its key is ``key``, else None."""
        if not self.enabled or not self._source_usable():
            return None
        path = self.source / f"{name}.pkl"
        if not os.path.lexists(path) or self._key() is None:
            return None
        try:
            stored_key, payload = _verified_payload(_read_entry(path), name, self._secret)
            if stored_key != key:
                return None  # this user's entry for other inputs
            value = pickle.loads(payload)  # signed with this user's key: its own bytes
        except _Ignored as exc:
            _warn(path, f"cache entry ignored ({exc}); recomputing")
            return None
        except Exception as exc:  # noqa: BLE001 - a signed entry that no longer loads
            _warn(path, f"cache entry ignored ({type(exc).__name__}: {str(exc)[:80]}); "
                  "recomputing")
            return None
        self.reused.append(name)
        return value

    def put(self, name: str, key: str, value) -> None:
        """Store ``value`` under ``name`` (into the new results folder), signed."""
        if not (_NAME.fullmatch(name) and _TOKEN.fullmatch(key)):
            raise ValueError(f"cache entry {name!r}, key {key!r}: a name of lower-case letters "
                             "and a key without spaces expected")
        if self.target is None or self._key() is None:
            return
        payload = pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL)
        header = b" ".join([MAGIC, str(CACHE_FORMAT).encode(), name.encode(), key.encode(),
                            str(len(payload)).encode(),
                            _signature(self._secret, name, key, payload).encode()])
        self.target.mkdir(parents=True, exist_ok=True)
        with open(self.target / f"{name}.pkl", "wb") as fh:
            fh.write(header + b"\n" + payload)


def _warn(path, message: str) -> None:
    warnings.warn(CacheWarning(f"{path}: {message}"), stacklevel=4)
