"""The chart of the joints-from-motion study (benchmarks/motion_positions.py): the located
joints' RMS error against the truth (Monte Carlo over the CMM noise) against the spread of
the rig positions and against their number, with the 0.1 and 0.2 mm marks. Matplotlib only
here, without pyplot; the chart carries its provenance."""

from __future__ import annotations

from pathlib import Path

from elastokin.report.doe_charts import new_figure, save
from elastokin.report.files import config_provenance

#: the joints drawn (a ball joint's centre; the strut's point across its axis)
JOINTS = ("J7", "J8", "tie_rod:J6", "tie_rod:J3", "strut")
_STYLE = {"J7": ("tab:blue", "o"), "J8": ("tab:orange", "s"), "tie_rod:J6": ("tab:green", "^"),
          "tie_rod:J3": ("tab:red", "v"), "strut": ("tab:purple", "D")}


def _errors(study: dict, plans: list[str], joint: str) -> list[float]:
    out = []
    for p in plans:
        j = study[p].get("joints", {}).get(joint)
        out.append(float("nan") if j is None or j["rms_error_mm"] is None
                   else j["rms_error_mm"])
    return out


def draw_motion_positions_chart(doc: dict, out_dir: Path, suspension,
                                name: str = "motion_positions", svg: bool = False
                                ) -> list[Path]:
    """The chart of a joints-from-motion positions study (``doc``: its plans from
    :func:`elastokin.studies.motion_study.motion_position_study`, ``draws``, ``noise_mm``,
    ``rack_per_travel`` and the plans of its ``spread_series`` and ``count_series``) into
    ``out_dir/name.png`` (and ``.svg``), with ``suspension``'s provenance. Two panels: RMS
    error (mm) against the rig travel spread (the same grid of positions scaled) and against
    the number of rig positions (the full spread). Returns the files written."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    study = doc["plans"]
    fig, axes = new_figure(7.0, 4.0, 1, 2)
    spread, count = doc["spread_series"], doc["count_series"]
    panels = ((axes[0, 0], [s["plan"] for s in spread], [s["travel_mm"] for s in spread],
               f"wheel travel +- mm\n(rack +- {doc['rack_per_travel']:g} x travel; 5 x 5 grid "
               "+ 3 wheel turns)"),
              (axes[0, 1], [s["plan"] for s in count], [s["positions"] for s in count],
               f"positions measured\n(n x n grid: travel +- {count[0]['travel_mm']:g}, rack "
               f"+- {count[0]['rack_mm']:g} mm; + 3 turns)"))
    for ax, plans, x, label in panels:
        for joint in JOINTS:
            colour, marker = _STYLE[joint]
            ax.plot(x, _errors(study, plans, joint), color=colour, marker=marker,
                    markersize=4, linewidth=1.2, label=joint)
        for level, style in ((0.1, ":"), (0.2, "--")):
            ax.axhline(level, color="0.35", linestyle=style, linewidth=0.9)
            ax.annotate(f"{level:g} mm", (0.0, level), xycoords=("axes fraction", "data"),
                        xytext=(3, 2), textcoords="offset points", ha="left", va="bottom",
                        fontsize=7, color="0.35")
        ax.set_yscale("log")
        ax.yaxis.set_major_locator(FixedLocator([0.03, 0.05, 0.07, 0.1, 0.15, 0.2, 0.3, 0.5, 1.0]))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel(label, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="both", color="0.9", linewidth=0.6)
    axes[0, 0].set_ylabel(f"RMS error vs truth, mm ({doc['draws']} noise draws)", fontsize=8)
    axes[0, 1].legend(fontsize=7, loc="upper right")
    fig.suptitle("Joints from motion: error against the spread and number of rig positions "
                 f"(CMM noise {doc['noise_mm']:g} mm, 95 %)", fontsize=9)
    return save(fig, name, out_dir, config_provenance(suspension), svg)
