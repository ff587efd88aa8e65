"""The walk of one design point through the package, module by module, as it runs.

    python benchmarks/walk.py [--inside-layers] [--files | --folders] [ARGS...]
                                        (default: solve thesis-pzt-single-2d --json --out DIR)

Runs the `taxel` command in this process under a profile hook and records, from the
moment the command's handler in the taxel.cli package takes over (after argument
parsing; `_solve` in taxel.cli.solve for `solve`), every call
from one module of the package into another (calls inside a module, and calls into
third-party code, are not steps). Prints the modules in the order they are first
entered, how many distinct modules the walk passes through, and how many times it
comes back into a module it had already left (a call into a module that is not the
caller and was entered before). Scene validation (pydantic validators in
taxel.scene and taxel.schema calling taxel.units) is counted like any other call. Calls from one module of
the FEM (taxel.fem) or the meshing (taxel.meshing) into another of the same folder
are the solver's own machinery, where the design point is no longer a scene but a
Problem or a layout: they are left out unless --inside-layers is given. A subpackage
of the FEM (taxel.fem.static, taxel.fem.assembly, ...) counts as one module: its
callers see only its surface (its __init__'s __all__), its private modules are its
own machinery.
--files counts every file as its own module, a FEM subpackage's private modules too.
--folders draws the walk one stop per folder (taxel.analyses, taxel.fem, ...).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path


FILES = False          # --files


def trace(argv: list[str]) -> tuple[str, list[tuple[str, str]]]:
    """The handler's module, and every (caller, callee) call between modules, in order."""
    from taxel import cli
    cli_folder = Path(cli.__file__).resolve().parent
    roots = {}
    import importlib
    for sub in ("taxel", "taxel.fem", "taxel.meshing", "taxel.optimize", "taxel.studies", "taxel.reports"):
        roots[Path(importlib.import_module(sub).__file__).resolve().parent] = sub

    def module_of(filename: str) -> str | None:
        p = Path(filename).resolve()
        best = None
        for r, name in roots.items():
            if p.is_relative_to(r) and (best is None or len(r.parts) > len(best[0].parts)):
                best = (r, name)
        if best is None:
            return None
        rel = p.relative_to(best[0]).with_suffix("")
        parts = [best[1], *rel.parts]
        if best[1] == "taxel.fem" and len(parts) > 2 and not FILES:   # a FEM subpackage is one module
            parts = parts[:2]
        return ".".join(parts).removesuffix(".__init__")

    steps: list[tuple[str, str]] = []

    def at_import(frame) -> bool:
        """Inside a module body being imported (import-time work is not the walk)."""
        f = frame.f_back
        while f is not None:
            if f.f_code.co_name == "<module>" and f.f_code.co_filename != __file__:
                return True
            f = f.f_back
        return False
    cache: dict[str, str | None] = {}

    active: list[str] = []
    handler = "_" + argv[0].replace("-", "_")     # the command's handler in taxel.cli (_solve for solve)

    def hook(frame, event, arg):
        if not active and frame.f_code.co_name == handler and \
                Path(frame.f_code.co_filename).resolve().parent == cli_folder:
            active.append(module_of(frame.f_code.co_filename))   # the command line is parsed: the walk begins
        if not active or event != "call" or frame.f_code.co_name == "<module>" or at_import(frame):
            return
        callee = cache.setdefault(frame.f_code.co_filename, module_of(frame.f_code.co_filename))
        if callee is None or callee == active[0] and not steps:
            return
        back = frame.f_back
        while back is not None and cache.setdefault(back.f_code.co_filename, module_of(back.f_code.co_filename)) is None:
            back = back.f_back
        caller = None if back is None else cache[back.f_code.co_filename]
        if caller is not None and caller != callee:
            steps.append((caller, callee))

    sys.setprofile(hook)
    try:
        cli.main(argv)
    finally:
        sys.setprofile(None)
    return (active[0] if active else "taxel.cli"), steps


def package(module: str) -> str:
    """The layer folder a module is in (taxel.fem, taxel.meshing, ...; taxel's own modules apart)."""
    parts = module.split(".")
    return ".".join(parts[:2]) if len(parts) > 2 and parts[1] in LAYER_PACKAGES else module


LAYER_PACKAGES = ["fem", "meshing"]


def main() -> None:
    args = sys.argv[1:]
    inside = "--inside-layers" in args          # also count calls inside the fem and meshing folders
    by_folder = "--folders" in args             # one stop per folder (taxel.analyses, taxel.reports, ...)
    global FILES
    FILES = "--files" in args                   # every file its own module, a FEM subpackage's private ones too
    args = [a for a in args if a not in ("--inside-layers", "--folders", "--files")]
    if by_folder:
        LAYER_PACKAGES.extend(("cli", "analyses", "reports", "studies", "optimize", "jobs"))
    with tempfile.TemporaryDirectory() as tmp:
        argv = args or ["solve", "thesis-pzt-single-2d", "--json", "--out", str(Path(tmp) / "x")]
        import contextlib
        import io
        with contextlib.redirect_stdout(io.StringIO()):
            start, steps = trace(argv)
    if not inside:     # the design point's walk: within the FEM and the meshing (which never see the scene)
        steps = [(a, b) for a, b in steps if not (package(a) == package(b) != a)]
    if by_folder:
        steps = [(package(a), package(b)) for a, b in steps if package(a) != package(b)]
        start = package(start)
    edges = list(dict.fromkeys(steps))            # each caller -> callee pair once, in first-call order
    seen, order, back = {start}, [start], []
    for caller, callee in edges:
        if callee in seen:
            back.append((caller, callee))
        else:
            seen.add(callee)
            order.append(callee)
    print(f"taxel {' '.join(argv)}")
    print(f"{len(order)} modules; {len(edges)} distinct calls between modules ({len(steps)} in all); "
          f"{len(back)} come back into a module already entered")
    for i, m in enumerate(order, 1):
        frm = sorted({c for c, k in edges if k == m})
        print(f"  {i:2d}. {m:<34} from {', '.join(frm)}")
    if back:
        print("back into a module already entered:")
        for c, k in back:
            print(f"      {c} -> {k}")


if __name__ == "__main__":
    main()
