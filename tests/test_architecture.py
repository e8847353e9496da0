"""The house rules of the package, checked from its source (README "Architecture"): layer
folders along the data flow, a module importing only its own or lower layers; Exudyn,
matplotlib and dask each imported in one layer; the report layer importable without Exudyn."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "elastokin"
#: lowest first; a module may import from its own layer and the layers before it
LAYERS = ("errors", "version", "physics", "config", "mbs", "rig", "formats", "identification",
          "synthetic", "studies", "report", "cli")
THIRD_PARTY = {"exudyn": "mbs", "matplotlib": "report", "plotly": "report", "dask": "studies",
               "distributed": "studies"}


def layer_of(module: str) -> str | None:
    """The layer of ``elastokin.<layer>[...]`` (None for the package itself)."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else None


def imports():
    """(importing module, imported module) for every import in the package, function-level
    and type-checking imports included."""
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE.parent).with_suffix("")
        module = ".".join(p for p in rel.parts if p != "__init__")
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                yield module, node.module
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    yield module, alias.name


EDGES = sorted(set(imports()))


def test_no_module_imports_a_higher_layer():
    inside = [(m, t) for m, t in EDGES if t.startswith("elastokin") and layer_of(m)]
    assert len(inside) > 100  # the check sees the package's imports
    wrong = [f"{m} imports {t}" for m, t in inside
             if layer_of(t) is None or LAYERS.index(layer_of(t)) > LAYERS.index(layer_of(m))]
    assert not wrong, wrong


def test_third_party_layers():
    for module, target in EDGES:
        top = target.split(".")[0]
        if top in THIRD_PARTY:
            assert layer_of(module) == THIRD_PARTY[top], f"{module} imports {target}"


def test_every_module_is_in_a_layer():
    for path in PACKAGE.rglob("*.py"):
        rel = path.relative_to(PACKAGE)
        name = rel.parts[0].removesuffix(".py")
        assert name in LAYERS or name == "__init__", path


def test_report_and_api_import_without_exudyn():
    code = ("import sys, elastokin, elastokin.report.files, elastokin.report.html.page, "
            "elastokin.report.charts, elastokin.rig.channels; "
            "print('exudyn' in sys.modules, 'matplotlib' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split()
    assert out == ["False", "False"]


def test_public_api_names_resolve():
    import elastokin

    for name in elastokin.__all__:
        assert getattr(elastokin, name) is not None, name
    with pytest.raises(AttributeError):
        elastokin.no_such_name  # noqa: B018
