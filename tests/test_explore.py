"""The design explorer (taxel explore) driven from headless Chromium.

The app runs as `taxel explore` in a subprocess on a free port; Chromium is
driven over the DevTools protocol with real key presses. Waits are event-driven
(the page's text is polled) with generous limits: the first page load imports
the FEM and trame on a possibly loaded 2-core machine.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from taxel.explore.browser import chromium_path
from waits import CEILING

pytestmark = pytest.mark.skipif(chromium_path() is None,
                                reason="no Chromium here (Debian's chromium package; .ci/run installs it)")

SCENE = "thesis-pzt-single-2d"


def cli(*args, check=True):
    return subprocess.run([sys.executable, "-m", "taxel.cli", *args], capture_output=True, text=True,
                          check=check, env={"MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
                                            "PATH": "/usr/bin:/bin"})


def scene_file(tmp: Path, name: str, **array) -> Path:
    """The built-in scene with [array] values replaced, as a TOML file for `taxel solve`."""
    from taxel.scene import EXAMPLES
    text = (EXAMPLES / f"{SCENE}.toml").read_text()
    for key, value in array.items():
        lines = [f'{key} = "{value}"' if ln.startswith(f"{key} =") else ln for ln in text.splitlines()]
        text = "\n".join(lines) + "\n"
    path = tmp / f"{name}.toml"
    path.write_text(text)
    return path


THUMB = "document.getElementById('slider_{0}').closest('.v-slider').querySelector('[role=slider]')"
TEXT = "(document.getElementById('{0}') || {{textContent: ''}}).textContent.trim()"


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    from taxel.explore.browser import Browser, ExplorerProcess
    out = tmp_path_factory.mktemp("explore")
    with ExplorerProcess(SCENE, out, limit=CEILING) as app, Browser(timeout=CEILING) as b:
        b.goto(app.url)
        b.wait(TEXT.format("voltage"), CEILING, "the first voltage")
        yield b, out


def test_slider_gives_the_voltage_of_taxel_solve(page, tmp_path):
    b, _ = page
    from taxel.units import engineering
    first = b.js(TEXT.format("voltage"))
    rec = json.loads(cli("solve", str(scene_file(tmp_path, "s", silicone_above="1 mm")), "--json").stdout)
    assert first == engineering(rec["electrodes"]["taxel_0_0"]["voltage_V"], "V")
    rec = json.loads(cli("solve", str(scene_file(tmp_path, "thin", silicone_above="0.8 mm")), "--json").stdout)
    expected = engineering(rec["electrodes"]["taxel_0_0"]["voltage_V"], "V")
    assert expected != first
    b.js(THUMB.format("silicone_above") + ".focus()")
    for _ in range(4):                                   # 1 mm -> 0.8 mm in steps of 0.05 mm
        b.key("ArrowLeft", "ArrowLeft", 37)
    assert b.wait("document.getElementById('field_silicone_above').value", CEILING) == "0.80"
    shown = b.wait(f"(() => {{ const t = {TEXT.format('voltage')}; return t === {json.dumps(expected)} && t; }})()",
                   CEILING, f"the voltage of taxel solve ({expected}); shown: {b.js(TEXT.format('voltage'))}")
    assert shown == expected
    assert "2D (plane strain)" in b.js(TEXT.format("answer_model"))


def test_bad_value_shows_the_cli_message(page, tmp_path):
    b, _ = page
    r = cli("solve", str(scene_file(tmp_path, "bad", silicone_below="-1 mm")), check=False)
    assert r.returncode == 2
    message = r.stderr.strip().removeprefix("taxel: error: ")
    assert message.startswith("array.silicone_below")
    b.type_into("#field_silicone_below", "-1")
    shown = b.wait("(() => { const m = document.getElementById('field_silicone_below').closest('.v-input')"
                   ".querySelector('.v-messages'); return m && m.textContent.trim(); })()", 60,
                   "the message beside the field")
    assert shown == message
    b.type_into("#field_silicone_below", "1")            # back to a valid design
    b.wait("(() => { const m = document.getElementById('field_silicone_below').closest('.v-input')"
           ".querySelector('.v-messages'); return m && m.textContent.trim() === ''; })()", 60)


def test_3d_shows_progress_and_a_result(page, tmp_path):
    b, out = page
    from taxel.units import to_si
    before = b.js(TEXT.format("voltage"))
    b.js("document.getElementById('solve3d').click()")
    progress = b.wait(f"(() => {{ const t = {TEXT.format('progress3d')}; return t.includes('3D solve') && t; }})()",
                      CEILING, "3D progress")
    assert "3D solve" in progress
    text = b.wait(TEXT.format("answer3d"), CEILING, "the 3D answer")
    assert text.startswith("3D: ") and "coarse mesh" in text, text
    v3d = to_si(text.split()[1] + " " + text.split()[2].rstrip("(").strip(), "V", "voltage")
    v2d = to_si(before, "V", "voltage")
    # a single square taxel under uniform pressure: plane strain and coarse 3D agree to a few per cent
    assert abs(v3d - v2d) < 0.05 * abs(v2d), (text, before)
    shot = b.screenshot(tmp_path / "explore.png")
    print(f"screenshot: {shot}")
    assert shot.stat().st_size > 10_000


def test_export_writes_the_shown_design(page):
    b, out = page
    import taxel
    from taxel.units import engineering
    b.js("document.getElementById('export').click()")
    msg = b.wait(TEXT.format("export_msg"), CEILING, "the export message")
    assert msg.startswith("wrote "), msg
    path = Path(msg.removeprefix("wrote "))
    assert path.parent == (out / "exports").resolve()
    saved = taxel.load(path)
    assert saved.array.silicone_above == pytest.approx(0.8e-3)
    rec = json.loads(cli("solve", str(path), "--json").stdout)
    assert engineering(rec["electrodes"]["taxel_0_0"]["voltage_V"], "V") == b.js(TEXT.format("voltage"))


FRONT_SPEC = """
base = "thesis-pzt-3x3-2d"
reference = {gap = "3 mm"}
[variables]
gap = {path = "array.gap", min = "1 mm", max = "5 mm", start = "3 mm"}
[objective]
maximize = "sensitivity"
[requirements]
total_thickness = "<= 2.2 mm"
[pareto]
points = 2
[algorithm]
global = "none"
local = "COBYLA"
max_evaluations = 6
"""


@pytest.fixture(scope="module")
def front_page(tmp_path_factory):
    """A two-point front of the 2D 3x3 array (the gap), then the explorer on its folder."""
    import taxel
    from taxel.explore.browser import Browser, ExplorerProcess
    tmp = tmp_path_factory.mktemp("front")
    (tmp / "front.toml").write_text(FRONT_SPEC)
    result = taxel.run_optimization(tmp / "front.toml", tmp / "front", workers=1)
    with ExplorerProcess(str(tmp / "front"), tmp / "app", limit=CEILING) as app, Browser(timeout=CEILING) as b:
        b.goto(app.url)
        b.wait(TEXT.format("voltage"), CEILING, "the first voltage")
        yield b, tmp, result


def test_front_is_shown_and_a_click_loads_its_design(front_page):
    b, tmp, result = front_page
    from taxel.explore.front import Front
    front = Front.of(tmp / "front")
    assert len(front.designs) == len(result.front_rows) >= 1
    rows = b.wait("(() => { const r = [...document.querySelectorAll('#front_table tr')]; "
                  "return r.length && r.map(x => x.textContent); })()", CEILING, "the front's table")
    assert len(rows) == len(front.designs)
    for row, d in zip(rows, front.designs):
        assert f"{d.sensitivity:.4g} V/N" in row and f"{100 * d.crosstalk:.2f} %" in row
    assert b.wait("document.getElementById('front_image').src.startsWith('data:image/png') && "
                  "document.getElementById('front_image').src", CEILING, "the front plot").startswith("data:")
    # move the gap away from every front design, then click the last front design
    gaps = [d.values["gap"] for d in front.designs]
    away = next(g for g in (4.7, 4.3, 1.3) if all(abs(g - x) > 0.05 for x in gaps))
    b.type_into("#field_gap", str(away))
    b.wait(f"document.getElementById('field_gap').value === '{away}'", CEILING)
    d = front.designs[-1]
    b.js(f"document.getElementById('front_row_{len(front.designs) - 1}').click()")
    shown = b.wait(f"(() => {{ const v = document.getElementById('field_gap').value; "
                   f"return v !== '{away}' && v; }})()", CEILING, "the front design's gap")
    assert float(shown) == pytest.approx(d.values["gap"], rel=1e-5)
    # the live answer of the loaded design is the stored front point, to display precision
    expected = f"{100 * d.crosstalk:.1f} %"
    b.wait(f"{TEXT.format('crosstalk')} === 'crosstalk: {expected}'", CEILING,
           f"the front design's crosstalk {expected}; shown: {b.js(TEXT.format('crosstalk'))}")
    star = f"current design (the star): {d.sensitivity:.4g} V/N, {100 * d.crosstalk:.2f} %"
    b.wait(f"{TEXT.format('front_current')} === {json.dumps(star)}", CEILING,
           f"the moving point at the front design ({star}); shown: {b.js(TEXT.format('front_current'))}")
    print(f"screenshot: {b.screenshot(tmp / 'explore-front.png')}")


def test_send_to_optimization_writes_a_loadable_spec(front_page):
    b, tmp, result = front_page
    from taxel.optimize.spec import load_optimization
    b.js("document.getElementById('send').click()")
    msg = b.wait(f"(() => {{ const t = {TEXT.format('send_msg')}; return t.startsWith('wrote ') && t; }})()",
                 CEILING, "the send message")
    path = Path(msg.removeprefix("wrote "))
    assert path.parent == (tmp / "app" / "exports").resolve() and path.suffix == ".toml"
    problem = load_optimization(path)
    gap = float(b.js("document.getElementById('field_gap').value"))
    assert problem.names == ["gap"] and problem.x0[0] == pytest.approx(gap, rel=1e-5)
    assert problem.spec.pareto.points == 2 and problem.constraints[0][0] == "total_thickness"
