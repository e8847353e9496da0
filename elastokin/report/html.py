"""``report.html``: one self-contained page (charts embedded as PNG data, no external files or
scripts) with the characteristics and errors of every model, the static equilibrium and the
provenance of every number (versions, config hash, solver settings, test files)."""

from __future__ import annotations

import base64
import html
import json
from pathlib import Path

from elastokin.rig.channels import CHARACTERISTIC_LIST, ERROR_LIST

#: the characteristics and errors tables: (summary key, label, unit, number format)
ROWS = [(c.name, (c.label, c.unit, c.fmt)) for c in CHARACTERISTIC_LIST]
ERROR_ROWS = [(e.name, (e.label, e.unit, e.fmt)) for e in ERROR_LIST]

_CSS = """body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;
text-align:right}th:first-child,td:first-child{text-align:left}figure{display:inline-block;
margin:0.5em;width:47%}figure img{width:100%}pre{background:#f4f4f4;padding:0.5em;
overflow-x:auto;font-size:85%}.note{color:#555;font-size:90%}"""


def _fmt(v, fmt: str) -> str:
    return "&ndash;" if v is None else format(v, fmt)


def _table(header: list[str], rows: list[list[str]]) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{c}</td>" for c in r) + "</tr>" for r in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _image(path: Path) -> str:
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return (f'<figure><img alt="{html.escape(path.stem)}" src="data:image/png;base64,{data}">'
            f"<figcaption>{html.escape(path.name)}</figcaption></figure>")


def write_report(path: Path, summary: dict, charts: list[Path]) -> Path:
    """Write ``report.html`` from ``summary.json``'s content and the PNG charts."""
    models = summary["models"]
    labels = list(models)
    rig = (f", rig file <code>{html.escape(summary['rig_file'])}</code>"
           if summary.get("rig_file") else "")
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>elastokin K&amp;C "
             f"report: {html.escape(summary['config_file'])}</title><style>{_CSS}</style>"
             "</head><body>",
             f"<h1>K&amp;C report: {html.escape(summary['config_file'])}</h1>",
             f"<p class='note'>elastokin {summary['elastokin_version']}, Exudyn "
             f"{summary['exudyn_version']}, config sha256 <code>{summary['config_sha256']}"
             f"</code>{rig}. Units mm, N, N&middot;mm, deg; signs ISO 8855 (see summary.json "
             "<code>sign_conventions</code>).</p>"]
    if "test" in models:
        parts.append("<p class='note'>The <b>test</b> curves are the K&amp;C test files of the "
                     "config (for the shipped case study: SYNTHETIC data, see the README).</p>")
    parts.append("<h2>Characteristics</h2>")
    rows = [[f"{html.escape(label)} [{unit}]", *(_fmt(models[m].get(key), fmt) for m in labels)]
            for key, (label, unit, fmt) in ROWS]
    parts.append(_table(["characteristic", *labels], rows))
    refs = summary.get("reference", {}).get("steer_amplitude_deg", {})
    if refs:
        parts.append("<p class='note'>Reference steer amplitude (deg, "
                     f"{html.escape(summary['static'].get('reference_source', ''))}): "
                     + ", ".join(f"{html.escape(k)} {v:g}" for k, v in refs.items()) + "</p>")
    if summary.get("warnings"):
        parts.append("<ul>" + "".join(f"<li>{html.escape(w)}</li>" for w in summary["warnings"])
                     + "</ul>")
    errors = summary.get("errors") or {}
    if errors:
        parts.append("<h2>Errors against the test</h2><p class='note'>RMS of the model's "
                     "change from its static state minus the test's, branch by branch, at the "
                     "test points.</p>")
        err_labels = list(errors)
        rows = [[f"{html.escape(label)} [{unit}]",
                 *(_fmt(errors[m].get(key), fmt) for m in err_labels)]
                for key, (label, unit, fmt) in ERROR_ROWS]
        parts.append(_table(["RMS error", *err_labels], rows))
    fit = summary.get("stiffness_identification")
    if fit:
        parts.append("<h2>Bushing-stiffness identification</h2><p class='note'>Model "
                     "<b>identified_stiffness</b>: per fitted bushing F(u) = scale &middot; "
                     "f<sub>config</sub>(u) &middot; (1 + cubic &middot; u&sup2;), fitted to the "
                     "test data by least squares (details, correlations and the residuals in "
                     f"{html.escape(fit['file'])}). Condition number "
                     f"{fit['condition_number']:.3g}.</p>")
        rows = [[html.escape(k), f"{v['value']:.4g}", html.escape(v["unit"]),
                 f"[{v['ci95'][0]:.4g}, {v['ci95'][1]:.4g}]",
                 "yes" if v["determined"] else "no"]
                for k, v in fit["parameters"].items()]
        parts.append(_table(["parameter", "value", "unit", "95 % interval", "determined"],
                            rows))
        if fit["warnings"]:
            parts.append("<ul>" + "".join(f"<li>{html.escape(w)}</li>" for w in fit["warnings"])
                         + "</ul>")
    st = summary["static"]
    parts.append(f"<h2>Static equilibrium under {st['wheel_load_N']:g} N</h2>")
    rows = [[html.escape(n), f"{b['radial_mm']:.3f}", f"{b['axial_mm']:.3f}",
             f"{b['torsion_deg']:.4f}", html.escape(", ".join(
                 f"{k} {v:g}" for k, v in b.get("reference", {}).items()))]
            for n, b in st["bushings"].items()]
    parts.append(_table(["bushing", "radial mm", "axial mm", "torsion deg", "reference"], rows))
    parts.append("<h2>Charts</h2>")
    parts += [_image(p) for p in charts if p.suffix == ".png"]
    parts.append("<h2>Provenance and solver settings</h2><pre>"
                 + html.escape(json.dumps({k: summary[k] for k in (
                     "elastokin_version", "exudyn_version", "config_file", "config_sha256",
                     "rig_file", "units", "solver") if k in summary}, indent=2)) + "</pre>")
    parts.append("</body></html>\n")
    path.write_text("".join(parts), encoding="utf-8")
    return path
