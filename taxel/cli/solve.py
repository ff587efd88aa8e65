"""`taxel solve`, `taxel lumped`, `taxel mesh`, `taxel work-precision`, `taxel examples`:
one scene in, its answer out, each a thin shell over taxel.api.

Output folders: an analysis writes its folder (`result.to_folder`: JSON, CSV,
summary.txt, figures) only when --out is given, whatever its type. With --json,
stdout holds exactly one JSON record (the result's `record()`); notes go to stderr.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from taxel.cli.files import EXIT_FAILED, InputError, number, writable_file
from taxel.units import engineering as si


def register(sub) -> None:
    p = sub.add_parser("solve", help="solve a scene and print per-electrode voltage and charge")
    p.add_argument("scene", help="scene TOML file or built-in example name")
    p.add_argument("--json", action="store_true", help="print one JSON record")
    p.add_argument("--quiet", action="store_true", help="no progress lines on the terminal")
    p.add_argument("--estimate", action="store_true", help="estimate the error of each output (discretisation, "
                   "model form, material law; one coarse solve and, for 2D, the cheapest 3D model)")
    p.add_argument("--vtu", metavar="FILE", help="write displacement, potential, strain and stress fields")
    p.add_argument("--solver", default="auto", choices=["auto", "superlu", "pardiso", "umfpack", "krylov"])
    p.add_argument("--out", metavar="DIR", help="folder for the outputs (result.json, scene.json, CSV, "
                   "summary.txt, figures); nothing is written without it")
    p.add_argument("--friction-band", action="store_true", help="a press: also solve at frictionless and "
                   "sticking (and the scene's Coulomb coefficient) and print the sensitivity and crosstalk of each")
    p.set_defaults(run=_solve)
    p = sub.add_parser("work-precision",
                       help="the work-precision chart: wall time against error of every model and mesh")
    p.add_argument("scenes", nargs="+", help="scene TOML files or built-in example names")
    p.add_argument("--force", type=number(0, 100, low_open=True, unit="N"), action="append", metavar="N", help="force in newtons (repeat; "
                   "default 0.2 and 1)")
    p.add_argument("--out", metavar="DIR", default=None, help="output folder (default out/work-precision)")
    p.add_argument("--store", metavar="DIR", help="the solve cache (default DIR/store)")
    p.set_defaults(run=_work_precision)
    p = sub.add_parser("lumped", help="the 3-DoF lumped model's answer to a scene (frequency response)")
    p.add_argument("scene")
    p.add_argument("--json", action="store_true", help="print one JSON record")
    p.add_argument("--out", metavar="DIR", help="folder for the outputs; nothing is written without it")
    p.set_defaults(run=_lumped)
    p = sub.add_parser("mesh", help="mesh a scene and write it")
    p.add_argument("scene")
    p.add_argument("-o", "--output", required=True, help=".msh (gmsh, physical groups) or .vtu/.xdmf")
    p.set_defaults(run=_mesh)
    p = sub.add_parser("examples", help="list the built-in example scenes")
    p.set_defaults(run=_examples)


def _solve(args):
    import taxel.api as api
    vtu = writable_file(args.vtu, "--vtu", (".vtu",)) if args.vtu else None
    scene = api.load(args.scene) if args.friction_band else args.scene
    if args.friction_band and not (scene.load.kind == "probe" and scene.load.contact):
        raise InputError("--friction-band needs a press: load.kind = 'probe' and load.contact = true in the scene")
    res = api.solve(scene, out=args.out, solver=args.solver, estimate=args.estimate)
    if vtu is not None and res.kind == "static":
        res.to_vtu(vtu)
    band = api.friction_band(res.scene, result=res, solver=args.solver) if args.friction_band else None
    _print(res, args, (res.details() if res.kind == "static" else []) + ([] if band is None else band.lines()),
           None if band is None else {"friction_band": band.record()})
    if vtu is not None and res.kind == "static":
        print(f"fields written to {args.vtu}", file=sys.stderr if args.json else sys.stdout)
    if not res.success:                       # the numbers printed and written are the last converged state's
        st = res.stop
        print(f"taxel: failed: {st.message}; the results" + (f" in {args.out}" if args.out else "")
              + f" are its last converged state, at load.{st.load} "
              f"{si(getattr(res.scene.load, st.load), st.unit)} of {si(st.requested, st.unit)}", file=sys.stderr)
        return EXIT_FAILED


def _lumped(args):
    import taxel.api as api
    _print(api.lumped(args.scene, out=args.out), args)


def _print(res, args, details=(), extra: dict | None = None) -> None:
    """A result on stdout: its one JSON record (--json; with `extra`'s keys), else its summary;
    then what --out holds."""
    if args.json:
        print(json.dumps({**res.record(), **(extra or {})}))
    else:
        print("\n".join([*res.summary(), *details]))
    if args.out:
        print(f"wrote {Path(args.out).resolve()}", file=sys.stderr if args.json else sys.stdout)


def _mesh(args):
    import taxel.api as api
    import meshio
    out = writable_file(args.output, "-o", tuple(sorted({".msh", *meshio.extension_to_filetypes})))
    tm = api.mesh(args.scene, out)
    print(f"{out}: {tm.mesh.nelements} elements, {tm.mesh.nvertices} nodes; "
          f"regions {', '.join(tm.regions)}; facet sets {', '.join(tm.facets)}")


def _examples(args):
    from taxel.scene import examples
    for name in examples():
        print(name)


def _work_precision(args):
    import taxel.api as api
    from taxel.reports.work_precision import lines
    forces = args.force or [0.2, 1.0]
    out = Path(args.out or "out/work-precision")
    for s in args.scenes:
        api.load(s)                           # a bad scene fails before any solve

    def progress(level, p):
        print(f"  {level.label:<36} " + ("failed (stored)" if p is None else
                                         f"{p.seconds:7.2f} s  {p.unknowns:>7} unknowns"), flush=True)
    api.work_precision(args.scenes, out, forces, args.store, progress)
    for line in lines(json.loads((out / "work-precision.json").read_text())):
        print(line)
    print(f"wrote {out.resolve()}")
