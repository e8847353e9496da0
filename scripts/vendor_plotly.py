"""Vendor plotly.js's official gl3d partial bundle (npm package ``plotly.js-gl3d-dist-min``:
the trace types scatter, scatter3d, mesh3d, cone, surface, isosurface, volume, streamtube,
and plotly's core: layout, legend, buttons) into ``elastokin/report/vendor/``, where the 3D
view embeds it (1.75 MB where plotly's full bundle is 4.8 MB, for the same view).

    python scripts/vendor_plotly.py                 # the plotly.js version of the installed
                                                    # plotly Python package (the tests check
                                                    # figures against its schema)
    python scripts/vendor_plotly.py --version 4.2.0

Runs ``npm pack`` (npm, the registry's own client, verifies the tarball's integrity), then
writes ``plotly-gl3d.min.js``, the package's ``LICENSE`` (MIT) as ``LICENSE-plotly.js.txt``,
and ``plotly-gl3d.json``: the package, version, tarball integrity (sha512, as the registry
publishes it) and the SHA-256 and size of the file, which ``tests/test_view.py`` checks the
shipped file against. Commit the three files, then run the tests and ``python
docs/make_pictures.py``.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import re
import shutil
import subprocess
import tarfile
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VENDOR = ROOT / "elastokin" / "report" / "vendor"
PACKAGE = "plotly.js-gl3d-dist-min"
BUNDLE = "plotly-gl3d.min.js"


def plotly_python_js_version() -> str:
    """The plotly.js version bundled with the installed plotly Python package."""
    from plotly.offline import get_plotlyjs

    return re.search(r"plotly\.js v(\d+\.\d+\.\d+)", get_plotlyjs()[:300]).group(1)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--version", default=None,
                    help="plotly.js version (default: the installed plotly Python package's)")
    args = ap.parse_args()
    version = args.version or plotly_python_js_version()
    npm = shutil.which("npm")
    if npm is None:
        raise SystemExit("npm is needed (apt-get install npm)")
    with tempfile.TemporaryDirectory() as tmp:
        done = subprocess.run([npm, "pack", f"{PACKAGE}@{version}", "--json",
                               "--pack-destination", tmp], capture_output=True, text=True,
                              check=True, timeout=600)
        (info,) = json.loads(done.stdout)
        with tarfile.open(Path(tmp) / info["filename"]) as tar:
            bundle = tar.extractfile(f"package/{BUNDLE}").read()
            licence = tar.extractfile("package/LICENSE").read()
    header = bundle[:200].decode("utf-8")
    if f"v{version}" not in header or "gl3d" not in header:
        raise SystemExit(f"{PACKAGE}@{version}: unexpected bundle header {header!r}")
    VENDOR.mkdir(parents=True, exist_ok=True)
    (VENDOR / BUNDLE).write_bytes(bundle)
    (VENDOR / "LICENSE-plotly.js.txt").write_bytes(licence)
    manifest = {"package": PACKAGE, "version": version, "file": BUNDLE,
                "tarball": f"https://registry.npmjs.org/{PACKAGE}/-/{info['filename']}",
                "tarball_integrity": info["integrity"], "bytes": len(bundle),
                "sha256": hashlib.sha256(bundle).hexdigest(), "license": "MIT"}
    (VENDOR / "plotly-gl3d.json").write_text(json.dumps(manifest, indent=2) + "\n")
    print(f"{PACKAGE}@{version}: {len(bundle)} bytes -> {VENDOR.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
