"""report.html reads like a K&C report (issue 19, item 2): a section per stage (geometric
identification with the joints against dL_max, static state, characteristics, errors), the
sign conventions, full-width charts with captions, provenance as a short table. The page is
checked as HTML here, and rendered in headless Chromium when it is installed."""

from __future__ import annotations

import json
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.report.html import HEADINGS, solver_rows

from .conftest import CASE

RIG = CASE.parent / "rigs" / "travel_only.yaml"
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                  "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync", "--hide-scrollbars"]


class Page(HTMLParser):
    """The structure of the report: sections (id, heading), figures (id, image source,
    caption), table rows (class, text), every src/href, and whether a <pre> is there."""

    def __init__(self, text: str):
        super().__init__()
        self.sections: list[list[str]] = []
        self.figures: list[dict] = []
        self.rows: list[tuple[str, str]] = []
        self.links: list[str] = []
        self.tags: set[str] = set()
        self._in: list[str] = []
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.tags.add(tag)
        self.links += [a[k] for k in ("src", "href") if k in a]
        if tag == "section":
            self.sections.append([a.get("id"), ""])
        elif tag == "figure":
            self.figures.append({"id": a.get("id"), "src": "", "caption": ""})
        elif tag == "img" and self.figures and "figure" in self._in:
            self.figures[-1]["src"] = a.get("src", "")
        elif tag == "tr":
            self.rows.append((a.get("class", ""), ""))
        if tag not in ("img", "meta", "br"):
            self._in.append(tag)

    def handle_endtag(self, tag):
        if tag in self._in:
            del self._in[len(self._in) - 1 - self._in[::-1].index(tag)]

    def handle_data(self, data):
        if "h2" in self._in and self.sections:
            self.sections[-1][1] += data
        if "figcaption" in self._in:
            self.figures[-1]["caption"] += data
        if "tr" in self._in and self.rows:
            cls, text = self.rows[-1]
            self.rows[-1] = (cls, text + data + " ")


@pytest.fixture(scope="module")
def results(tmp_path_factory) -> Path:
    """`elastokin kc` on the case study, initial and identified models, travel-only rig (a
    few seconds): identification, test data and a rig file, every section but the fit."""
    out = tmp_path_factory.mktemp("report") / "res"
    result = CliRunner().invoke(main, ["kc", "--config", str(CASE), "--rig", str(RIG),
                                       "--models", "initial,identified", "--out", str(out),
                                       "--quiet"])
    assert result.exit_code == 0, result.output
    return out


@pytest.fixture(scope="module")
def page(results) -> Page:
    return Page((results / "report.html").read_text())


def test_a_section_per_stage_in_order(page):
    assert [s[0] for s in page.sections] == ["summary", "warnings", "identification",
                                             "static", "characteristics", "charts", "errors",
                                             "signs", "provenance"]
    for number, (key, heading) in enumerate(page.sections, start=1):
        assert heading == f"{number}. {HEADINGS[key]}"


def test_identification_section_shows_shifts_against_dl_max(page, results):
    ident = json.loads((results / "identification.json").read_text())
    flagged = {n for n, j in ident["joints"].items() if j["exceeds_clearance"]}
    assert flagged == {"J1", "J8"}
    rows = [text.split()[0] for cls, text in page.rows if cls == "flag"]
    assert sorted(rows) == sorted(flagged)
    text = " ".join(t for _, t in page.rows)
    assert "knuckle 0.0339 3 M2" in text  # the dropped mark, by its label
    html = (results / "report.html").read_text()
    assert "Verification" in html and "eq. (1)" in html and "beyond dL" in html


def test_charts_full_width_embedded_with_captions(page, results):
    pngs = sorted(p.stem for p in results.glob("*.png"))
    assert sorted(f["id"].removeprefix("chart-") for f in page.figures) == pngs
    for f in page.figures:
        assert f["src"].startswith("data:image/png;base64,")
        assert f["caption"].startswith("Chart ") and f"{f['id'][6:]}.png" in f["caption"]
        assert len(f["caption"]) > 120  # says what is plotted, not only a file name
    assert "Fig. 9a" in page.figures[0]["caption"]
    assert "figure img{width:100%" in (results / "report.html").read_text()


def test_self_contained_and_provenance_as_a_short_table(page, results):
    summary = json.loads((results / "summary.json").read_text())
    assert not [u for u in page.links if u.startswith(("http:", "https:", "//"))]
    assert "pre" not in page.tags  # no raw JSON dump
    text = " ".join(t for _, t in page.rows)
    for f in summary["input_files"]:
        assert f["sha256"] and f["sha256"] in text, f
    roles = [f["role"] for f in summary["input_files"]]
    assert roles[:2] == ["config", "rig file"] and roles.count("K&C test") == 10
    assert summary["config_sha256"] != summary["rig_sha256"]
    assert text.count("newton_relative_tolerance") == 1  # solver settings once


def test_solver_settings_once_and_what_differs():
    rows = solver_rows({"a": {"tol": 1e-8, "kinematic": False},
                        "b": {"tol": 1e-8, "kinematic": True},
                        "test": {"source": "K&C rig test data"}})
    assert rows == [["tol", "1e-08"], ["kinematic", "a: False, b: True"]]


def test_signs_in_the_report(page):
    text = " ".join(t for _, t in page.rows)
    assert "positive toe-in" in text and "top of the wheel leaning outboard" in text


# ------------------------------------------------------------------------------ browser
def _chromium() -> str:
    path = shutil.which("chromium") or shutil.which("chromium-browser")
    if path is None:
        pytest.skip("headless Chromium is not installed (apt-get install chromium)")
    return path


def test_rendered_in_headless_chromium(results, tmp_path):
    """The page as a browser builds it (scripts run) has every section, and its screenshot is
    a page of text and charts, not an empty or broken one."""
    from PIL import Image

    chromium = _chromium()
    url = (results / "report.html").resolve().as_uri()
    profile = tmp_path / "profile"
    run = [chromium, *CHROMIUM_FLAGS, f"--user-data-dir={profile}"]
    dom = subprocess.run([*run, "--dump-dom", url], capture_output=True, text=True,
                         timeout=120, check=True).stdout
    rendered = Page(dom)
    assert [s[0] for s in rendered.sections] == [s[0] for s in Page(
        (results / "report.html").read_text()).sections]
    assert 'id="lightbox" hidden' in dom  # the enlarge overlay exists, closed
    shot = tmp_path / "report.png"
    subprocess.run([*run, "--window-size=1280,3000", f"--screenshot={shot}", url],
                   capture_output=True, timeout=120, check=True)
    pixels = np.asarray(Image.open(shot).convert("L"), float)
    assert pixels.shape == (3000, 1280)
    ink = pixels < 128  # text and lines
    assert 0.01 < ink.mean() < 0.3
    # the content spans the page's width: the tables and the heading rules
    assert ink[:, 100:1180].any(axis=0).mean() > 0.9
