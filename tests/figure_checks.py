"""Checks of a drawn matplotlib figure shared by the chart tests."""

from __future__ import annotations


def texts_outside_the_figure(fig) -> list[str]:
    """What of ``fig`` (each axes' title, axis labels, drawn tick labels and legend, and the
    figure's own texts) lies outside the figure, as readable lines; empty when all fits."""
    fig.canvas.draw()  # places the axis labels beside their tick labels
    renderer = fig.canvas.get_renderer()
    boxes = [(f"axes {k} ({ax.get_title()!r})", ax.get_tightbbox(renderer))
             for k, ax in enumerate(fig.axes)]
    boxes += [(repr(t.get_text()), t.get_window_extent(renderer)) for t in fig.texts
              if t.get_text()]
    width, height = fig.bbox.x1, fig.bbox.y1
    return [f"{what}: {box.bounds} outside (0, 0, {width}, {height})" for what, box in boxes
            if box.x0 < -0.5 or box.y0 < -0.5 or box.x1 > width + 0.5 or box.y1 > height + 0.5]
