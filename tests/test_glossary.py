"""The glossary (docs/glossary.md) names code: every code path it gives exists.

A code path is a dotted name inside backticks whose first part is the package or one
of its layer folders (`taxel.fem.contact.Press`, `fem.contact.StopCause`,
`studies.evaluate.evaluate`); a call's arguments are dropped (`taxel.read(folder)`).
It resolves by importing its longest module prefix and getting the rest as attributes
(a dataclass or pydantic field counts). A repository file path in backticks
(`fem/contact/_press.py`) must exist. So a rename that forgets the glossary fails here.
"""

from __future__ import annotations

import dataclasses
import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
GLOSSARY = ROOT / "docs" / "glossary.md"
# the layer folders, as the installed package names them
PREFIX = {"taxel": "taxel", "fem": "taxel.fem", "meshing": "taxel.meshing", "optimize": "taxel.optimize",
          "studies": "taxel.studies", "reports": "taxel.reports", "analyses": "taxel.analyses"}
DOTTED = re.compile(r"(?<![\w./-])([A-Za-z_]\w*(?:\.[A-Za-z_]\w*)+)(?:\([^)]*\))?")
FILE = re.compile(r"(?<![\w./-])((?:[\w-]+/)+[\w.-]+\.(?:py|toml|json|csv|md))\b")


def _spans(text: str) -> list[str]:
    return re.findall(r"`([^`\n]+)`", text)


def code_paths(text: str) -> list[str]:
    out = []
    for span in _spans(text):
        for m in DOTTED.finditer(span):
            head, _, rest = m.group(1).partition(".")
            if head in PREFIX:
                path = f"{PREFIX[head]}.{rest}" if head != "taxel" else m.group(1)
                if path not in out:
                    out.append(path)
    return out


def file_paths(text: str) -> list[str]:
    out = []
    for span in _spans(text):
        out += [m.group(1) for m in FILE.finditer(span) if m.group(1) not in out]
    return out


def resolve(path: str):
    """The object at a dotted path: the longest importable module, then attributes."""
    parts = path.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ModuleNotFoundError:
            continue
        for name in parts[i:]:
            if hasattr(obj, name):
                obj = getattr(obj, name)
                continue
            fields = ({f.name for f in dataclasses.fields(obj)} if dataclasses.is_dataclass(obj) else set()) | set(
                getattr(obj, "model_fields", {}) or {})
            if name not in fields:
                raise AttributeError(f"{path}: no `{name}` in {obj!r}")
            obj = None
        return obj
    raise ModuleNotFoundError(path)


TEXT = GLOSSARY.read_text(encoding="utf-8")


def test_the_glossary_names_code():
    assert len(code_paths(TEXT)) >= 30, "the glossary's code paths were not found: has its format changed?"


@pytest.mark.parametrize("path", code_paths(TEXT))
def test_every_code_path_in_the_glossary_exists(path):
    resolve(path)


@pytest.mark.parametrize("path", file_paths(TEXT))
def test_every_file_in_the_glossary_exists(path):
    assert (ROOT / path).exists(), f"docs/glossary.md names {path}, which does not exist"


def test_the_parser_finds_paths_in_any_cell():
    text = ("| a | b | `taxel.fem.contact.Press`, `fem/contact/_press.py` (`fem.assembly.elimination(sy)`) |\n"
            "| c | `[load] kind = \"probe\"`, `Options.rule`, `benchmarks/studies.py` | `taxel solve --json` |\n")
    assert code_paths(text) == ["taxel.fem.contact.Press", "taxel.fem.assembly.elimination"]
    assert file_paths(text) == ["fem/contact/_press.py", "benchmarks/studies.py"]
    with pytest.raises(AttributeError):
        resolve("taxel.fem.contact.NoSuchName")


@pytest.mark.parametrize("path", code_paths(TEXT) + file_paths(TEXT))
def test_every_path_in_the_glossary_is_public(path):
    """No private module or name (`_name`): the glossary names a subpackage's surface."""
    parts = re.split(r"[./]", path.removesuffix(".py"))
    assert not [p for p in parts if p.startswith("_")], f"docs/glossary.md names the private {path}"


def test_the_glossary_names_its_own_test():
    assert "`tests/test_glossary.py`" in TEXT.split("##", 1)[0]


# Names that changed (CHANGELOG.md keeps them); none is written or read anywhere else.
OLD_NAMES = ["voltage_pressed", "largest 2D/3D disagreement", "taxel.optimize(", "taxel.skin(", "taxel.explore(",
             "api.optimize(", "api.skin(", "api.explore(", 'rec.get("silicone")', "reduced basis", "reduced run",
             "taxel.analyses.problem.", "taxel.analyses.error_estimate", "taxel.analyses.model_choice",
             "taxel.analyses.influence", "taxel.analyses.coverage", "taxel.analyses.localization",
             "taxel.analyses.reduced", "taxel.analyses.noise", "taxel.analyses.dynamic", "taxel.analyses.at_readout",
             "taxel.analyses.analysis", "tests/test_docs.py`)"]


def test_no_old_name_is_read_anywhere():
    import subprocess
    files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True).stdout.split()
    skip = {"CHANGELOG.md", "tests/test_glossary.py"}
    hits = []
    for f in files:
        path = ROOT / f
        if f in skip or f.startswith("tests/data/") or not path.is_file() or path.suffix not in (
                ".py", ".md", ".toml", ".html", ".txt", ".cfg", ".json", ".yml", ".yaml", ".sh", ""):
            continue
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue
        hits += [f"{f}: {old}" for old in OLD_NAMES if old in text]
    assert not hits, "old names: " + "; ".join(hits)
