"""The package's structure: no import cycles, no cross-module imports of underscore
names, and a public API that no subpackage can shadow.

The import graph is read from the sources with `ast`, every import counted (at the
top of a module or inside a function: a cycle held by a lazy import is still a
cycle), with the folder -> package mapping of setup.py.
"""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def package_dirs() -> dict[str, Path]:
    """Every installed package -> its folder, by setup.py's folder map and package finder."""
    import runpy
    build = runpy.run_path(str(ROOT / "setup.py"), run_name="setup")     # (setup() runs only as __main__)
    mapped = build["FOLDERS"]

    def folder(pkg: str) -> Path:          # setuptools' rule: the nearest mapped parent, then the names
        head, tail = pkg, []
        while head not in mapped and "." in head:
            head, _, last = head.rpartition(".")
            tail.insert(0, last)
        return ROOT.joinpath(mapped.get(head, head.replace(".", "/")), *tail)
    import os
    here = os.getcwd()
    os.chdir(ROOT)                          # the finder reads the folders relative to the checkout
    try:
        names = build["packages"]()
    finally:
        os.chdir(here)
    return {pkg: folder(pkg) for pkg in names}


def modules() -> dict[str, Path]:
    """Every module of the installed package: dotted name -> source file."""
    out = {}
    for pkg, folder in package_dirs().items():
        for f in folder.glob("*.py"):
            out[pkg if f.stem == "__init__" else f"{pkg}.{f.stem}"] = f
    return out


def resolve(name: str, mods: dict) -> str | None:
    """The package module an imported dotted name lives in."""
    while name and name not in mods:
        name = name.rpartition(".")[0]
    return name or None


def imports(mod: str, path: Path, mods: dict) -> list[tuple[str, int, str | None]]:
    """(imported module, line, imported name or None) of every import in a module."""
    tree = ast.parse(path.read_text(), str(path))
    pkg = mod if path.stem == "__init__" else mod.rpartition(".")[0]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(resolve(a.name, mods), node.lineno, None) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = pkg.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([base] if base else []))
            for a in node.names:
                full = f"{base}.{a.name}"
                target = full if full in mods else resolve(base, mods)
                out.append((target, node.lineno, None if full in mods else a.name))
    return [(t, n, a) for t, n, a in out if t is not None]


def graph() -> dict[str, set[str]]:
    mods = modules()
    return {m: {t for t, _, _ in imports(m, p, mods) if t != m} for m, p in mods.items()}


def cycles(g: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in g.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(g):
        if v not in index:
            visit(v)
    return out


def test_the_graph_sees_the_layers():
    g = graph()
    assert "taxel.fem.static" in g and "taxel.analyses.model.problem" in g
    assert "taxel.fem.assembly" in g["taxel.analyses.model.problem"]       # a real edge is found


def test_the_checks_see_a_cycle_and_an_underscore_import(tmp_path):
    """The cycle finder and the import reader find what they are for (else the two tests
    below would pass on a broken check)."""
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []
    bad = tmp_path / "bad.py"
    bad.write_text("from taxel.fem.static import _private\nfrom taxel.analyses.model import problem\n")
    found = imports("taxel.fake", bad, modules())
    assert ("taxel.fem.static", 1, "_private") in found and ("taxel.analyses.model.problem", 2, None) in found


def test_no_import_cycles():
    found = cycles(graph())
    assert not found, "import cycles: " + "; ".join(" <-> ".join(c) for c in found)


def test_no_underscore_names_across_modules():
    """`from taxel.x import _name` and `module._name` on an imported package module are
    private reach-ins; a name used by another module is public (no underscore)."""
    mods = modules()
    bad = []
    for mod, path in mods.items():
        tree = ast.parse(path.read_text(), str(path))
        aliases = {}
        for t, line, name in imports(mod, path, mods):
            if name is not None and name.startswith("_") and t != mod:
                bad.append(f"{path.relative_to(ROOT)}:{line} imports {t}.{name}")
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module:
                for a in node.names:
                    full = f"{node.module}.{a.name}"
                    if full in mods:
                        aliases[a.asname or a.name] = full
            elif isinstance(node, ast.Import):
                for a in node.names:
                    if a.asname and a.name in mods:
                        aliases[a.asname] = a.name
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id in aliases and node.attr.startswith("_") and not node.attr.startswith("__")
                    and aliases[node.value.id] != mod):
                bad.append(f"{path.relative_to(ROOT)}:{node.lineno} uses {aliases[node.value.id]}.{node.attr}")
    assert not bad, "\n".join(bad)


FEM_SUBPACKAGES = ("constitution", "linalg", "assembly", "static", "readout", "hyperelastic", "contact", "dynamics")


def private_reach_ins(mod: str, path: Path, mods: dict) -> list[str]:
    """Imports by `mod` of a private module (`_name`) of a package it is not inside."""
    out = []
    for t, line, _ in imports(mod, path, mods):
        head, _, last = t.rpartition(".")
        if last.startswith("_") and not last.startswith("__") and not (mod == head or mod.startswith(head + ".")):
            out.append(f"{path.relative_to(ROOT) if path.is_relative_to(ROOT) else path.name}:{line} imports {t}")
    return out


def test_the_private_module_check_sees_a_reach_in(tmp_path):
    mods = modules()
    bad = tmp_path / "bad.py"
    bad.write_text("from taxel.fem.contact._press import Press\nfrom taxel.fem.contact import Press\n")
    assert private_reach_ins("taxel.analyses.fake", bad, mods) == ["bad.py:1 imports taxel.fem.contact._press"]
    assert private_reach_ins("taxel.fem.contact.fake", bad, mods) == []       # inside its own package


def test_no_module_imports_another_packages_private_module():
    """Callers import from a subpackage (its `__all__`), never from its private modules:
    the package's own modules, the benchmarks and the docs' scripts. (Tests may reach in:
    they test the private modules themselves.)"""
    mods = modules()
    bad = []
    for mod, path in mods.items():
        bad += private_reach_ins(mod, path, mods)
    for path in [*ROOT.glob("benchmarks/*.py"), *ROOT.glob("docs/**/*.py")]:
        bad += private_reach_ins("outside", path, mods)
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("sub", FEM_SUBPACKAGES)
def test_each_fem_subpackage_has_a_docstring_and_a_curated_all(sub):
    """fem/ is its modelling chain: every subpackage says what it is and exports a list of
    public names, each of which resolves."""
    pkg = importlib.import_module(f"taxel.fem.{sub}")
    assert pkg.__doc__ and len(pkg.__doc__.split()) > 20, f"taxel.fem.{sub} has no package docstring"
    assert pkg.__all__ and all(not n.startswith("_") for n in pkg.__all__)
    for name in pkg.__all__:
        assert getattr(pkg, name) is not None, f"taxel.fem.{sub}.{name}"
    folder = package_dirs()[f"taxel.fem.{sub}"]
    assert all(f.name.startswith("_") for f in folder.glob("*.py")), f"{sub}: a module without an underscore"


def test_the_fem_import_contract_follows_the_chain():
    """The import contract names every fem subpackage, in at most 9 tiers."""
    cfg = tomllib.loads((ROOT / ".ci" / "importlinter.toml").read_text())
    chain = next(c for c in cfg["tool"]["importlinter"]["contracts"] if c.get("containers") == ["taxel.fem"])
    named = {n.strip() for tier in chain["layers"] for n in tier.split("|")}
    assert named == set(FEM_SUBPACKAGES) and len(chain["layers"]) <= 9


def test_every_package_folder_is_installed():
    """A folder with an __init__.py under a layer folder is one of setup.py's packages
    (found, not listed: an unlisted one would work editable and be missing from a real install)."""
    listed = package_dirs()
    for folder in set(listed.values()):
        for init in folder.rglob("__init__.py"):
            assert init.parent in listed.values(), f"{init.parent.relative_to(ROOT)} is not among setup.py's packages"


def test_electrode_names_come_from_one_helper():
    """'taxel_{r}_{c}' is spelled once (taxel.schema.electrode_name)."""
    hits = [f"{p.relative_to(ROOT)}" for p in modules().values()
            if 'f"taxel_{' in p.read_text() and p.name != "schema.py"]
    assert not hits, hits


def test_the_public_api_cannot_be_shadowed():
    """Every public name of `taxel` stays what it is after importing every subpackage: no
    public function shares its name with a subpackage (`taxel.optimize` is the subpackage,
    `taxel.run_optimization` the function), and no package's public name (its `__all__`)
    is both a function or class and a module."""
    code = """
import importlib, importlib.util, sys, taxel
for name in NAMES:
    importlib.import_module(name)
import types, taxel.optimize.driver
assert callable(taxel.run_optimization), taxel.run_optimization
for name in taxel.__all__:
    value = getattr(taxel, name)
    assert value is not None, name
    assert (name == "measure") == isinstance(value, types.ModuleType), name
    assert name == "measure" or importlib.util.find_spec("taxel." + name) is None, name
clashes = []                     # no package's public name is both a function (or class) and a module
for name in NAMES:
    pkg = sys.modules[name]
    if not hasattr(pkg, "__path__"):
        continue
    for attr in getattr(pkg, "__all__", [n for n in vars(pkg) if not n.startswith("_")]):
        if not isinstance(getattr(pkg, attr), types.ModuleType) and importlib.util.find_spec(f"{name}.{attr}"):
            clashes.append(f"{name}.{attr}")
assert not clashes, clashes
assert type(taxel) is types.ModuleType         # no module-class swap
from taxel import Scene, StaticResult, FrequencyResult, TransientResult, LumpedResult, SceneError
assert isinstance(taxel.load("thesis-pzt-single-2d"), Scene)
print("ok")
"""
    code = f"NAMES = {sorted(modules())!r}\n" + code
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr[-2000:]


def test_optimize_twice(tmp_path):
    """The API bug this guards: a second `taxel.run_optimization(...)` raised "'module' object is
    not callable". A small optimization (3 evaluations of a coarse 2D taxel), twice,
    after importing the subpackage, in a fresh process."""
    (tmp_path / "opt.toml").write_text("""
base = "thesis-pzt-single-2d"
[variables]
silicone_above = {path = "array.silicone_above", min = "0.5 mm", max = "1.5 mm", start = "1 mm"}
[objective]
maximize = "sensitivity"
[algorithm]
global = "none"
max_evaluations = 3
""")
    code = f"""
import taxel, taxel.optimize.driver
a = taxel.run_optimization({str(tmp_path / 'opt.toml')!r}, {str(tmp_path / 'a')!r}, workers=1)
b = taxel.run_optimization({str(tmp_path / 'opt.toml')!r}, {str(tmp_path / 'b')!r}, workers=1)
assert type(a) is type(b)
print("ok")
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode == 0 and out.stdout.strip().endswith("ok"), out.stderr[-2000:]


def test_every_module_imports():
    names = sorted(modules())
    assert len(names) > 60
    for n in names:
        importlib.import_module(n)
