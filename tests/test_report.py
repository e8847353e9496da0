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
from elastokin.report.html.page import HEADINGS, solver_rows
from elastokin.rig.channels import AXLE_CHARACTERISTIC_LIST, CHARACTERISTIC_LIST, display_unit

from .conftest import CASE, ROOT

RIG = CASE.parent / "rigs" / "travel_only.yaml"
AXLE = ROOT / "configs" / "double_wishbone_axle.yaml"
AXLE_RIG = ROOT / "tests" / "data" / "rigs" / "axle_quick.yaml"  # every axle chart, few steps
CORNER = ROOT / "tests" / "data" / "double_wishbone.yaml"
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
        self.cells: list[list[str]] = []  # per table row, each cell's text
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
            self.cells.append([])
        elif tag in ("td", "th") and self.cells:
            self.cells[-1].append("")
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
            if self.cells and self.cells[-1]:
                self.cells[-1][-1] += data


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


def run_kc(out: Path, config: Path, rig: Path) -> Path:
    result = CliRunner().invoke(main, ["kc", "--config", str(config), "--rig", str(rig),
                                       "--out", str(out), "--quiet"])
    assert result.exit_code == 0, result.output
    return out


@pytest.fixture(scope="module")
def axle_results(tmp_path_factory) -> Path:
    """`elastokin kc` on the double wishbone axle (rack, anti-roll bar, vehicle data; no test
    data): parallel travel, roll and steering in few steps (a few seconds)."""
    return run_kc(tmp_path_factory.mktemp("report") / "axle", AXLE, AXLE_RIG)


@pytest.fixture(scope="module")
def axle_page(axle_results) -> Page:
    return Page((axle_results / "report.html").read_text())


def test_a_section_per_stage_in_order(page):
    assert [s[0] for s in page.sections] == ["summary", "warnings", "view", "identification",
                                             "static", "characteristics", "charts", "axle",
                                             "loads", "errors", "signs", "provenance"]
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


# ------------------------------------------------------------------------------ the axle
def _rows(page: Page) -> dict[str, list[str]]:
    """Table rows by their first cell's text (the first such row): the other cells' texts."""
    out = {}
    for cells in page.cells:
        if cells:
            out.setdefault(cells[0].strip(), [c.strip() for c in cells[1:]])
    return out


def test_axle_section_of_the_double_wishbone_axle(axle_page, axle_results):
    summary = json.loads((axle_results / "summary.json").read_text())
    assert [s[0] for s in axle_page.sections] == ["summary", "warnings", "view", "static",
                                                  "characteristics", "charts", "axle",
                                                  "loads", "signs", "provenance"]
    # the rig's 25 deg steering step leaves one steering-wheel angle (0) in the +-20 deg
    # window of the on-centre steering ratio: not determined, a dash and a warning saying why
    assert [summary["models"][m]["axle"]["steering_ratio_centre"] for m in summary["models"]
            ] == [None, None]
    assert any("steering ratio on centre" in w and "within +-20 deg" in w
               for w in summary["warnings"])
    axle = summary["axle"]
    assert (axle["config_side"], axle["wheelbase_mm"], axle["track_mm"]) == (
        "left", 3378.0, pytest.approx(1820.0))
    rows = _rows(axle_page)
    assert rows["wheelbase [mm]"] == ["3378"]
    assert rows["steering rack"] == ["yes"] and rows["anti-roll bar"] == ["yes"]
    models = list(summary["models"])
    assert models == ["initial", "initial_kinematic"]
    # one column per model; roll stiffness in N*m/deg; a figure a model lacks is a dash
    figures = [summary["models"][m]["axle"] for m in models]
    assert rows["roll stiffness (total) [N*m/deg]"] == [
        f"{a['roll_stiffness_Nmm_per_deg'] / 1000:.1f}" for a in figures]
    assert rows["roll centre height (kinematic) [mm]"] == [
        f"{a['roll_centre_height_mm']:.1f}" for a in figures]
    assert figures[1]["roll_centre_height_force_based_mm"] is None
    assert rows["roll centre height (force-based) [mm]"] == [
        f"{figures[0]['roll_centre_height_force_based_mm']:.1f}", "\u2013"]
    assert rows["percent Ackermann at the left lock [%]"] == [
        f"{a['percent_ackermann_lock']:.1f}" for a in figures]
    assert rows["steering ratio (on centre) [deg/deg]"] == ["\u2013", "\u2013"]
    # every axle figure that is a number (or none) has its row; the matrix has none
    scalar = [k for k, v in figures[0].items() if not isinstance(v, (dict, list))]
    labels = {f"{c.label} [{display_unit(c.unit)[0]}]" for c in AXLE_CHARACTERISTIC_LIST}
    assert len(scalar) == len(AXLE_CHARACTERISTIC_LIST) and labels <= set(rows)
    html = (axle_results / "report.html").read_text()
    assert "compliance_matrix_12x12" not in html
    assert "Named compliances" in html and "anti-phase" in html
    # the per-wheel figures, left and right
    header = next(c for c in axle_page.cells if c[:2] == ["characteristic", "initial left"])
    assert header == ["characteristic", "initial left", "initial right",
                      "initial_kinematic left", "initial_kinematic right"]
    start = axle_page.cells.index(header)
    wheel = {c[0]: c[1:] for c in axle_page.cells[start + 1:start + 1 + len(CHARACTERISTIC_LIST)]}
    initial = summary["models"]["initial"]
    assert wheel["bump camber [deg/m]"][:2] == [f"{initial['bump_camber_deg_per_m']:.3f}",
                                                f"{initial['right']['bump_camber_deg_per_m']:.3f}"]
    assert wheel["wheel rate [N/mm]"] == ["\u2013"] * 4  # no vertical force case run


def test_axle_charts_in_the_axle_section_with_captions(axle_page, axle_results):
    ids = [f["id"].removeprefix("chart-") for f in axle_page.figures]
    assert ids == ["steer_vs_travel", "camber_vs_travel", "wheel_centre_lateral_vs_travel",
                   "toe_vs_roll_angle", "camber_vs_roll_angle", "roll_moment_vs_roll_angle",
                   "steer_vs_steering_wheel_angle", "roll_centre_height_vs_travel",
                   "largest_loads"]
    assert all((axle_results / f"{i}.png").exists() for i in ids)
    captions = {f["id"].removeprefix("chart-"): f["caption"] for f in axle_page.figures}
    assert captions["toe_vs_roll_angle"].startswith("Chart 4. Toe vs roll angle")
    assert "100 % Ackermann" in captions["steer_vs_steering_wheel_angle"]
    assert "kinematic roll centre" in captions["roll_centre_height_vs_travel"]
    assert "roll stiffness" in captions["roll_moment_vs_roll_angle"]
    html = (axle_results / "report.html").read_text()
    assert html.index('id="axle"') < html.index('id="chart-toe_vs_roll_angle"')


def test_axle_section_of_the_case_study(page, results):
    summary = json.loads((results / "summary.json").read_text())
    assert summary["axle"]["vehicle"] is None and not summary["axle"]["steering"]
    rows = _rows(page)
    assert rows["vehicle data"][0].startswith("none (axle.vehicle)")
    identified = summary["models"]["identified"]["axle"]
    assert rows["roll centre height (force-based) [mm]"][1] == (
        f"{identified['roll_centre_height_force_based_mm']:.1f}")
    # the per-wheel table: the test has both wheels (the synthetic real axle's)
    start = next(k for k, c in enumerate(page.cells) if c[:2] == ["characteristic",
                                                                  "test left"])
    wheel = {c[0]: c[1:] for c in page.cells[start + 1:start + 1 + len(CHARACTERISTIC_LIST)]}
    test_left = summary["models"]["test"]["steer_amplitude_deg"]
    initial = summary["models"]["initial"]
    assert wheel["steer amplitude over the travel stroke [deg]"] == [
        f"{test_left:.4f}",
        f"{summary['models']['test']['right']['steer_amplitude_deg']:.4f}",
        f"{initial['steer_amplitude_deg']:.4f}",
        f"{initial['right']['steer_amplitude_deg']:.4f}",
        *(f"{w['steer_amplitude_deg']:.4f}" for w in (summary["models"]["identified"],
                                                      summary["models"]["identified"]["right"]))]
    assert "chart-roll_centre_height_vs_travel" in [f["id"] for f in page.figures]


def test_no_axle_section_for_a_corner(tmp_path):
    out = run_kc(tmp_path / "corner", CORNER, RIG)
    summary = json.loads((out / "summary.json").read_text())
    assert "axle" not in summary
    corner = Page((out / "report.html").read_text())
    assert "axle" not in [s[0] for s in corner.sections]
    assert not list(out.glob("roll_*.png")) and (out / "steer_vs_travel.png").exists()


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


def test_axle_report_rendered_in_headless_chromium(axle_results, tmp_path):
    """The axle's page as a browser builds it: the axle section with its tables and its
    charts, every chart image decoded (a broken image has no natural width)."""
    chromium = _chromium()
    url = (axle_results / "report.html").resolve().as_uri()
    run = [chromium, *CHROMIUM_FLAGS, f"--user-data-dir={tmp_path / 'profile'}"]
    dom = subprocess.run([*run, "--dump-dom", url], capture_output=True, text=True,
                         timeout=120, check=True).stdout
    rendered = Page(dom)
    assert "axle" in [s[0] for s in rendered.sections]
    assert [f["id"] for f in rendered.figures] == [f["id"] for f in Page(
        (axle_results / "report.html").read_text()).figures]
    assert "roll stiffness (total) [N*m/deg]" in " ".join(t for _, t in rendered.rows)
