"""What a design study writes: ``elastokin optimize`` the optimised config (the user's file
with every moved value and its old one in a comment), ``design.json`` (variables, targets
before and after, what binds, the optimiser's history, provenance), the charts and
``report.html``; ``elastokin sensitivity`` ``sensitivity.csv`` (every hardpoint coordinate's
effect per mm on every characteristic, ranked), ``sensitivity.json``, a chart and
``report.html``. Units mm, N, N*mm, deg; characteristics in their own units."""

from __future__ import annotations

import csv
import hashlib
import json
from pathlib import Path

import numpy as np

from elastokin.formats.config_edit import check_written, edited_config
from elastokin.formats.targets import characteristic_unit
from elastokin.report import design_charts
from elastokin.report.files import config_provenance
from elastokin.report.html.parts import esc, figure, note, table

CSS = ("body{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em;color:#222}"
       "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #ccc;"
       "padding:2px 8px;text-align:right}td.text,th.text{text-align:left}"
       "tr.flag td{background:#fde2e2}.note{color:#555;font-size:90%}"
       "figure{margin:1em 0}img{max-width:100%}h2{border-bottom:1px solid #ccc}")


def _sha(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _page(title: str, body: list[str]) -> str:
    return (f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>{esc(title)}'
            f"</title><style>{CSS}</style></head><body><h1>{esc(title)}</h1>"
            + "".join(body) + "</body></html>\n")


def write_design_results(result, suspension, config_path: Path, targets_path: Path,
                         out: Path, svg: bool = False, decimals: int = 6) -> list[str]:
    """Every file of ``elastokin optimize`` into ``out``; returns their names."""
    prov = {**config_provenance(suspension), "targets_file": str(targets_path),
            "targets_sha256": _sha(targets_path)}
    name = f"{Path(config_path).stem}_optimised.yaml"
    text = edited_config(Path(config_path).read_text(encoding="utf-8"), suspension,
                         result.variables, result.best.values, decimals)
    check_written(text, name, suspension, result.variables, result.best.values, decimals)
    (out / name).write_text(text, encoding="utf-8")
    doc = design_document(result, prov, name)
    (out / "design.json").write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    charts = design_charts_of(result, out, prov, svg)
    (out / "report.html").write_text(design_html(result, doc, charts), encoding="utf-8")
    return [name, "design.json", *(p.name for p in charts), "report.html"]


def design_document(result, provenance: dict, config_name: str) -> dict:
    """``design.json``: the outcome, each variable's start, optimised value and bounds,
    each target's verdict before and after, what binds, the history, provenance."""
    def rows(values):
        return [{"target": r.name, "kind": r.kind, "model": r.value, "asked": r.asked,
                 "met": r.met, "missed_by": r.miss, "unit": r.unit} for r in values.rows]

    return {
        "met": result.met, "optimiser_message": result.message, "binding": result.binding,
        "model": result.label, "optimised_config": config_name,
        "model_runs_with_derivatives": result.model_runs, "seconds": result.seconds,
        "variables": [{"name": v.name, "unit": v.unit, "start": float(a), "optimised":
                       float(b), "moved_by": float(b - a), "lower": v.lower, "upper": v.upper}
                      for v, a, b in zip(result.variables, result.start.values,
                                         result.best.values)],
        "targets_start": rows(result.start_values),
        "targets_optimised": rows(result.best_values),
        "history": [{"run": h.run, "values": h.values, "objective": h.objective,
                     "violation": h.violation} for h in result.history],
        "provenance": {**provenance, "solver": result.best.models[result.label].solver},
    }


def _model_curve(run, label, spec):
    from elastokin.studies.design_targets import curve_branch

    sweep = run.sweep(label, spec.load_case, spec.side)
    rows = curve_branch(sweep, spec.x)
    x = np.asarray(sweep.columns[spec.x], float)[rows]
    y = np.asarray(sweep.columns[spec.y], float)[rows]
    order = np.argsort(x)
    x, y = x[order], y[order]
    if spec.relative:
        y = y - np.interp(0.0, x, y)
    lo, hi = min(spec.points[spec.x]), max(spec.points[spec.x])
    pad = 0.1 * (hi - lo) or 1.0
    keep = (x >= lo - pad) & (x <= hi + pad)
    return x[keep], y[keep]


def _footer(prov: dict) -> dict:
    """The provenance for a chart's footer: the files by name (the full paths are in
    design.json and the report)."""
    return {**prov, "config_file": Path(prov["config_file"]).name,
            "rig_file": prov.get("rig_file") and Path(prov["rig_file"]).name}


def design_charts_of(result, out: Path, prov: dict, svg: bool) -> list[Path]:
    spec, label = result.targets.spec, result.label
    prov = _footer(prov)
    paths = []
    for name, c in spec.curves.items():
        paths += design_charts.curve_chart(name, c, _model_curve(result.start, label, c),
                                           _model_curve(result.best, label, c), out, prov,
                                           svg)[:1]
    if spec.characteristics:
        start = {n: result.start.summary[label][n] for n in spec.characteristics}
        best = {n: result.best.summary[label][n] for n in spec.characteristics}
        paths += design_charts.characteristics_chart(start, best, spec.characteristics, out,
                                                     prov, svg)[:1]
    paths += design_charts.history_chart(result.history, out, prov, svg)[:1]
    return paths


def design_html(result, doc: dict, charts: list[Path]) -> str:
    verdict = ("every target is met" if result.met else
               "the targets cannot all be met: the best point found is written")
    body = [f"<h2>1. Summary</h2><p><b>{esc(verdict)}</b> (model <code>{esc(result.label)}"
            f"</code>, {result.model_runs} model runs with derivatives, {result.seconds:.1f} s;"
            f" optimiser: {esc(result.message)}). The optimised config is "
            f"<code>{esc(doc['optimised_config'])}</code>.</p>"]
    if result.binding:
        body.append("<p>What binds:</p><ul>" + "".join(f"<li>{esc(b)}</li>"
                                                       for b in result.binding) + "</ul>")
    body.append("<h2>2. Design variables</h2>" + table(
        ["variable", "unit", "start", "optimised", "moved by", "lower", "upper"],
        [[esc(v["name"]), esc(v["unit"]), f"{v['start']:.6g}", f"{v['optimised']:.6g}",
          f"{v['moved_by']:+.4g}", f"{v['lower']:.6g}", f"{v['upper']:.6g}"]
         for v in doc["variables"]], text_columns=(0, 1)))
    pairs = zip(result.start_values.rows, result.best_values.rows)
    body.append("<h2>3. Targets</h2>" + table(
        ["target", "asked", "unit", "start", "optimised", "met"],
        [[esc(a.name), esc(b.asked), esc(b.unit), f"{a.value:.5g}", f"{b.value:.5g}",
          "yes" if b.met else f"no (by {b.miss:.3g})"] for a, b in pairs],
        ["" if b.met else "flag" for b in result.best_values.rows], text_columns=(0, 1, 2)))
    body.append(note("A curve's value is its worst point; the optimised figures are those of "
                     "a plain run of the written (rounded) values."))
    body.append("<h2>4. Charts</h2>" + "".join(
        figure(p, p.stem, i + 1, p.stem.replace("_", " ")) for i, p in enumerate(charts)))
    prov = doc["provenance"]
    body.append("<h2>5. Provenance</h2>" + table(None, [
        [esc(k), esc(v)] for k, v in prov.items() if k != "solver"] + [
        ["solver", esc(json.dumps(prov["solver"]))]], text_columns=(0, 1)))
    return _page("elastokin design to targets", body)


def write_sensitivity_results(tab, suspension, out: Path, svg: bool = False) -> list[str]:
    """Every file of ``elastokin sensitivity`` into ``out``; returns their names."""
    prov = config_provenance(suspension)
    with open(out / "sensitivity.csv", "w", newline="", encoding="utf-8") as fh:
        fh.write(f"# elastokin sensitivity: effect of each hardpoint coordinate (config frame) "
                 f"per mm on each characteristic, model {tab.label}; config "
                 f"{prov['config_file']} sha256 {prov['config_sha256']}; elastokin "
                 f"{prov['elastokin_version']}, exudyn {prov['exudyn_version']}\n")
        w = csv.writer(fh)
        w.writerow(["characteristic", "unit", "value", "rank", "hardpoint", "axis",
                    "effect_per_mm"])
        for j, name in enumerate(tab.characteristics):
            for rank, (v, e) in enumerate(tab.ranked(name), 1):
                w.writerow([name, characteristic_unit(name), f"{tab.values[j]:.10g}", rank,
                            v.item, "xyz"[v.axis], f"{e:.10g}"])
    doc = {"model": tab.label, "seconds": tab.seconds,
           "left_out": [{"coordinate": n, "why": w} for n, w in tab.skipped],
           "characteristics": {name: {"unit": characteristic_unit(name),
                                      "value": float(tab.values[j]),
                                      "effects_per_mm": {v.name: float(tab.effects[i, j])
                                                         for i, v in enumerate(tab.variables)}}
                               for j, name in enumerate(tab.characteristics)},
           "provenance": {**prov, "solver": tab.run.models[tab.label].solver}}
    (out / "sensitivity.json").write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    charts = design_charts.effects_chart(tab, out, _footer(prov), svg)[:1]
    (out / "report.html").write_text(sensitivity_html(tab, prov, charts), encoding="utf-8")
    return ["sensitivity.csv", "sensitivity.json", *(p.name for p in charts), "report.html"]


def sensitivity_html(tab, prov: dict, charts: list[Path], top: int = 10) -> str:
    body = [f"<p>Model <code>{esc(tab.label)}</code> of <code>{esc(prov['config_file'])}"
            f"</code>: the exact derivative of each characteristic with respect to each of "
            f"{len(tab.variables)} hardpoint coordinates (config frame; both sides of an axle "
            f"moved together), from one run with sensitivities ({tab.seconds:.1f} s). The "
            f"{top} largest effects per characteristic; every one in "
            "<code>sensitivity.csv</code>.</p>"]
    if tab.skipped:
        body.append(note("Left out (the config does not let them move): " + "; ".join(
            f"{esc(name)} ({esc(why)})" for name, why in tab.skipped)))
    for j, name in enumerate(tab.characteristics):
        unit = characteristic_unit(name)
        body.append(f"<h2>{esc(name)} = {tab.values[j]:.5g} {esc(unit)}</h2>" + table(
            ["rank", "hardpoint coordinate", f"effect [{unit} per mm]"],
            [[str(r), esc(v.name), f"{e:+.4g}"] for r, (v, e) in
             enumerate(tab.ranked(name)[:top], 1)], text_columns=(1,)))
    body += [figure(p, p.stem, i + 1, "largest effects per mm") for i, p in enumerate(charts)]
    body.append("<h2>Provenance</h2>" + table(None, [[esc(k), esc(v)] for k, v in prov.items()],
                                              text_columns=(0, 1)))
    return _page("elastokin hardpoint sensitivity table", body)
