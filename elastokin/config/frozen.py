"""Read-only containers of the resolved :class:`~elastokin.config.suspension.Suspension` and
plain data for configs given as Python objects.

A resolved suspension never changes: its mappings are :class:`FrozenMapping` (assignment
raises a :class:`TypeError` naming the function that makes a changed copy) and its arrays are
read-only numpy arrays. A deep copy of a frozen mapping is a plain, editable ``dict``
(``copy.deepcopy(suspension.raw)`` is the config mapping to edit), and pickling keeps it
frozen. :func:`plain_data` turns numpy scalars and arrays, tuples and mappings into the YAML
types a config is made of.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping

import numpy as np


class FrozenMapping(Mapping):
    """A read-only mapping; ``hint`` ends the message of a refused assignment (which
    function makes a changed copy)."""

    __slots__ = ("_data", "_hint")

    def __init__(self, data: Mapping | None = None, hint: str = ""):
        self._data = dict(data or {})
        self._hint = hint

    def __getitem__(self, key):
        return self._data[key]

    def __iter__(self) -> Iterator:
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def __repr__(self) -> str:
        return f"FrozenMapping({self._data!r})"

    def _refuse(self, *args, **kwargs):
        raise TypeError("a resolved Suspension is read-only" + (f": {self._hint}"
                                                                 if self._hint else ""))

    __setitem__ = __delitem__ = _refuse
    pop = popitem = clear = update = setdefault = _refuse

    def __or__(self, other: Mapping) -> dict:
        return {**self._data, **other}

    def __reduce__(self):
        return (FrozenMapping, (self._data, self._hint))

    def __copy__(self) -> dict:
        return dict(self._data)

    def __deepcopy__(self, memo: dict) -> dict:
        return plain_data(self)


def readonly(a, dtype=float) -> np.ndarray:
    """``a`` as a read-only array: the array itself when it already is one, else a read-only
    copy (the caller's array is never frozen)."""
    if isinstance(a, np.ndarray) and not a.flags.writeable:
        return a
    out = np.array(a, dtype=dtype)
    out.setflags(write=False)
    return out


def freeze(data, hint: str = ""):
    """A deeply read-only copy of config data: mappings as :class:`FrozenMapping`, lists as
    tuples (numbers and strings as they are)."""
    if isinstance(data, Mapping):
        return FrozenMapping({k: freeze(v, hint) for k, v in data.items()}, hint)
    if isinstance(data, list | tuple):
        return tuple(freeze(v, hint) for v in data)
    return data


def plain_data(data):
    """Config data made of the types a YAML file gives (dict, list, str, int, float, bool,
    None): numpy scalars as Python numbers, numpy arrays and tuples as lists, any mapping as a
    dict. Config mappings built in Python (``{"hardpoints": {"J3": np.array(...)}}``) are
    validated, hashed and written like a file's."""
    if isinstance(data, Mapping):
        return {k: plain_data(v) for k, v in data.items()}
    if isinstance(data, np.ndarray):
        return plain_data(data.tolist())
    if isinstance(data, list | tuple):
        return [plain_data(v) for v in data]
    if isinstance(data, np.str_):
        return str(data)
    if isinstance(data, np.bool_):
        return bool(data)
    if isinstance(data, np.integer):
        return int(data)
    if isinstance(data, np.floating):
        return float(data)
    return data
