"""The chart of the largest loads per element (``largest_loads.png``): for every connection,
spring, stop, the anti-roll bar and the steering gear, the largest force magnitude it
transmits in any load case, one bar per model, the load case of each bar written beside it.
From summary.json's ``models.<label>.loads`` (:func:`elastokin.rig.loads.load_peaks`); drawn on
the shared canvas (matplotlib, lazily imported).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from elastokin.report.chart_canvas import STYLE, footer_text

#: the chart's file (without suffix) and title
LOAD_CHART = "largest_loads"
LOAD_CHART_TITLE = "Largest force per element over every load case"
#: elements left out of the chart: the rig's contact patches (the applied loads), the model's
#: idle-spin springs
NOT_CHARTED = ("contact_patch", "idle_spin", "load")


@dataclass(frozen=True)
class LoadChartData:
    """Per model (in order) the largest force (N) of each element (in ``elements`` order,
    the first model's largest first) and the load case it occurs in."""

    elements: list[str]
    kinds: list[str]
    models: list[str]
    force_N: dict[str, list[float]]
    case: dict[str, list[str]]


def load_chart_data(summary: dict) -> LoadChartData | None:
    """The chart's data from summary.json's content (None: no model recorded loads)."""
    peaks: dict[str, dict[str, tuple[float, str]]] = {}
    kinds: dict[str, str] = {}
    for model, figures in summary["models"].items():
        for name, entry in (figures.get("loads") or {}).items():
            if entry["kind"] in NOT_CHARTED:
                continue
            kinds[name] = entry["kind"]
            cases = entry["load_cases"]
            case = max(cases, key=lambda c: cases[c]["force_N"])
            peaks.setdefault(model, {})[name] = (cases[case]["force_N"], case)
    if not peaks:
        return None
    models = list(peaks)
    first = peaks[models[0]]
    elements = sorted(kinds, key=lambda n: -first.get(n, (0.0, ""))[0])
    return LoadChartData(elements, [kinds[n] for n in elements], models,
                         {m: [peaks[m].get(n, (np.nan, ""))[0] for n in elements]
                          for m in models},
                         {m: [peaks[m].get(n, (np.nan, ""))[1] for n in elements]
                          for m in models})


def draw_load_chart(canvas, data: LoadChartData, provenance: dict):
    """Horizontal bars, the largest load at the top, a bar per model; returns the figure."""
    fig, ax, _, footer = canvas.axes("bars")
    n, k = len(data.elements), len(data.models)
    inches = 1.3 + n * (0.08 + 0.1 * k)  # a bar of 0.1 in per model, 0.08 in between
    fig.set_size_inches(7.0, inches)
    fig.subplots_adjust(bottom=0.75 / inches, top=1.0 - 0.4 / inches)
    height = 0.8 / k
    y = np.arange(n)
    top = max((max((v for v in vals if np.isfinite(v)), default=0.0)
               for vals in data.force_N.values()), default=0.0) or 1.0
    for j, model in enumerate(data.models):
        style = STYLE.get(model, {})
        pos = y - 0.4 + height * (j + 0.5)
        values = np.nan_to_num(np.asarray(data.force_N[model], float))
        bars = ax.barh(pos, values, height=height * 0.9, label=model,
                       color=style.get("color"), alpha=0.45 if ":" in
                       str(style.get("linestyle", "")) else 0.9)
        first = data.case[data.models[0]]
        for i, (bar, value, case) in enumerate(zip(bars, values, data.case[model])):
            if j and case == first[i]:
                continue  # the same load case as the first model's bar: named once
            text = case.removeprefix("vehicle_loads:") if value > 0.0 else "0 N"
            ax.text(value + 0.01 * top, bar.get_y() + bar.get_height() / 2, text,
                    va="center", fontsize=7, color="0.25")
    ax.set_yticks(y, [f"{e} ({kind})" for e, kind in zip(data.elements, data.kinds)],
                  fontsize=7)
    ax.invert_yaxis()
    ax.set_xlim(0.0, top * 1.35)  # room for the load cases' names
    ax.set_xlabel("largest force [N] (its load case beside the bar, once if the models agree)",
                  fontsize=9)
    ax.set_title(LOAD_CHART_TITLE, fontsize=11, y=1.0, pad=7)
    ax.grid(True, axis="x", alpha=0.3)
    ax.legend(fontsize=8, loc="lower right", framealpha=0.9)
    footer.set_text(footer_text(provenance))
    return fig
