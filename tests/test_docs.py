"""The documentation site: its key reference matches the schemas, `taxel schema`
prints them, and the site builds (warnings are errors, the gallery runs) with no
missing image and no broken internal link; its index and one gallery page open in
headless Chromium (screenshots kept under the test's tmp dir)."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
import tempfile
import typing
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest
from waits import CEILING
from pydantic import BaseModel

from taxel.cli import main
from taxel.cli.schema import KINDS, json_schema, markdown, model

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def _models_in(tp) -> list[tuple[str, type[BaseModel]]]:
    """Independent of the generator: the models an annotation holds, with how a
    path reaches into them (a table, an array of tables, a table keyed by name)."""
    if isinstance(tp, type) and issubclass(tp, BaseModel):
        return [("", tp)]
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if origin is list:
        return [("[]" + s, m) for s, m in _models_in(args[0])]
    if origin is dict:
        return [(".<name>" + s, m) for s, m in _models_in(args[1])]
    return [x for a in args for x in _models_in(a)]


def _all_paths(cls, prefix=""):
    for name, info in cls.model_fields.items():
        path = prefix + (info.alias or name)
        yield path
        for suffix, sub in _models_in(info.annotation):
            yield from _all_paths(sub, path + suffix + ".")


def _reference_keys(kind):
    return [m.group(1) for m in re.finditer(r"^\| `([^`]+)` \|", markdown(kind), re.M)]


@pytest.mark.parametrize("kind", list(KINDS))
def test_the_key_reference_lists_every_key_of_the_schema(kind):
    listed = _reference_keys(kind)
    assert len(listed) == len(set(listed)), "a key listed twice"
    assert set(listed) == set(_all_paths(model(kind)))
    if kind == "scene":            # nested tables and arrays of tables are walked
        assert {"model.type", "load.friction", "readout.C_f", "plate.layers[].thickness"} <= set(listed)


def test_the_scene_reference_carries_units_defaults_allowed_values_and_bounds():
    rows = {m.group(1): [c.strip() for c in m.group(2).split(" | ")]
            for m in re.finditer(r"^\| `([^`]+)` \| (.*) \|$", markdown("scene"), re.M)}
    # columns: type, unit, default, allowed, bounds, doc
    assert rows["array.silicone_above"][1:3] == ["m", '`"1 mm"`']
    assert rows["readout.R"][1] == "ohm" and rows["analysis.f_max"][1] == "Hz" and rows["load.force"][1] == "N"
    assert '"plane_strain" \\| "plane_stress" \\| "axisymmetric" \\| "3d"' == rows["model.type"][3]
    assert rows["mesh.piezo_layers"][4] == ">= 1, <= 8" and rows["model.tolerance"][4] == "> 0, < 1"
    assert rows["plate.layers"][2] == "required"
    assert "edge to edge" in rows["array.gap"][5]                  # the schema's own comment



def test_every_table_of_a_scene_has_an_example_under_the_reference_and_each_loads(tmp_path):
    """The key reference ends with one example per table (taxel.scene.KEY_EXAMPLES), the
    user materials included (a silicone: C10, C20, C30, K, rho; a piezo); each is a scene."""
    import tomllib
    import taxel
    from taxel.analyses import scene_materials
    from taxel.scene import KEY_EXAMPLES, Scene
    tables = {name for name, info in Scene.model_fields.items()
              if name not in ("name", "description")}
    covered = {title.split()[0] for title in KEY_EXAMPLES}
    assert tables == covered, f"tables without an example: {tables - covered}"
    page = markdown("scene")
    for title, text in KEY_EXAMPLES.items():
        assert f"### {title}" in page and text.strip() in page
        data = tomllib.loads(text)
        path = tmp_path / "example.toml"
        path.write_text(text if "array" in data or "plate" in data else text + "\n[array]\n")
        scene_materials(taxel.load(path))          # the materials are known and physical
    silicone = KEY_EXAMPLES["materials (a user silicone)"]
    assert all(k in silicone for k in ("C10", "C20", "C30", "K", "rho", 'kind = "solid"', "1000"))
    for kind in ("study", "optimization", "rig"):
        assert "## Examples" in markdown(kind)



def test_every_number_the_docs_read_from_a_benchmark_json_resolves():
    """docs/_ext/bench_json.py: each {bench} role names a value its JSON file holds and each
    bench-table a renderer; the press reference's table reproduces the script's numbers."""
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        import bench_json
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    roles, tables = [], []
    for page in DOCS.rglob("*.md"):
        if "_build" in page.parts:
            continue
        text = page.read_text(encoding="utf-8")
        roles += re.findall(r"\{bench\}`([^`]+)`", text)
        tables += re.findall(r"^```\{bench-table\} (\S+)", text, re.M)
    assert len(roles) >= 10 and {"reference_3d.single", "reference_3d.3x3", "press_3d_reference"} <= set(tables)
    for spec in roles:
        assert bench_json.value(spec), spec
    for name in tables:
        head, rows = bench_json.TABLES[name][1]()
        assert rows and all(len(r) == len(head) for r in rows), name
    assert bench_json.value("press_3d_reference.json:VF:.5f") == "-0.77981"
    assert bench_json.value("reference_3d.json:single.spread:.2%") == "0.66 %"


@pytest.mark.parametrize("kind", list(KINDS))
def test_the_key_reference_in_the_repository_is_current(kind):
    """docs/reference/keys/KIND.md is kept in the repository (the guide's links work from a
    clone) and is what the generator gives now (the docs build rewrites it)."""
    page = DOCS / "reference" / "keys" / f"{kind}.md"
    assert page.read_text(encoding="utf-8") == markdown(kind), (
        f"{page} is out of date: python -c \"from taxel.cli.schema import markdown; "
        f"open('{page.relative_to(ROOT)}', 'w').write(markdown('{kind}'))\"")


def test_every_scene_key_has_a_description_in_the_schema_and_the_command_prints_it(capsys):
    """Walks the scene schema: every key (nested tables, arrays of tables, the mesh's
    piezo_layers included) has a one-line description, is in the reference page, and
    `taxel schema scene` prints it with its unit and default."""
    from taxel.cli.schema import keys
    rows = keys("scene")
    assert set(r.path for r in rows) == set(_all_paths(model("scene")))
    missing = [r.path for r in rows if not r.doc or "\n" in r.doc]
    assert not missing, f"scene keys without a one-line description: {missing}"
    page = (DOCS / "reference" / "keys" / "scene.md").read_text(encoding="utf-8")
    assert all(f"`{r.path}`" in page for r in rows) and "`mesh.piezo_layers`" in page
    assert main(["schema", "scene"]) == 0
    out = capsys.readouterr().out
    for r in rows:
        assert f"{r.path}  (" in out and r.doc in out, r.path
    assert "mesh.piezo_layers  (integer; default 2; >= 1, <= 8)" in out
    assert "array.silicone_above  (number; unit m; default \"1 mm\")" in out
    description = model("scene").model_json_schema()["$defs"]["MeshTable"]["properties"]["piezo_layers"]
    assert description["description"].startswith("Elements through each piezo layer")


@pytest.mark.parametrize("kind", list(KINDS))
def test_taxel_schema_json_prints_the_json_schema(kind, capsys):
    assert main(["schema", kind, "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed == json.loads(json.dumps(json_schema(kind)))
    top = {(i.alias or n) for n, i in model(kind).model_fields.items()}
    assert set(printed["properties"]) == top and printed["additionalProperties"] is False


def test_taxel_schema_of_an_unknown_kind_is_one_line_and_exit_2(capsys):
    assert main(["schema", "sceen"]) == 2
    err = capsys.readouterr().err
    assert "invalid choice: 'sceen'" in err and len(err.strip().splitlines()) == 1


class _Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links, self.ids = [], [], set()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "img" and a.get("src"):
            self.images.append(a["src"])
        if tag in ("a", "link") and a.get("href"):
            self.links.append(a["href"])


def _parse(page: Path) -> _Links:
    p = _Links()
    p.feed(page.read_text(encoding="utf-8"))
    return p


def _broken(site: Path) -> list[str]:
    """Missing images and internal links (file or #anchor) of every page of the site."""
    broken, pages = [], {}
    for page in site.rglob("*.html"):
        pages[page] = _parse(page)
    for page, p in pages.items():
        for ref in p.images + p.links:
            url = urlsplit(ref)
            if url.scheme or ref.startswith("//") or ref.startswith("mailto:"):
                continue
            target = (page.parent / unquote(url.path)).resolve() if url.path else page
            if not target.exists():
                broken.append(f"{page.relative_to(site)}: {ref} (missing)")
            elif url.fragment and target.suffix == ".html":
                ids = pages[target].ids if target in pages else _parse(target).ids
                if url.fragment not in ids:
                    broken.append(f"{page.relative_to(site)}: {ref} (no such anchor)")
    return broken


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    pytest.importorskip("sphinx_gallery", reason="the docs extra is not installed (make setup installs it)")
    out = tmp_path_factory.mktemp("site") / "html"
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                          str(DOCS), str(out)], capture_output=True, text=True, cwd=ROOT, timeout=3 * CEILING)   # the whole site, gallery executed: 1-5 min here
    assert run.returncode == 0, (run.stdout + run.stderr)[-4000:]
    return out


@pytest.mark.slow
def test_the_site_builds_with_its_gallery_and_no_broken_link(site):
    gallery = sorted((site / "auto_gallery").glob("plot_*.html"))
    assert len(gallery) >= 10, [g.name for g in gallery]
    for page in gallery:                  # every example ran and made at least one figure
        images = [i for i in _parse(page).images if "sphx_glr_plot_" in i and not i.endswith("_thumb.png")]
        assert images, f"{page.name}: no figure"
    for kind in KINDS:
        text = (site / "reference" / "keys" / f"{kind}.html").read_text(encoding="utf-8")
        assert text.count("<tr") >= len(list(_all_paths(model(kind))))
    for page in ("getting-started", "glossary", "materials", "serial-protocol", "reference/api",
                 "verification", "benchmarks", "guide/scenes", "theory/contact"):
        assert (site / f"{page}.html").exists(), page
    assert "taxel.api.solve" in (site / "reference" / "api.html").read_text(encoding="utf-8")
    assert not _broken(site), _broken(site)[:20]


def _chromium():
    return shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.mark.slow
@pytest.mark.skipif(_chromium() is None, reason="Chromium is not installed (CI installs it: .ci/run)")
def test_index_and_a_gallery_page_open_in_headless_chromium(site, tmp_path):
    import matplotlib.image as mpimg
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
             "--disable-component-update", "--disable-sync"]
    for page in (site / "index.html", site / "auto_gallery" / "plot_taxel_2d.html"):
        shot = tmp_path / f"{page.stem}.png"
        with tempfile.TemporaryDirectory() as profile:
            run = subprocess.run([_chromium(), *flags, f"--user-data-dir={profile}", "--enable-logging=stderr",
                                  "--v=0", "--window-size=1200,1600", f"--screenshot={shot}", page.as_uri()],
                                 capture_output=True, text=True, timeout=CEILING)
        assert shot.exists(), run.stderr[-500:]
        failed = [line for line in run.stderr.splitlines() if "Failed to load" in line or "ERR_FILE_NOT_FOUND" in line]
        assert not failed, failed
        assert mpimg.imread(shot).std() > 0.02                    # not blank
        with tempfile.TemporaryDirectory() as profile:
            dom = subprocess.run([_chromium(), *flags, f"--user-data-dir={profile}", "--dump-dom", page.as_uri()],
                                 capture_output=True, text=True, timeout=CEILING).stdout
        for src in re.findall(r'<img[^>]+src="([^"]+)"', dom):   # every image the page shows is there
            if not urlsplit(src).scheme:
                assert (page.parent / unquote(src)).exists(), src
        assert dom.count("<img") >= 1


def test_the_study_optimization_and_rig_examples_cover_every_table_and_load(tmp_path):
    """Each key reference ends with whole example files that, together, use every top-level
    key of their schema, and each loads as its command would load it."""
    import importlib
    import tomllib
    from taxel.optimize.spec import load_optimization
    from taxel.studies.bench.rig import load_rig
    from taxel.studies.spec import load_study
    loaders = {"study": load_study, "optimization": load_optimization, "rig": load_rig}
    for kind, loader in loaders.items():
        cls = model(kind)
        examples = importlib.import_module(cls.__module__).KEY_EXAMPLES
        used = set()
        for i, text in enumerate(examples.values()):
            used |= set(tomllib.loads(text))
            path = tmp_path / f"{kind}-{i}.toml"
            path.write_text(text)
            loader(path)
        optional = {"name", "description", "samples", "seed", "sampling"}
        assert set(cls.model_fields) - optional <= used, (kind, set(cls.model_fields) - optional - used)
