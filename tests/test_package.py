"""One installed package with one Python API, and layers that only import downward."""

from __future__ import annotations

import importlib.metadata
import subprocess
import sys
from pathlib import Path

import pytest
from waits import CEILING

ROOT = Path(__file__).resolve().parents[1]


def test_taxel_is_the_only_top_level_name_installed():
    owners = importlib.metadata.packages_distributions()
    ours = sorted(name for name, dists in owners.items() if "taxel" in dists)
    assert ours == ["taxel"]


def test_from_an_empty_folder_the_api_solves_and_the_layer_folders_are_not_top_level(tmp_path):
    code = "import taxel; r = taxel.solve(taxel.load('thesis-pzt-single-2d')); print(r)"
    run = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=CEILING)
    assert run.returncode == 0, run.stderr
    assert "taxel_0_0" in run.stdout and " mV" in run.stdout
    for name in ("fem", "meshing", "optimize", "studies", "reports"):
        run = subprocess.run([sys.executable, "-c", f"import {name}"], cwd=tmp_path, capture_output=True, text=True)
        assert run.returncode != 0 and "ModuleNotFoundError" in run.stderr, name


def test_a_users_own_reports_module_does_not_break_the_cli(tmp_path):
    (tmp_path / "reports.py").write_text("raise SystemExit('the user module was imported')\n")
    (tmp_path / "fem.py").write_text("raise SystemExit('the user module was imported')\n")
    taxel = Path(sys.executable).parent / "taxel"
    run = subprocess.run([str(taxel), "examples"], cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0 and "thesis-pzt-single-2d" in run.stdout, run.stderr


def test_the_import_contract_holds():
    """.ci/lint-imports: import-linter on the checkout laid out as the package (layers, the
    FEM never sees the scene schema, the FEM's and the analyses' own layers); about 1 s."""
    run = subprocess.run([str(ROOT / ".ci" / "lint-imports")], capture_output=True, text=True, timeout=CEILING,
                         env={"PATH": "/usr/bin:/bin", "PYTHON": sys.executable})
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-2000:]
    assert "0 broken" in run.stdout
