"""Batch reports: every kind of folder, embedded images, well-formed markup, and the
pages in a real headless browser; the main job (reduced) produces the report."""

import base64
import re
import subprocess
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from taxel.reports.build import CHROMIUM_FLAGS, build, chromium
from taxel.cli import main


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    """The README's main job at a reduced size, plus a static solve folder."""
    root = tmp_path_factory.mktemp("demo")
    assert main(["demo", "--small", "--out", str(root)]) == 0
    assert main(["solve", "thesis-pzt-single-2d", "--out", str(root / "static")]) == 0
    return root


def test_main_job_writes_a_report_for_every_folder_kind(demo):
    index = demo / "report" / "index.html"
    assert index.exists()
    pages = {p.stem for p in (demo / "report").glob("*.html")} - {"index"}
    assert pages == {"fig-2-5", "thesis-pzt-front", "thesis-pzt-frequency", "thesis-pzt-step", "validation"}
    text = (demo / "report" / "validation.html").read_text()
    for section in ("Summary beside the thesis", "Step responses", "Frequency response", "Linearity and repeatability",
                    "Localization", "Provenance"):
        assert f"<h2>{section}</h2>" in text
    assert "1.7" in text and "9.75" in text and "95.65 / 96.63" in text
    idx = build([demo / "static", demo / "fig-2-5"], demo / "report2", compare=True)
    text = (demo / "report2" / "static.html").read_text()
    assert "Model comparison" in text and "lumped 3-DoF" in text and "3D" in text
    assert idx.exists()


def pages(demo):
    return sorted((demo / "report").glob("*.html")) + sorted((demo / "report2").glob("*.html"))


def test_pages_are_well_formed_and_images_embedded_and_non_empty(demo):
    for page in pages(demo):
        text = page.read_text(encoding="utf-8")
        ET.fromstring(text.split("\n", 2)[2])                        # XHTML: well-formed XML
        assert "http://" not in text.replace("http://www.w3.org/1999/xhtml", "")      # nothing to fetch
        srcs = re.findall(r'src="([^"]+)"', text)
        for src in srcs:
            assert src.startswith("data:image/png;base64,"), src[:40]
            data = base64.b64decode(src.split(",", 1)[1])
            assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 1000
        if page.stem != "index":
            assert len(srcs) >= 2 and "Provenance" in text


def test_study_page_has_the_parameter_curves_scene_and_renders(demo):
    text = (demo / "report" / "fig-2-5.html").read_text()
    for section in ("Parameter study", "Results", "Scene", "Fields", "Solver", "Provenance"):
        assert f"<h2>{section}</h2>" in text
    assert "3D render unavailable" not in text                     # the pyvista render is there


def test_not_a_result_folder_is_a_clear_error(tmp_path, capsys):
    assert main(["report", str(tmp_path), "--out", str(tmp_path / "r")]) == 2
    assert "not a study, optimization or solve folder" in capsys.readouterr().err


@pytest.mark.skipif(chromium() is None, reason="Chromium is not installed (CI installs it)")
def test_pages_open_in_headless_chromium_without_errors_and_are_not_blank(demo):
    import matplotlib.image as mpimg
    for page in (demo / "report" / "index.html", demo / "report" / "fig-2-5.html"):
        with tempfile.TemporaryDirectory() as profile:
            shot = Path(profile) / "shot.png"
            run = subprocess.run([chromium(), *CHROMIUM_FLAGS, f"--user-data-dir={profile}",
                                  "--enable-logging=stderr", "--v=0", "--window-size=1200,1600",
                                  f"--screenshot={shot}", page.resolve().as_uri()],
                                 capture_output=True, text=True, timeout=120)
            assert shot.exists(), run.stderr[-500:]
            console = [line for line in run.stderr.splitlines() if "CONSOLE" in line or "Failed to load" in line]
            assert not console, console
            img = mpimg.imread(shot)
            assert img.std() > 0.02                                   # not blank
    dom = subprocess.run([chromium(), *CHROMIUM_FLAGS, "--user-data-dir=" + tempfile.mkdtemp(), "--dump-dom",
                          (demo / "report" / "fig-2-5.html").resolve().as_uri()],
                         capture_output=True, text=True, timeout=120).stdout
    assert "fig-2-5 (study)" in dom and dom.count("<img") >= 4


@pytest.mark.skipif(chromium() is None, reason="Chromium is not installed (CI installs it)")
def test_pdf_option(demo, tmp_path):
    build([demo / "thesis-pzt-step"], tmp_path / "r", pdf=True, compare=False)
    pdf = tmp_path / "r" / "thesis-pzt-step.pdf"
    assert pdf.read_bytes()[:4] == b"%PDF" and pdf.stat().st_size > 10000


def test_offscreen_render_is_silent_on_a_headless_machine():
    """pyvista renders through EGL without a display and prints no X-server warning."""
    import os
    import subprocess
    import sys
    code = ("import taxel; from taxel.reports.figures import pyvista_render; "
            "png = pyvista_render(taxel.solve('thesis-pzt-single-2d')); assert png[:4] == b'\\x89PNG'")
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 0, run.stderr[-2000:]
    assert "X server" not in run.stderr and "WARN" not in run.stderr, run.stderr[-2000:]
