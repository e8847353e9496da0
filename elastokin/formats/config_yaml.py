"""Config files written as YAML: a config dict (elastokin units mm, N, N*mm, deg and the
config's own ``frame``, written as given) with a ``#`` comment header."""

from __future__ import annotations

import yaml

__all__ = ["dump_config"]


def dump_config(config: dict, header: str, flow: bool | None = None) -> str:
    """A config dict as YAML text with a ``#`` comment header (deterministic); ``flow`` as
    PyYAML's ``default_flow_style`` (None: lists of numbers inline)."""
    text = yaml.safe_dump(config, sort_keys=False, default_flow_style=flow, width=100)
    return "".join(f"# {ln}\n".replace("# \n", "#\n") for ln in header.splitlines()) + text
