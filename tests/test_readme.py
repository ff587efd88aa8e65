"""The README and the docs pages it points to cannot drift: every code block in
them runs here (the README's sections moved into the site keep their blocks, in
PAGES).

- ```python blocks are executed (their own asserts hold);
- ```sh blocks: every `taxel ...` line runs as a command and must exit 0; the
  set-up commands (`make demo`, `make test`, `make test-all`) run as `make -n` (their recipes
  resolve: running them here would run this suite inside itself, and the main job
  has its own test in test_reports.py);
- ```toml blocks are scenes: they load, materials included.
Outputs go to out/readme-* (ignored by git), as the README says.
"""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import taxel
from waits import CEILING

ROOT = Path(__file__).resolve().parents[1]
# The README and the pages holding the blocks that moved out of it (a page added here has
# its ```python, ```sh and ```toml blocks run; a ```toml block must be a scene).
PAGES = ["README.md", "docs/getting-started.md", "docs/guide/scenes.md", "docs/guide/measured-data.md",
         "docs/guide/silicone-and-contact.md", "docs/guide/meshes-and-accuracy.md",
         "docs/guide/materials.md"]
BLOCKS = [(page, kind, body) for page in PAGES
          for kind, body in re.findall(r"^```(\w+)\n(.*?)^```", (ROOT / page).read_text(encoding="utf-8"),
                                       re.S | re.M)]


def _commands(body):
    for line in body.splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            yield line


# slow: a block naming a scene whose solve is slow in test_examples.py, a command that is slow
# itself (a simulated rig's stream, an error estimate: 10-14 s of CPU each; test_measure_cli.py and
# test_error_estimate.py run them in the fast tier), and a tour of more than three commands (each its
# own process: the getting-started tour takes 25 s on a busy machine)
SLOW_SCENES = ("thesis-pzt-probe-3d", "thesis-pzt-3x3-3d", "thesis-pvdf-3x3-3d")
SLOW_COMMANDS = ("taxel measure simulate", "--estimate")


def _slow(lang, body):
    return (any(s in body for s in SLOW_SCENES + SLOW_COMMANDS)
            or (lang == "sh" and len(list(_commands(body))) > 3))


def blocks(lang):
    return [pytest.param(body, id=f"{Path(page).stem}-{lang}-{i}", marks=[pytest.mark.slow] if _slow(lang, body) else [])
            for i, (page, kind, body) in enumerate(BLOCKS) if kind == lang]


def test_the_readme_and_its_pages_have_the_blocks_this_test_runs():
    kinds = [k for _, k, _ in BLOCKS]
    assert kinds.count("python") >= 4 and kinds.count("sh") >= 4 and kinds.count("toml") >= 3
    assert set(kinds) <= {"python", "sh", "toml"}, f"a block this test does not run: {set(kinds)}"
    readme = [k for page, k, _ in BLOCKS if page == "README.md"]
    assert "python" in readme and "sh" in readme, "the README keeps its example and its two commands"


@pytest.mark.parametrize("body", blocks("python"))
def test_python_blocks_run(body, monkeypatch):
    monkeypatch.chdir(ROOT)
    exec(compile(body, "README.md", "exec"), {"__name__": "readme"})


@pytest.mark.parametrize("body", blocks("sh"))
def test_shell_blocks_run(body):
    bindir = Path(sys.executable).parent
    for cmd in _commands(body):
        argv = shlex.split(cmd)
        if argv[0] == "make":
            assert argv[1:] in (["demo"], ["test"], ["test-all"]), f"an unexpected make target in the README: {cmd}"
            run = subprocess.run(["make", "-n", *argv[1:]], cwd=ROOT, capture_output=True, text=True)
        else:
            assert argv[0] == "taxel", f"README command not run by this test: {cmd}"
            run = subprocess.run([str(bindir / "taxel"), *argv[1:]], cwd=ROOT, capture_output=True, text=True,
                                 timeout=CEILING)
        assert run.returncode == 0, f"{cmd}: exit {run.returncode}\n{run.stderr[-2000:]}"


@pytest.mark.parametrize("body", blocks("toml"))
def test_toml_blocks_are_valid_scenes(body, tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(body)
    tomllib.loads(body)
    scene = taxel.load(path)
    assert scene.array is not None or scene.plate is not None
