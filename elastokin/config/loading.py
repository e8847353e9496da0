"""Loading configs and rig files: YAML -> validated, resolved
:class:`~elastokin.config.suspension.Suspension`. Errors name the file, the line or the key.

Every YAML file elastokin reads goes through :class:`StrictLoader` (:func:`parse_yaml`,
:func:`read_yaml`): a safe loader that refuses a key appearing twice in one mapping. Schema
errors are reported in the config's own key paths (:func:`format_validation_error`).
"""

from __future__ import annotations

import difflib
import hashlib
import math
import os
import re
import types
import typing
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path

import yaml
from pydantic import BaseModel, ValidationError

from elastokin.config.axle_resolver import resolve_suspension
from elastokin.config.bounds import TOO_MANY_STEPS
from elastokin.config.frozen import plain_data
from elastokin.config.resolver import Resolver
from elastokin.config.schema.rig import RigSpec
from elastokin.config.schema.suspension import SuspensionFile
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError

# ----------------------------------------------------------------------------------------------
# Strict YAML

_MERGE_TAG = "tag:yaml.org,2002:merge"


class DuplicateKeyError(yaml.MarkedYAMLError):
    """A key that appears twice in one YAML mapping (``problem_mark``: its second place)."""


def yaml_key_path(path: tuple) -> str:
    """``hardpoints.J4``, ``a.b[2]``: a key path as the messages write it."""
    out = ""
    for seg in path:
        out += f"[{seg}]" if isinstance(seg, int) and not isinstance(seg, bool) else f".{seg}"
    return out.lstrip(".")


class NumberOverflowError(yaml.MarkedYAMLError):
    """A number in a YAML file too large for a float (``problem_mark``: its place)."""


#: YAML tags of numbers
_INT_TAG, _FLOAT_TAG = "tag:yaml.org,2002:int", "tag:yaml.org,2002:float"


class StrictLoader(yaml.SafeLoader):
    """The YAML loader of every file elastokin reads: :class:`yaml.SafeLoader` refusing a key
    that appears twice in one mapping at any nesting level (:class:`DuplicateKeyError`, naming
    the key, the mapping's key path and both lines). Merge keys (``<<``) may be overridden."""

    def get_single_data(self):
        node = self.get_single_node()
        if node is None:
            return None
        self.check_unique_keys(node, (), set())
        return self.construct_document(node)

    def check_unique_keys(self, node: yaml.Node, path: tuple, visited: set) -> None:
        if id(node) in visited:  # an alias: checked where it is anchored
            return
        visited.add(id(node))
        if isinstance(node, yaml.SequenceNode):
            for i, item in enumerate(node.value):
                self.check_unique_keys(item, (*path, i), visited)
            return
        if isinstance(node, yaml.ScalarNode) and node.tag in (_INT_TAG, _FLOAT_TAG):
            self.check_number(node, path)
            return
        if not isinstance(node, yaml.MappingNode):
            return
        first: dict = {}
        for key_node, value_node in node.value:
            if key_node.tag == _MERGE_TAG:
                self.check_unique_keys(value_node, path, visited)
                continue
            key = self.scalar_key(key_node)
            if key is not None and key in first:
                where = f"in '{yaml_key_path(path)}'" if path else "at the top level"
                raise DuplicateKeyError(
                    problem=f"key '{key}' appears twice {where} (first at line {first[key]})",
                    problem_mark=key_node.start_mark)
            if key is not None:
                first[key] = key_node.start_mark.line + 1
            self.check_unique_keys(value_node, (*path, key_node.value if key is None else key),
                                   visited)

    def check_number(self, node: yaml.ScalarNode, path: tuple) -> None:
        """A number too large for a float (``1.0e+400``, an integer of 400 digits; ``.inf``
        is left to the schema) raises :class:`NumberOverflowError` naming its key path."""
        try:
            value = float(self.construct_object(node, deep=True))
            big = math.isinf(value) and not node.value.lstrip("+-").lower().startswith(".inf")
        except (ValueError, OverflowError):  # an integer beyond Python's digit limit or a float's
            big = True
        if big:
            text = node.value if len(node.value) <= 24 else f"{node.value[:12]}... " \
                f"({len(node.value)} characters)"
            where = f"key '{yaml_key_path(path)}'" if path else "the document"
            raise NumberOverflowError(
                problem=f"{where}: the number {text} is too large (a float holds at most "
                        "about 1.8e308; lengths are in mm, forces in N)",
                problem_mark=node.start_mark)

    def scalar_key(self, key_node: yaml.Node) -> typing.Hashable | None:
        """The constructed key of a scalar key node; None for other (complex) keys."""
        if not isinstance(key_node, yaml.ScalarNode):
            return None
        key = self.construct_object(key_node, deep=True)
        try:
            hash(key)
        except TypeError:
            return None
        return key


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _yaml_problem(exc: yaml.YAMLError, text: bytes | str) -> tuple[str, str]:
    """Where (`` line L, column C``) and what of a YAML error; a line number always when the
    error has a mark or a position."""
    mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
    where = f" line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
    position = getattr(exc, "position", None)  # a ReaderError: characters from the start
    if mark is None and position is not None:
        decoded = text.decode("utf-8", "replace") if isinstance(text, bytes) else text
        where = f" line {decoded[:position].count(chr(10)) + 1}"
    problem = getattr(exc, "problem", None)
    context = getattr(exc, "context", None)
    start = getattr(exc, "context_mark", None)
    if problem and context:
        began = ""
        if start is not None and mark is not None and start.line != mark.line:
            began = f" (from line {start.line + 1})"
        problem = f"{context}{began}: {problem}"
    return where, _one_line(problem or (str(exc).splitlines() or [type(exc).__name__])[0])


def parse_yaml(text: bytes | str, source: str) -> object:
    """Parse YAML text with :class:`StrictLoader`; errors are a one-line
    :class:`~elastokin.errors.ConfigError` naming ``source`` and the line."""
    try:
        return yaml.load(text, Loader=StrictLoader)
    except (DuplicateKeyError, NumberOverflowError) as exc:
        raise ConfigError(f"{source}: line {exc.problem_mark.line + 1}: {exc.problem}") from None
    except yaml.YAMLError as exc:
        where, problem = _yaml_problem(exc, text)
        raise ConfigError(f"{source}:{where}: malformed YAML: {problem}") from None


def read_yaml(path: str | Path, what: str = "config file") -> tuple[dict, bytes]:
    """Read a YAML mapping (:func:`parse_yaml`); errors name the file (``what`` it is) and
    line."""
    p = Path(path)
    try:
        text = p.read_bytes()
    except OSError as exc:
        raise ConfigError(f"{p}: cannot read {what} ({exc.strerror})") from None
    data = parse_yaml(text, str(p))
    if not isinstance(data, dict):
        raise ConfigError(f"{p}: expected a YAML mapping of keys at the top level of the {what}")
    return data, text


# ----------------------------------------------------------------------------------------------
# Schema errors in the config's own key paths

#: pydantic error types saying the value is not of one member's type: of a union, all but one
#: of these are beside the point
_TYPE_MISMATCH = re.compile(r".*_(type|parsing)$|union_tag_not_found$|model_attributes_type$")


def _unwrap(t):
    """A type without ``Annotated`` and without ``| None``."""
    while True:
        origin = typing.get_origin(t)
        if origin is typing.Annotated:
            t = typing.get_args(t)[0]
        elif origin in (typing.Union, types.UnionType):
            members = [m for m in typing.get_args(t) if m is not type(None)]
            if len(members) != 1:
                return t
            t = members[0]
        else:
            return t


def _is_model(t) -> bool:
    return isinstance(t, type) and issubclass(t, BaseModel)


def _union_member(t, seg):
    """The member of union ``t`` that pydantic names ``seg`` in a location: its tag (the
    ``type`` literal) or its class name; None when none is."""
    for m in map(_unwrap, typing.get_args(t)):
        if not _is_model(m):
            continue
        tag = m.model_fields.get("type")
        if m.__name__ == seg or (tag is not None and seg in typing.get_args(tag.annotation)):
            return m
    return None


def _model_at(root: type[BaseModel], loc: tuple) -> type[BaseModel] | None:
    """The schema model that pydantic location ``loc`` (its own segments) leads to."""
    t = root
    for seg in loc:
        t = _unwrap(t)
        origin, args = typing.get_origin(t), typing.get_args(t)
        if _is_model(t):
            field = next((f for n, f in t.model_fields.items() if seg in (n, f.alias)), None)
            if field is None:
                return None
            t = field.annotation
        elif origin is dict:
            t = args[1]
        elif origin in (list, tuple) and isinstance(seg, int):
            t = args[0] if origin is list or args[-1] is Ellipsis else args[min(seg, len(args) - 1)]
        elif origin in (typing.Union, types.UnionType):
            t = _union_member(t, seg)
        else:
            return None
    t = _unwrap(t)
    return t if _is_model(t) else None


def _config_loc(loc: tuple, data: object, keep_last: bool) -> tuple:
    """``loc`` without pydantic's own segments (union tags, type names, validators): only the
    keys and indices found in the input ``data``; with ``keep_last`` the last segment stays
    (a missing key)."""
    out, here = [], data
    for i, seg in enumerate(loc):
        if isinstance(here, dict) and seg in here:
            here = here[seg]
        elif (isinstance(here, list | tuple) and isinstance(seg, int)
              and 0 <= seg < len(here)):
            here = here[seg]
        elif not (keep_last and i == len(loc) - 1):
            continue
        out.append(seg)
    return tuple(out)


def _suggestion(key: object, known: list[str]) -> str:
    close = difflib.get_close_matches(str(key), known, n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


def _problem(e: dict, data: object, root: type[BaseModel] | None,
             prefix: tuple) -> tuple[tuple, str]:
    """One pydantic error as (key path in the config's terms, message)."""
    kind, loc = e["type"], tuple(e["loc"])
    path = (*prefix, *_config_loc(loc, data, keep_last=kind in ("missing", TOO_MANY_STEPS)))
    ctx = e.get("ctx") or {}
    if kind == TOO_MANY_STEPS and ctx.get("key"):
        path = (*path, *str(ctx["key"]).split("."))
    if kind == "extra_forbidden" and loc:
        model = _model_at(root, loc[:-1]) if root is not None else None
        known = [f.alias or n for n, f in model.model_fields.items()] if model else []
        parent = path[:-1]
        where = f"key '{yaml_key_path(parent)}': unknown" if parent else "unknown top-level"
        return parent, f"{where} key '{loc[-1]}'{_suggestion(loc[-1], known)}"
    msg = re.sub(r"^(Value error|Assertion failed), ", "", e["msg"])
    msg = re.sub(r" or instance of \w+", "", msg)
    if kind == "missing":
        msg = "required key is missing"
        if loc and isinstance(loc[-1], int):  # a tuple too short: [x, y] for a point
            msg = f"item [{loc[-1]}] is missing: the list has too few items"
    if kind == "tuple_type":
        msg = "expected a list (YAML [a, b, ...]; a point is [x, y, z] in mm)"
    return path, msg


def format_validation_error(path: str, err: ValidationError, data: object = None,
                            root: type[BaseModel] | None = None, prefix: tuple = ()) -> str:
    """A pydantic error as one line: ``FILE: key 'KEY.PATH': what is wrong (N more
    problems)``, the key path in the config's own terms (given the validated ``data``; the
    ``root`` model lets an unknown key suggest the closest known one). Unknown keys come
    first (a missing key they cause is one of the more problems); of a union, the member
    whose error goes deepest speaks."""
    errors = err.errors()
    found = [(e, *_problem(e, data, root, prefix)) for e in errors]
    unknown = [f"{path}: {msg}" for e, _, msg in found if e["type"] == "extra_forbidden"]
    groups: dict[tuple, list] = {}
    for e, loc, msg in found:
        if e["type"] != "extra_forbidden":
            groups.setdefault(loc, []).append((e, msg))
    deeper = {loc[:i] for loc in groups for i in range(len(loc))}
    lines = list(dict.fromkeys(unknown))
    for loc, items in groups.items():
        kept = [(e, m) for e, m in items if not _TYPE_MISMATCH.match(e["type"])]
        if not kept and loc in deeper:
            continue  # another member of the union got further: its error speaks
        text = ("; " if kept else "; or ").join(dict.fromkeys(m for _, m in kept or items))
        key = yaml_key_path(loc)
        lines.append(f"{path}: key '{key}': {text}" if key else f"{path}: {text}")
    if not lines:  # cannot happen; never hide the error
        lines = [f"{path}: {_one_line(str(err))}"]
    n = len(lines) - 1
    more = f" ({n} more problem{'s' if n > 1 else ''})" if n else ""
    return _one_line(lines[0] + more)


# ----------------------------------------------------------------------------------------------
# A config written elsewhere


def relocated_folder(folder: str, config_dir: str | Path, new_dir: str | Path) -> str:
    """A data folder of the config in ``config_dir`` (``measurements.folder``,
    ``kc_test.folder``: relative to the config, or absolute) as a config written into
    ``new_dir`` names it: relative to ``new_dir`` (POSIX separators, links resolved), as a
    config's own paths are; an absolute folder as given; absolute where the two folders share
    nothing but the root."""
    if Path(folder).is_absolute():
        return folder
    here = (Path(config_dir) / folder).resolve()
    there = Path(new_dir).resolve()
    common = Path(os.path.commonpath([here, there]))
    if common == common.parent:  # only the root in common
        return here.as_posix()
    return Path(os.path.relpath(here, there)).as_posix()


# ----------------------------------------------------------------------------------------------
# Loading


def load_suspension(path: str | Path, overrides: dict | None = None) -> Suspension:
    """Load, validate and resolve a suspension config file.

    ``overrides`` (optional) is merged over the top-level keys before validation (e.g.
    ``{"kinematic": True}``); the hashes then identify the file's bytes plus the overrides.
    """
    return _load(path, overrides)


def _digest(text: bytes, overrides: dict | None) -> str:
    """SHA-256 of a file's bytes and of the overrides merged over it (none: of the bytes)."""
    h = hashlib.sha256(text)
    if overrides:
        h.update(yaml.safe_dump(plain_data(overrides), sort_keys=True).encode())
    return h.hexdigest()


def _load(path: str | Path, overrides: dict | None,
          rig_file: tuple[str, dict, bytes] | None = None) -> Suspension:
    """A config file with ``overrides``, and a rig file (path, mapping, bytes) replacing its
    ``rig`` section: ``sha256`` covers all of them, ``config_sha256`` the file and the
    overrides, ``rig_sha256`` the rig file."""
    data, text = read_yaml(path)
    overrides = dict(overrides or {})
    every = {**overrides, "rig": rig_file[1]} if rig_file is not None else overrides
    if every:
        data = {**data, **every}
    s = suspension_from_dict(data, str(path), _digest(text, every),
                             config_sha256=_digest(text, overrides),
                             rig_sha256=None if rig_file is None
                             else hashlib.sha256(rig_file[2]).hexdigest(),
                             rig_source="" if rig_file is None else rig_file[0])
    return s


def read_rig(path: str | Path) -> tuple[dict, bytes]:
    """Read and validate a rig file: the load cases of :class:`RigSpec` as a YAML mapping,
    either at the top level or under one ``rig:`` key; returns the mapping and the file's
    bytes. Errors name the rig file and key."""
    data, text = read_yaml(path, "rig file")
    prefix: tuple = ()
    if set(data) == {"rig"}:
        data, prefix = data["rig"], ("rig",)
        if not isinstance(data, dict):
            raise ConfigError(f"{path}: key 'rig': expected a mapping of load cases")
    try:
        RigSpec.model_validate(data)
    except ValidationError as err:
        raise ConfigError(format_validation_error(f"{path} (rig file)", err, data, RigSpec,
                                                  prefix)) from None
    return data, text


def load_rig(path: str | Path) -> dict:
    """The validated load cases of a rig file (:func:`read_rig`)."""
    return read_rig(path)[0]


def load_suspension_with_rig(config_path: str | Path, rig_path: str | Path | None,
                             overrides: dict | None = None) -> Suspension:
    """:func:`load_suspension` with the config's ``rig`` section replaced by a rig file
    (:func:`read_rig`) when ``rig_path`` is given: ``rig_sha256`` is the rig file's hash,
    ``config_sha256`` still the config's, ``sha256`` covers both."""
    if rig_path is None:
        return load_suspension(config_path, overrides)
    rig, text = read_rig(rig_path)
    return _load(config_path, overrides, (str(rig_path), rig, text))


def suspension_from_dict(data: Mapping, source: str = "<dict>", sha256: str = "", *,
                         config_sha256: str = "", rig_sha256: str | None = None,
                         rig_source: str = "") -> Suspension:
    """Validate a config mapping and resolve names, axes and laws (see module docstring).

    ``data`` may hold numpy scalars and arrays, tuples and read-only mappings (a
    suspension's ``raw``): they are taken as the plain YAML types first. ``sha256``: what
    identifies the inputs (default: the SHA-256 of the mapping as YAML); ``config_sha256``,
    ``rig_sha256`` and ``rig_source`` (a rig file whose load cases are ``data['rig']``: its
    keys' errors name it) as :class:`~elastokin.config.suspension.Suspension` says."""
    data = plain_data(data)
    try:
        spec = SuspensionFile.model_validate(data)
    except ValidationError as err:
        message = format_validation_error(source, err, data, SuspensionFile)
        rig_key = f"{source}: key 'rig."
        if rig_source and message.startswith(rig_key):  # e.g. steps from the design load
            message = f"{rig_source} (rig file): key '{message[len(rig_key):]}"
        raise ConfigError(message) from None
    if not sha256:
        sha256 = hashlib.sha256(yaml.safe_dump(data, sort_keys=True).encode()).hexdigest()
    s = resolve_suspension(Resolver(spec, source), sha256, data, config_sha256, rig_sha256)
    return replace(s, rig_source=rig_source) if rig_source else s


