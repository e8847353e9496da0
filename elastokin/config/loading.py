"""Loading configs and rig files: YAML -> validated, resolved
:class:`~elastokin.config.suspension.Suspension`. Errors name the file, the line or the key.
"""

from __future__ import annotations

import hashlib
from dataclasses import replace
from pathlib import Path

import yaml
from pydantic import ValidationError

from elastokin.config.schema import RigSpec, SuspensionFile
from elastokin.config.suspension import Resolver, Suspension
from elastokin.errors import ConfigError

# ----------------------------------------------------------------------------------------------
# Loading


def format_validation_error(path: str, err: ValidationError) -> str:
    first = err.errors()[0]
    loc = ".".join(str(p) for p in first["loc"] if not str(p).startswith("function-"))
    msg = first["msg"]
    extra = f" ({len(err.errors()) - 1} more problems)" if len(err.errors()) > 1 else ""
    return f"{path}: key '{loc}': {msg}{extra}"


def read_yaml(path: str | Path, what: str = "config file") -> tuple[dict, bytes]:
    """Read a YAML mapping; errors name the file (``what`` it is) and line."""
    p = Path(path)
    try:
        text = p.read_bytes()
    except OSError as exc:
        raise ConfigError(f"{p}: cannot read {what} ({exc.strerror})") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc)
        raise ConfigError(f"{p}:{where}: malformed YAML: {problem}") from None
    if not isinstance(data, dict):
        raise ConfigError(f"{p}: expected a YAML mapping of keys at the top level of the {what}")
    return data, text


def load_suspension(path: str | Path, overrides: dict | None = None) -> Suspension:
    """Load, validate and resolve a suspension config file.

    ``overrides`` (optional) is merged over the top-level keys before validation (e.g.
    ``{"kinematic": True}``); the hash still identifies the file's bytes plus the overrides.
    """
    data, text = read_yaml(path)
    if overrides:
        data = {**data, **overrides}
    digest = hashlib.sha256(text)
    if overrides:
        digest.update(yaml.safe_dump(overrides, sort_keys=True).encode())
    return suspension_from_dict(data, str(path), digest.hexdigest())


def load_rig(path: str | Path) -> dict:
    """Read and validate a rig file: the load cases of :class:`RigSpec` as a YAML mapping,
    either at the top level or under one ``rig:`` key. Errors name the rig file and key."""
    data, _ = read_yaml(path, "rig file")
    if set(data) == {"rig"}:
        data = data["rig"]
        if not isinstance(data, dict):
            raise ConfigError(f"{path}: key 'rig': expected a mapping of load cases")
    try:
        RigSpec.model_validate(data)
    except ValidationError as err:
        raise ConfigError(format_validation_error(f"{path} (rig file)", err)) from None
    return data


def load_suspension_with_rig(config_path: str | Path, rig_path: str | Path | None,
                             overrides: dict | None = None) -> Suspension:
    """:func:`load_suspension` with the config's ``rig`` section replaced by a rig file
    (:func:`load_rig`) when ``rig_path`` is given; the config hash then covers the rig too."""
    if rig_path is None:
        return load_suspension(config_path, overrides)
    rig = load_rig(rig_path)
    s = load_suspension(config_path, {**(overrides or {}), "rig": rig})
    return replace(s, rig_source=str(rig_path))


def suspension_from_dict(data: dict, source: str = "<dict>", sha256: str = "") -> Suspension:
    """Validate a config mapping and resolve names, axes and laws (see module docstring)."""
    try:
        spec = SuspensionFile.model_validate(data)
    except ValidationError as err:
        raise ConfigError(format_validation_error(source, err)) from None
    if not sha256:
        sha256 = hashlib.sha256(yaml.safe_dump(data, sort_keys=True).encode()).hexdigest()
    return Resolver(spec, source).resolve(sha256, data)


