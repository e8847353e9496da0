"""The README's pictures of the shipped configs: for every config in configs/ (``*.yaml``),
``elastokin view`` at the design position (nothing solved), drawn in headless Chromium and
saved as ``docs/pictures/<config name>.png`` (the 3D scene alone: no legend, no colour bar, no
buttons; the view's own "3D" camera). A config added to configs/ gets its picture from
running this again:

    python docs/make_pictures.py            # every config
    python docs/make_pictures.py NAME ...   # only these (config names without .yaml)

Needs Chromium (``apt-get install chromium``).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # tests/browser.py: headless Chromium over a pipe

#: the picture's size (px)
WIDTH, HEIGHT = 960, 560
#: the scene alone: every legend, colour bar, button and the mode bar off, the scene over
#: the whole plot, seen a little closer than the view's "3D" camera
BARE = """(function(){var gd=document.getElementById('ekv-plot'), bars=[], loose=[];
gd.data.forEach(function(t,k){if(t.marker&&t.marker.colorbar){bars.push(k);}
if(t.name==='other hardpoints'){loose.push(k);}});
var eye=gd.layout.scene.camera.eye, c=ZOOM;
document.querySelectorAll('.modebar').forEach(function(m){m.style.display='none';});
function some(ks,update){return ks.length?Plotly.restyle(gd,update,ks):Promise.resolve();}
return some(bars,{'marker.showscale':false}).then(function(){
return some(loose,{visible:false});}).then(function(){
return Plotly.relayout(gd,{showlegend:false,updatemenus:[],'scene.domain.x':[0,1],
'scene.domain.y':[0,1],width:WIDTH,height:HEIGHT,'scene.camera.eye':{x:c*eye.x,y:c*eye.y,z:c*eye.z}});
}).then(function(){return 1;});})()""".replace("ZOOM", "0.8").replace(
    "WIDTH", str(WIDTH)).replace("HEIGHT", str(HEIGHT))


def picture(config: Path, out: Path, browser) -> Path:
    """The picture of one config (its view page made in a temporary folder)."""
    from elastokin.cli.view import design_view
    from elastokin.config.draft import draft_suspension
    from elastokin.report.view3d import write_view_page

    draft = draft_suspension(config)
    if draft.errors:
        raise SystemExit(f"{config}: {len(draft.errors)} errors: {draft.errors[0]}")
    with tempfile.TemporaryDirectory() as tmp:
        page = write_view_page(Path(tmp) / "view.html", draft.name, [design_view(draft)],
                               [], [])
        browser.open(page.resolve().as_uri())
        browser.wait_for("document.getElementById('ekv-plot').getAttribute('data-ready')"
                         " === '1'")
        browser.run(BARE)
        browser.settle()
        time.sleep(0.3)
        box = browser.run("(function(){var r=document.getElementById('ekv-plot')"
                          ".getBoundingClientRect();return [r.left+window.scrollX,"
                          "r.top+window.scrollY];})()")
        img = browser.screenshot({"x": box[0], "y": box[1], "width": WIDTH, "height": HEIGHT})
    from PIL import Image

    out.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(img).quantize(colors=192).save(out, optimize=True)
    return out


def main() -> None:
    from elastokin.config.vehicle import is_vehicle_file
    from tests.browser import Browser

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", help="config names (default: every config)")
    ap.add_argument("--out", default=str(ROOT / "docs" / "pictures"))
    args = ap.parse_args()
    configs = [c for c in sorted((ROOT / "configs").glob("*.yaml"))
               if not is_vehicle_file(c)]  # a vehicle file names two axles: no picture
    if args.names:
        configs = [c for c in configs if c.stem in args.names]
    with Browser(WIDTH + 400, HEIGHT + 400, offline=True) as browser:
        for config in configs:
            out = picture(config, Path(args.out) / f"{config.stem}.png", browser)
            print(f"{config.relative_to(ROOT)} -> {out.relative_to(ROOT)}")
        if browser.errors:
            raise SystemExit(f"the pages logged errors: {browser.errors}")


if __name__ == "__main__":
    main()
