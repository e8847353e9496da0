"""The pieces ``report.html`` is made of (:mod:`elastokin.report.html.page`,
:mod:`elastokin.report.html.axle`): escaped text, numbers, tables, notes and the figures of the
charts (PNG embedded as data)."""

from __future__ import annotations

import base64
import html
from pathlib import Path

#: the style of every report page
PAGE_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;max-width:1100px;
margin:1.5em auto;padding:0 1em;color:#1d1d1d;line-height:1.4}
h1{margin-bottom:0.2em}h2{border-bottom:2px solid #1d1d1d;padding-bottom:2px;margin-top:2em}
h3{margin-top:1.4em}
table{border-collapse:collapse;margin:0.6em 0 1em 0;font-size:92%}
td,th{border:1px solid #c4c4c4;padding:3px 8px;text-align:right;vertical-align:top}
th{background:#f0f0f0}th:first-child,td:first-child{text-align:left}
td.text,th.text{text-align:left}
tr.flag td{background:#fff1e0}.bad{color:#b00000;font-weight:bold}
.note{color:#505050;font-size:92%}.synthetic{background:#fff4c2;padding:0.5em 0.8em;
border-left:4px solid #d9a400}
nav ol{columns:2;font-size:95%}
figure{margin:1.2em 0 2em 0;width:100%}
figure img{width:100%;height:auto;cursor:zoom-in;border:1px solid #ddd}
figcaption{font-size:92%;color:#303030;margin-top:0.3em}
#lightbox{position:fixed;inset:0;background:rgba(0,0,0,0.85);display:flex;
align-items:center;justify-content:center;cursor:zoom-out;z-index:10}
#lightbox[hidden]{display:none}
#lightbox img{max-width:98vw;max-height:96vh;height:96vh;width:auto;object-fit:contain;
background:#fff}
code{font-size:92%}
h4{margin:1em 0 0.3em 0}.wide{overflow-x:auto}
.worst{font-weight:bold;background:#ffd9a0;padding:0 3px}
details{margin:0.5em 0}
"""

#: click a chart to see it as large as the window; click or Escape to close
LIGHTBOX_SCRIPT = """<div id="lightbox" hidden><img alt="enlarged chart"></div><script>
(function(){var box=document.getElementById('lightbox'),big=box.querySelector('img');
document.querySelectorAll('figure img').forEach(function(img){img.addEventListener('click',
function(){big.src=img.src;big.alt=img.alt;box.hidden=false;});});
box.addEventListener('click',function(){box.hidden=true;});
document.addEventListener('keydown',function(e){if(e.key==='Escape'){box.hidden=true;}});
})();</script>"""


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


def page(title: str, intro: list[str], sections: list[tuple[str, str, list[str]]]) -> str:
    """A whole report page: its title, ``intro`` (HTML under the title), the contents and
    the numbered ``sections`` (id, heading, body pieces), the charts' lightbox."""
    head = [f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><meta '
            f'name="viewport" content="width=device-width, initial-scale=1"><title>'
            f"{esc(title)}</title><style>{PAGE_CSS}</style></head><body>",
            f"<header><h1>{esc(title)}</h1>", *intro,
            "<nav><b>Contents</b><ol>" + "".join(
                f'<li><a href="#{key}">{esc(heading)}</a></li>' for key, heading, _ in sections)
            + "</ol></nav></header>"]
    body = [f'<section id="{key}"><h2>{k + 1}. {esc(heading)}</h2>' + "".join(parts)
            + "</section>" for k, (key, heading, parts) in enumerate(sections)]
    return "".join(head + body) + LIGHTBOX_SCRIPT + "</body></html>\n"
