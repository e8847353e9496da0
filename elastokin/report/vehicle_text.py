"""The whole car's table, as ``elastokin kc --vehicle`` prints it and the report shows it:
one row per figure, the front axle's, the rear axle's and the car's side by side (units as
the report shows them: :func:`~elastokin.rig.channels.display_unit`). No heavy import."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from elastokin.rig.channels import display_unit
from elastokin.rig.vehicle_channels import figure

#: where a cell's figure is: (``front``, ``rear`` or ``car``, key in summary.json
#: ``models.<label>.<that>``), None for an empty cell
Cell = tuple[str, str] | None


@dataclass(frozen=True)
class CarRow:
    """A row of the car's table: its label and the figures of its front, rear and car
    cells."""

    label: str
    front: Cell
    rear: Cell
    car: Cell = None

    @property
    def cells(self) -> tuple[Cell, Cell, Cell]:
        return self.front, self.rear, self.car

    @property
    def unit(self) -> str:
        """The unit the row shows its figures in."""
        where, key = next(c for c in self.cells if c is not None)
        return display_unit(figure(key, "car" if where == "car" else "axle").unit)[0]

    def values(self, figures: dict) -> list[float | None]:
        """The row's figures of one car model (summary.json ``models.<label>``), in the
        unit it shows."""
        out = []
        for cell in self.cells:
            v = None if cell is None else figures.get(cell[0], {}).get(cell[1])
            if v is not None:
                scope = "car" if cell[0] == "car" else "axle"
                v = v * display_unit(figure(cell[1], scope).unit)[1]
            out.append(v)
        return out

    def fmt(self) -> str:
        where, key = next(c for c in self.cells if c is not None)
        return figure(key, "car" if where == "car" else "axle").fmt


def _axles(key: str) -> tuple[Cell, Cell]:
    return ("front", key), ("rear", key)


#: the car's table (definitions: summary.json ``sign_conventions``, docs/characteristics.md
#: "Whole car")
CAR_ROWS = (
    CarRow("roll stiffness", *_axles("roll_stiffness_Nmm_per_deg"),
           ("car", "roll_stiffness_Nmm_per_deg")),
    CarRow("roll stiffness distribution", ("car", "roll_stiffness_front_percent"),
           ("car", "roll_stiffness_rear_percent")),
    CarRow("roll stiffness on the table (total moment / body roll)", None, None,
           ("car", "roll_stiffness_table_Nmm_per_deg")),
    CarRow("roll centre height, kinematic (car: roll axis under the CG)",
           *_axles("roll_centre_height_mm"), ("car", "roll_axis_height_under_cg_mm")),
    CarRow("roll centre height, force-based (car: roll axis under the CG)",
           *_axles("roll_centre_height_force_based_mm"),
           ("car", "roll_axis_height_under_cg_force_based_mm")),
    CarRow("roll axis inclination, kinematic (+ rising rearward)", None, None,
           ("car", "roll_axis_inclination_deg")),
    CarRow("CG height above the roll axis, kinematic", None, None,
           ("car", "roll_moment_arm_mm")),
    CarRow("roll gradient", None, None, ("car", "roll_gradient_deg_per_g")),
    CarRow("bump steer, left wheel (+ toe-in)", *_axles("bump_steer_deg_per_m")),
    CarRow("roll steer, axle (+ left)", *_axles("axle_roll_steer_deg_per_deg")),
    CarRow("lateral force steer, axle in phase (+ left)",
           *_axles("lateral_force_steer_deg_per_kN")),
    CarRow("understeer gradient from compliance steer",
           *_axles("understeer_compliance_steer_deg_per_g"),
           ("car", "understeer_compliance_steer_deg_per_g")),
    CarRow("understeer gradient from roll steer", *_axles("understeer_roll_steer_deg_per_g"),
           ("car", "understeer_roll_steer_deg_per_g")),
    CarRow("understeer gradient from the suspensions", None, None,
           ("car", "understeer_suspension_deg_per_g")),
    CarRow("anti-dive (front) / anti-lift under braking (rear)", ("front", "percent_anti_dive"),
           ("rear", "percent_anti_lift_braking")),
    CarRow("anti-lift under traction (front) / anti-squat (rear)",
           ("front", "percent_anti_lift_traction"), ("rear", "percent_anti_squat")),
)


def car_rows(figures: dict) -> list[tuple[CarRow, list[str]]]:
    """The rows of :data:`CAR_ROWS` with a figure for this car model (summary.json
    ``models.<label>``), each with its three cells formatted (``-``: none; "" where the row
    has no such cell)."""
    out = []
    for row in CAR_ROWS:
        values = row.values(figures)
        if all(v is None for v in values):
            continue
        cells = ["" if c is None else "-" if v is None else format(v, row.fmt())
                 for c, v in zip(row.cells, values)]
        out.append((row, cells))
    return out


def vehicle_table(summary: dict, out_dir: Path) -> str:
    """What ``elastokin kc --vehicle`` prints: provenance, the vehicle's data, the car's
    table per car model, where the results are."""
    v = summary["vehicle"]
    lines = [f"elastokin {summary['elastokin_version']} (exudyn {summary['exudyn_version']}), "
             f"vehicle {summary['vehicle_file']} sha256 {summary['vehicle_sha256'][:12]}"
             + (f", rig {summary['rig_file']}" if summary.get("rig_file") else "")]
    for role, a in summary["axles"].items():
        lines.append(f"  {role + ':':<7}{a['config_file']} sha256 {a['config_sha256'][:12]} "
                     f"(results {out_dir / a['results']}/)")
    lines += [f"Vehicle: wheelbase {v['wheelbase_mm']:g} mm, CG {v['cg_height_mm']:g} mm high "
              f"and {v['cg_behind_front_axle_mm']:.0f} mm behind the front axle, "
              f"{v['mass_kg']:.1f} kg ({100 * v['front_mass_fraction']:.1f} % on the front "
              f"axle); front axle's share of braking {v['brake_fraction_front']:g}, of drive "
              f"{v['drive_fraction_front']:g}", "",
              "The car on the rig (every figure and its definition: summary.json, "
              "docs/characteristics.md 'Whole car')"]
    tables = {label: car_rows(m) for label, m in summary["models"].items()}
    w = max(len(f"{row.label} {row.unit}") for rows in tables.values() for row, _ in rows)
    for label, rows in tables.items():
        m = summary["models"][label]
        lines += ["", f"model {label} (front axle {m['front_model']}, rear axle "
                  f"{m['rear_model']})", f"  {'':<{w}}{'front':>10}{'rear':>10}{'car':>10}"]
        lines += [f"  {row.label + ' ' + row.unit:<{w}}" + "".join(f"{c:>10}" for c in cells)
                  for row, cells in rows]
    lines += ["", f"Results in {out_dir}/: " + ", ".join(summary["files"])]
    return "\n".join(lines)
