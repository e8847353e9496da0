"""The README teaches what the code does: the tutorial's YAML blocks are the shipped double
wishbone axle config, its commands print what the README shows, its Python block prints what
the README shows, every shipped config, rig file and example is named, and every link to a
section lands on a heading."""

from __future__ import annotations

import contextlib
import io
import re
import shlex
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli.main import main

ROOT = Path(__file__).parents[1]
README = (ROOT / "README.md").read_text()
TUTORIAL_TITLE = "## Tutorial: your own suspension, step by step"


def section(title: str) -> str:
    start = README.index(title)
    end = README.find("\n## ", start + len(title))
    return README[start:end if end > 0 else None]


def blocks(text: str) -> list[tuple[str, str]]:
    """(language, content) of every fenced block, in order."""
    return re.findall(r"```(\w+)\n(.*?)```", text, re.S)


TUTORIAL = section(TUTORIAL_TITLE)


def test_tutorial_yaml_blocks_are_the_shipped_config():
    """Put together, the tutorial's YAML blocks are configs/double_wishbone_axle.yaml (its
    data: the file's comments cite the sources), each top-level key in one block only."""
    merged: dict = {}
    for lang, text in blocks(TUTORIAL):
        if lang != "yaml":
            continue
        data = yaml.safe_load(text)
        assert not set(data) & set(merged), set(data) & set(merged)
        merged.update(data)
    shipped = yaml.safe_load((ROOT / "configs" / "double_wishbone_axle.yaml").read_text())
    assert merged == shipped


def _expected_lines(text: str) -> list[str]:
    return [ln.rstrip() for ln in text.splitlines() if ln.strip() and "..." not in ln]


def test_tutorial_commands_and_python_print_what_the_readme_shows(tmp_path, monkeypatch):
    """Every `$ elastokin ...` of the tutorial, run in a fresh folder beside the shipped
    configs, prints every line the README shows after it; the Python block then prints the
    lines of the console block that follows it."""
    (tmp_path / "configs").symlink_to(ROOT / "configs")
    monkeypatch.chdir(tmp_path)
    printed = None
    ran = 0
    for lang, text in blocks(TUTORIAL):
        if lang == "console" and text.startswith("$ elastokin"):
            command, _, shown = text.partition("\n")
            result = CliRunner().invoke(main, shlex.split(command)[2:])
            assert result.exit_code == 0, result.output
            got = [ln.rstrip() for ln in result.output.splitlines()]
            for line in _expected_lines(shown):
                assert line in got, f"README line not printed by {command!r}:\n{line}"
            ran += 1
        elif lang == "python":
            out = io.StringIO()
            with contextlib.redirect_stdout(out):
                exec(compile(text, "README tutorial", "exec"), {})
            printed = [ln.rstrip() for ln in out.getvalue().splitlines()]
        elif lang == "console" and printed is not None:
            assert _expected_lines(text) == printed
            printed = None
            ran += 1
    assert ran == 2


def test_the_error_the_tutorial_shows(tmp_path, monkeypatch):
    """The tutorial's example of a bad config: the message it quotes, word for word."""
    quoted = re.search(r"for example \(the spring's rate misspelt\):\n`(.*?)`", TUTORIAL, re.S)
    message = " ".join(quoted.group(1).split())
    (tmp_path / "configs").mkdir()
    text = (ROOT / "configs" / "double_wishbone_axle.yaml").read_text()
    bad = tmp_path / "configs" / "double_wishbone_axle.yaml"
    bad.write_text(text.replace("rate_N_per_mm: 167.062", "rate_N_per_m: 167.062"))
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, ["kc", "--config", "configs/double_wishbone_axle.yaml"])
    assert result.exit_code == 1
    assert message in " ".join(result.output.split())


@pytest.mark.parametrize("path", sorted(
    p.relative_to(ROOT).as_posix() for p in [*ROOT.glob("configs/*.yaml"),
                                             *ROOT.glob("configs/rigs/*.yaml"),
                                             *ROOT.glob("examples/*.py")]))
def test_every_shipped_config_rig_and_example_is_named(path):
    assert f"`{path}`" in README


def _slug(heading: str) -> str:
    """GitHub's anchor of a heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def test_every_section_link_lands_on_a_heading():
    anchors = {_slug(h) for h in re.findall(r"^#+ (.*)$", README, re.M)}
    links = set(re.findall(r"\]\(#([^)]+)\)", README))
    assert links and links <= anchors, sorted(links - anchors)


@pytest.mark.slow
def test_case_study_console_shows_what_kc_prints(case_kc):
    """The case study's console excerpt is the table `elastokin kc` prints for the shipped
    run (rebuilt from its summary.json; the first line names the config as given)."""
    import json

    from elastokin.report.text import kc_table

    summary = json.loads((case_kc / "summary.json").read_text())
    printed = [ln.rstrip() for ln in kc_table(summary, case_kc).splitlines()]
    (text,) = [t for lang, t in blocks(section("## The case study")) if lang == "console"
               and t.startswith("$ elastokin kc --config configs/pseudo_mcpherson.yaml")]
    for line in _expected_lines(text.partition("\n")[2]):
        if not line.startswith("elastokin "):
            assert line in printed, line
