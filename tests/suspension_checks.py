"""Checks of a resolved Suspension read back from a file, shared by the ADAMS/Car tests."""

from __future__ import annotations

import copy

import numpy as np


def assert_same_bushings(expected, actual, deflections: np.ndarray) -> None:
    """Every bushing of ``actual`` has the name and, at ``deflections`` (mm or deg), the
    force/torque of each direction's law of ``expected``'s (to 1e-12 relative, 1e-9 N)."""
    assert [b.name for b in actual.bushings] == [b.name for b in expected.bushings]
    for b0, b1 in zip(expected.bushings, actual.bushings):
        for law0, law1 in zip(b0.laws, b1.laws):
            np.testing.assert_allclose(law1(deflections), law0(deflections), rtol=1e-12,
                                       atol=1e-9)


def scrambled(data: dict) -> dict:
    """The config with every hardpoint moved by 5 mm (a point on the centre plane, y = 0, kept
    on it) and every bushing 3x stiffer: a template whose geometry and bushings must all come
    back from the ADAMS files."""
    t = copy.deepcopy(data)
    t["hardpoints"] = {k: [v[0] + 5.0, v[1] if v[1] == 0.0 else v[1] - 5.0, v[2] + 5.0]
                       for k, v in t["hardpoints"].items()}
    for c in t["connections"].values():
        if c["type"] == "bushing":
            c["stiffness"] = {d: 3.0 * v if isinstance(v, (int, float)) else
                              {"deflection": v["deflection"], "load": [3 * x for x in v["load"]]}
                              for d, v in c["stiffness"].items()}
    return t
