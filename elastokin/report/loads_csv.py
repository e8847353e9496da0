"""``loads.csv``: the loads of every element of every model at every step of every load case
(:mod:`elastokin.rig.loads`), one row per model, load case and step. Units in the column
names (N, N*mm); provenance and conventions in ``#`` header lines (read with
``pandas.read_csv(path, comment="#")``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from elastokin.rig.channels import LOAD_CASES
from elastokin.rig.loads import load_columns


def write_loads_csv(path: Path, models: dict, header: dict) -> bool:
    """``loads.csv``: one row per model, load case and step (numbered as in kc.csv), the load
    case's input, then every element's load (:func:`elastokin.rig.loads.load_columns`: force
    and moment on its first part in the body frame and its own, N and N*mm); a ``#`` header
    with provenance and conventions. ``models``: label -> ModelResult. False (nothing written)
    when no model recorded loads."""
    blocks = [(label, sw) for label, m in models.items() for sw in m.sweeps
              if sw.loads is not None]
    if not blocks:
        return False
    inputs = list(dict.fromkeys(_input(sw.load_case) for _, sw in blocks))
    columns = [load_columns(sw.loads) for _, sw in blocks]
    names = list(dict.fromkeys(c for cols in columns for c in cols))
    where = {c: i for i, c in enumerate([*inputs, *names])}
    with open(path, "w", newline="") as fh:
        for key in ("elastokin_version", "exudyn_version", "config_file", "config_sha256"):
            fh.write(f"# {key}: {header[key]}\n")
        if header.get("rig_file"):
            fh.write(f"# rig_file: {header['rig_file']}\n# rig_sha256: {header['rig_sha256']}\n")
        fh.write("# loads of every element: <element>_<component>_<frame>_<unit>, the force "
                 "(N) and moment (N*mm) it applies to its first part (a connection's parts[0]),"
                 " the moment about its point; frame body: the ground part's (config frame), "
                 "local: the element's own (docs/characteristics.md, Loads); empty = not "
                 "applicable\n")
        fh.write(",".join(["model", "load_case", "step", "branch", *where]) + "\n")
        for (label, sw), cols in zip(blocks, columns):
            values = np.full((sw.steps, len(where)), np.nan)
            name = _input(sw.load_case)
            if name in sw.columns:
                values[:, where[name]] = sw.columns[name]
            for c, v in cols.items():
                values[:, where[c]] = v
            row = ",".join(["%.10g"] * len(where))
            for k, (branch, line) in enumerate(zip(sw.columns["branch"], values)):
                text = (row % tuple(line)).replace("nan", "")
                fh.write(f"{label},{sw.load_case},{k + 1},{branch},{text}\n")
    return True


def _input(load_case: str) -> str:
    """The input channel of a load case (``vehicle_loads:<case>``: ``vehicle_loads``'s)."""
    return LOAD_CASES[load_case.partition(":")[0]].input
