"""The pieces ``report.html`` is made of (:mod:`elastokin.report.html`,
:mod:`elastokin.report.html_axle`): escaped text, numbers, tables, notes and the figures of the
charts (PNG embedded as data)."""

from __future__ import annotations

import base64
import html
from pathlib import Path


def esc(text) -> str:
    return html.escape(str(text))


def num(value, fmt: str) -> str:
    """A number in ``fmt``, or an en dash for none."""
    return "&ndash;" if value is None else format(value, fmt)


def table(header: list[str] | None, rows: list[list[str]], classes: list[str] | None = None,
          text_columns: tuple[int, ...] = ()) -> str:
    """An HTML table (``header`` None: none); cells are HTML already; ``classes``: a class per
    row (e.g. ``flag``); ``text_columns``: left-aligned columns."""
    def cell(tag: str, i: int, c: str) -> str:
        cls = ' class="text"' if i in text_columns else ""
        return f"<{tag}{cls}>{c}</{tag}>"

    head = "".join(cell("th", i, esc(h)) for i, h in enumerate(header or []))
    body = [f"<tr>{head}</tr>"] if header else []
    for k, r in enumerate(rows):
        cls = f' class="{classes[k]}"' if classes and classes[k] else ""
        body.append(f"<tr{cls}>" + "".join(cell("td", i, c) for i, c in enumerate(r))
                    + "</tr>")
    return f"<table>{''.join(body)}</table>"


def note(text: str) -> str:
    return f'<p class="note">{text}</p>'


def figure(path: Path, title: str, number: int, caption: str) -> str:
    """A chart as a full-width figure: the PNG embedded, "Chart n." and its caption, the
    file's name."""
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    image = f'<img alt="{esc(title)}" src="data:image/png;base64,{data}" width="1050">'
    return (f'<figure id="chart-{esc(path.stem)}">{image}<figcaption><b>Chart {number}.</b> '
            f'{esc(caption)} <span class="note">(file <code>{esc(path.name)}</code>)</span>'
            "</figcaption></figure>")
