"""Bump steer against the height of the tie rod's inner ball joint: a notebook-style example
of elastokin's Python API (cells marked ``# %%`` run one by one in Jupyter or VS Code, or the
whole file as a script: ``python examples/tie_rod_height.py [chart.png]``).

Load the case study, take its nominal geometry, move a hardpoint through the API (a resolved
suspension is read-only), run parallel wheel travel on both and plot toe against travel.
Units mm, N, deg; config frame.
"""

# %% Load the pseudo-McPherson and take its nominal geometry (no CMM data, no test data)
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no screen needed; drop this line in a notebook
import matplotlib.pyplot as plt  # noqa: E402

import elastokin as ek  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
case = ek.load_suspension(ROOT / "configs" / "pseudo_mcpherson.yaml")
nominal = ek.suspension_from_dict({**case.raw, "measurements": None, "kc_test": None},
                                  "nominal pseudo-McPherson")
print("tie rod inner ball joint J3 [mm]:", nominal.hardpoints["J3"])

# %% Change a hardpoint through the API
# nominal.hardpoints["J3"] = ...  would raise: a resolved suspension never changes;
# with_hardpoints returns a new one, every joint, axis and seat on J3 following
raised = ek.with_hardpoints(nominal, {"J3": nominal.hardpoints["J3"] + [0.0, 0.0, 5.0]})
print("moved J3 [mm]:", raised.hardpoints["J3"])

# %% Parallel wheel travel on both (compliant models; the design preloads are solved so
# that each geometry is the static equilibrium under the design wheel load)
sweeps = {}
for label, suspension in (("nominal", nominal), ("J3 5 mm higher", raised)):
    model = ek.build_model(suspension)
    sweeps[label] = ek.parallel_travel(model, label)  # a Sweep: columns with units in names
    figures = ek.summary_figures([sweeps[label]], False)
    print(f"{label}: steer amplitude {figures['steer_amplitude_deg']:.4f} deg, bump steer "
          f"{figures['bump_steer_deg_per_m']:.3f} deg/m")
# a Sweep's columns are plain arrays: pandas.DataFrame(sweeps["nominal"].columns) is a table

# %% Plot toe against wheel travel over the stroke
fig, ax = plt.subplots(figsize=(7.0, 4.5))
for label, sweep in sweeps.items():
    ax.plot(sweep.stroke("wheel_travel_mm"), sweep.stroke("toe_deg"), label=label)
ax.set_xlabel("wheel travel [mm] (+ bump)")
ax.set_ylabel("toe [deg] (+ toe-in)")
ax.set_title("Bump steer and the tie rod's inner ball joint")
ax.grid(True, alpha=0.3)
ax.legend()
out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("tie_rod_height.png")
fig.savefig(out, dpi=120)
print(f"chart: {out}")
