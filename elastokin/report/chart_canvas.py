"""The canvas every K&C chart is drawn on (matplotlib's Agg, no pyplot; imported lazily): the
models' line styles, the layouts (one panel, a chart over its residual panel, a left and a right
wheel's panels side by side), the provenance footer, the legend's corner and the PNG/SVG writer.
One figure per layout is made once and reused from chart to chart.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

STYLE = {
    "test": {"color": "black", "linestyle": "-", "linewidth": 2.0},
    "initial": {"color": "tab:blue", "linestyle": "-"},
    "identified": {"color": "tab:red", "linestyle": "-"},
    "identified_motion": {"color": "tab:purple", "linestyle": "-."},
    "initial_kinematic": {"color": "tab:blue", "linestyle": ":"},
    "identified_kinematic": {"color": "tab:red", "linestyle": ":"},
    "identified_stiffness": {"color": "tab:green", "linestyle": "--"},
}
#: number formats of the legend by unit: (static value, RMS error)
LEGEND_FORMATS = {"deg": (".3f", ".4f"), "mm": (".2f", ".3f"), "N": (".0f", ".1f")}


#: resolution of the PNG charts: 7 in wide at 150 dpi is 1050 px, the report's full width
DPI = 150
#: figure size (in) and margins of each layout: one panel (1), a 3:1 chart over its residual
#: panel (2), or a left and a right wheel's panels side by side sharing the y axis ("pair"),
#: under a figure title (fixed margins: a layout engine costs about as much as drawing the chart;
#: one panel is as tall as the two-panel chart's upper one, so that the longest two-line y
#: label fits)
LAYOUTS = {1: ((7.0, 5.6), {"left": 0.155, "right": 0.975, "bottom": 0.11, "top": 0.94}),
           2: ((7.0, 6.6), {"left": 0.155, "right": 0.975, "bottom": 0.1, "top": 0.945,
                            "hspace": 0.07, "height_ratios": (3, 1)}),
           "pair": ((7.0, 5.0), {"left": 0.115, "right": 0.98, "bottom": 0.125, "top": 0.875,
                                 "wspace": 0.04}),
           # horizontal bars with long labels (the loads chart sets its height per bar)
           "bars": ((7.0, 8.0), {"left": 0.34, "right": 0.97, "bottom": 0.08, "top": 0.95})}
#: x position of the y labels (axes fraction): fixed, so that stacked panels align without
#: measuring their tick labels; the pair's narrower panels need more
YLABEL_X = -0.115
YLABEL_X_PAIR = -0.2


def footer_text(provenance: dict) -> str:
    """The provenance line every chart carries: versions, the config (and rig) file with the
    first 12 hex digits of its SHA-256."""
    rig = provenance.get("rig_file")
    rig_sha = provenance.get("rig_sha256") or ""
    rig_txt = f"; rig {rig} ({rig_sha[:12]})" if rig else ""
    return (f"elastokin {provenance['elastokin_version']}, Exudyn "
            f"{provenance['exudyn_version']}; config {provenance['config_file']} "
            f"(sha256 {provenance['config_sha256'][:12]}){rig_txt}")


def provenance_footer(fig, provenance: dict | None = None):
    """Write the provenance line (:func:`footer_text`) at the figure's bottom left (None: an
    empty line, whose text is set per chart); returns the text artist."""
    text = "" if provenance is None else footer_text(provenance)
    return fig.text(0.01, 0.008, text, fontsize=7, color="0.3", ha="left", va="bottom")


class ChartCanvas:
    """The figures the charts are drawn on (matplotlib's Agg canvas, no pyplot): one per
    layout (:data:`LAYOUTS`), created on first use and reused, a chart's artists removed
    after it is saved; axes, ticks and fonts are made once."""

    def __init__(self):
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self._new = (Figure, FigureCanvasAgg)
        self._layouts: dict[int | str, tuple] = {}

    def axes(self, panels: int | str):
        """(figure, chart axes, residual axes or None, footer text), emptied, for
        ``panels`` 1 or 2; for ``"pair"``: (figure, left wheel's axes, right wheel's axes,
        footer text), the y axis shared."""
        if panels not in self._layouts:
            self._layouts[panels] = self._make(panels)
        fig, ax, axr, footer = self._layouts[panels]
        for a in (ax, axr):
            if a is None:
                continue
            for artist in [*a.lines, *a.texts, *a.collections, *a.patches]:
                artist.remove()
            if a.get_legend() is not None:
                a.get_legend().remove()
            a.set_prop_cycle(None)  # colours of unstyled models from the start
            a.set_title("")
            a.set_xlabel("")
            a.set_ylabel("")
            a.relim()
            a.autoscale(True)
        return fig, ax, axr, footer

    def _make(self, panels: int | str) -> tuple:
        Figure, FigureCanvasAgg = self._new
        size, margins = LAYOUTS[panels]
        fig = Figure(figsize=size, dpi=DPI)
        FigureCanvasAgg(fig)
        kw = dict(margins)
        if panels in (1, "bars"):
            fig.subplots_adjust(**kw)
            axes = (fig.add_subplot(), None)
        elif panels == 2:
            gs = fig.add_gridspec(2, 1, height_ratios=kw.pop("height_ratios"), **kw)
            top = fig.add_subplot(gs[0])
            axes = (top, fig.add_subplot(gs[1], sharex=top))
            top.tick_params(labelbottom=False)
        else:
            gs = fig.add_gridspec(1, 2, **kw)
            left = fig.add_subplot(gs[0])
            axes = (left, fig.add_subplot(gs[1], sharey=left))
            axes[1].tick_params(labelleft=False)
        for ax in axes:
            if ax is not None:
                ax.yaxis.set_label_coords(YLABEL_X_PAIR if panels == "pair" else YLABEL_X,
                                          0.5)
        return (fig, *axes, provenance_footer(fig))


def corner_counts(ax, curves: list[tuple[np.ndarray, np.ndarray]], entries: int,
                  width: float = 0.6) -> dict[str, int]:
    """How many curve points lie in each corner box of ``ax`` about the size of a legend of
    ``entries`` lines, ``width`` of the axes wide (:func:`legend_height` high)."""
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    height = legend_height(entries)
    counts = {}
    for corner, (left, bottom) in (("upper left", (0.0, 1.0 - height)),
                                   ("upper right", (1.0 - width, 1.0 - height)),
                                   ("lower left", (0.0, 0.0)),
                                   ("lower right", (1.0 - width, 0.0))):
        n = 0
        for xs, ys in curves:
            u = (np.asarray(xs) - x0) / (x1 - x0 or 1.0)
            v = (np.asarray(ys) - y0) / (y1 - y0 or 1.0)
            n += int(np.count_nonzero((u >= left) & (u <= left + width)
                                      & (v >= bottom) & (v <= bottom + height)))
        counts[corner] = n
    return counts


#: the smallest y range a chart shows (its display unit): a quantity that does not change
#: (the toe of an axle that cannot steer) is drawn flat, not as solver noise of 1e-16
MIN_Y_SPAN = 1e-4


def floor_y_span(ax, min_span: float = MIN_Y_SPAN) -> None:
    """Widen ``ax``'s y range about its middle to ``min_span`` when it is narrower."""
    y0, y1 = ax.get_ylim()
    if y1 - y0 < min_span:
        mid = 0.5 * (y0 + y1)
        ax.set_ylim(mid - 0.5 * min_span, mid + 0.5 * min_span)


def legend_height(entries: int) -> float:
    """About how high a legend of ``entries`` lines is, as a fraction of a chart's axes."""
    return min(0.9, 0.06 * entries + 0.04)


def legend_corner(ax, curves: list[tuple[np.ndarray, np.ndarray]], entries: int,
                  width: float = 0.6) -> str:
    """The corner of ``ax`` whose box (:func:`corner_counts`) holds the fewest curve points:
    matplotlib's ``loc="best"`` at a small part of its cost."""
    counts = corner_counts(ax, curves, entries, width)
    return min(counts, key=counts.get)  # first of the least crowded, in the order above


def save_chart(fig, path: Path, svg: bool = False) -> list[Path]:
    """``path`` (.png) and, with ``svg``, the same chart as .svg beside it (reproducible
    ids, no date)."""
    from matplotlib import rc_context
    from PIL import Image

    # the opaque chart as RGB at a fast zlib level: half the time of savefig's RGBA PNG, 10 %
    # larger than its best compression
    fig.canvas.draw()
    rgb = np.asarray(fig.canvas.buffer_rgba())[..., :3]
    Image.fromarray(np.ascontiguousarray(rgb)).save(path, compress_level=3, dpi=(DPI, DPI))
    if not svg:
        return [path]
    with rc_context({"svg.hashsalt": "elastokin"}):
        fig.savefig(path.with_suffix(".svg"), metadata={"Date": None})
    return [path, path.with_suffix(".svg")]


def residual_rms(points: list[tuple[str, np.ndarray, np.ndarray]] | None) -> float | None:
    """The RMS of the residuals of :func:`elastokin.rig.comparison.residual_points` (model
    minus test, changes from the static state, every branch): None without points."""
    if not points:
        return None
    r = np.concatenate([p[2] for p in points])
    return float(np.sqrt(np.mean(r ** 2))) if r.size else None
