"""The `taxel` command.

    taxel solve SCENE [--json] [--vtu FILE] [--solver NAME] [--out DIR]
    taxel lumped SCENE [--out DIR]
    taxel work-precision SCENE... [--force N]... [--out DIR] [--store DIR]   (the work-precision chart)
    taxel mesh SCENE -o FILE          (.msh with physical groups, or .vtu/.xdmf via meshio)
    taxel study run STUDY [--out DIR] [--workers N] [--scheduler ADDR] [--retry-failed]
    taxel study status DIR | taxel study export DIR --csv FILE
    taxel optimize OPT [--out DIR] [--workers N]
    taxel report DIR... --out OUT [--pdf]
    taxel demo [--out DIR] [--small] [--full] [--presses-3d N]
    taxel examples
    taxel measure capture|import|export|rebuild|simulate ...   (taxel/cli_measure.py)

SCENE is a TOML file or the name of a built-in example. Bad input exits with
code 2 and one line naming the problem and the fix.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import json
import os
import sqlite3
import sys
from pathlib import Path

from taxel import cli_explore, cli_material, cli_measure, cli_reduce, cli_schema
from taxel.cli_files import InputError, writable_file as _writable_file
from taxel.units import engineering as si

# Imported after the command line is parsed (main): the API pulls in the scene schema,
# the analyses and the FEM, which `taxel --help` and a bad argument never need.
api = SceneError = examples = None


def _import_api() -> None:
    global api, SceneError, examples
    from taxel import api
    from taxel.scene import SceneError, examples

EXIT_INPUT, EXIT_FAILED = 2, 1


def _print_written(out: Path, files, summary):
    for line in summary:
        print(line)
    for f in files:
        print(f"wrote {out / Path(f).name}")


def _work_precision(args):
    from taxel.reports.work_precision import lines
    forces = args.force or [0.2, 1.0]
    for f in forces:
        if not (0 < f <= 100):
            raise SceneError(f"--force {f:g}: give a force in newtons between 0 and 100")
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


def _solve(args):
    from taxel.analyses.results import output_folder
    from taxel.reports import analysis
    scene = api.load(args.scene)
    if scene.analysis.type != "static":
        out = Path(args.out or Path("out") / scene.name)
        with output_folder(out) as tmp:           # made first: a bad --out fails before the solve
            files, summary = analysis.write(api.solve(scene, estimate=args.estimate), tmp)
        _print_written(out, files, summary)
        return
    vtu = _writable_file(args.vtu, "--vtu", (".vtu",)) if args.vtu else None
    with output_folder(Path(args.out)) if args.out else contextlib.nullcontext() as tmp:
        try:
            sol = api.solve(scene, solver=args.solver, estimate=args.estimate)
        except RuntimeError as exc:               # stopped short of the load: its last converged state is kept
            from taxel.analyses import stopped_result
            sol = stopped_result(scene, exc)
            if sol is None:
                raise
        if tmp is not None:                       # result.json, scene.json, the field figures, summary.txt
            analysis.write(sol, tmp)
    _print_static(sol, args, vtu)
    if sol.stop is not None:                      # the numbers printed and written are the last converged state's
        print(f"taxel: failed: {sol.stop.message}; the results"
              + (f" in {args.out}" if args.out else "") + f" are its last converged state, at {_reached(sol)}",
              file=sys.stderr)
        return EXIT_FAILED


def _reached(sol) -> str:
    """The load a stopped solve reached, against the one asked for."""
    st = sol.stop
    return f"load.{st.load} {si(getattr(sol.scene.load, st.load), st.unit)} of {si(st.requested, st.unit)}"


def _print_static(sol, args, vtu):
    """Print a static result (its summary, or --json's record) and write --vtu."""
    from taxel.meshing.build import export
    if vtu:
        export(sol.mesh, vtu, point_data={"u": sol.fields.u, "phi": sol.fields.phi},
               cell_data={"strain": sol.fields.strain, "stress": sol.fields.stress})
    if args.json:
        print(json.dumps(sol.record()))
        return
    print(sol)
    if sol.times:                                 # a stopped solve's last converged state has none
        print(f"times: mesh {sol.times['mesh']:.3f} s, assemble {sol.times['assemble']:.3f} s, "
              f"solve {sol.times['solve']:.3f} s")
    print(f"applied force {si(sol.applied_force, 'N')}, support reaction {si(sol.reaction[-1], 'N')} (vertical), "
          f"relative residual {sol.residual:.1e}")
    if sol.newton is not None:
        print(f"Newton: {sol.newton.message}")
    if sol.model_note:
        print(sol.model_note)
    if sol.mesh.layout.taxels:
        from taxel.analyses import linear_error
        est = linear_error(sol.max_silicone_strain)
        linear = not sol.yeoh
        print(f"largest silicone strain {100 * sol.max_silicone_strain:.1f} %"
              + (f" (a linear silicone errs by about {100 * est:.2g} % here; model.silicone = 'auto' or "
                 "'yeoh' to do better)" if linear and est > 0.02 else ""))
    if args.vtu:
        print(f"fields written to {args.vtu}")


def _lumped(args):
    from taxel.analyses import lumped_response
    from taxel.analyses.results import output_folder
    from taxel.reports import analysis
    scene = api.load(args.scene)
    out = Path(args.out or Path("out") / scene.name)
    with output_folder(out) as tmp:
        files, summary = analysis.write(lumped_response(scene), tmp)
    _print_written(out, files, summary)


def _study(args):

    from pydantic import ValidationError

    from taxel.studies.spec import Study, StudyError, StudySpec
    from taxel.studies.store import tidy_rows, write_rows
    if args.action == "run":
        out = Path(args.out) if args.out else None
        summary = api.run_study(args.target, out, workers=args.workers, scheduler=args.scheduler,
                                retry_failed=args.retry_failed, progress=not args.quiet)
        print(f"{summary.name}: {summary.total} points: {summary.done} computed, {summary.cached} cached, "
              f"{summary.failed} failed, {summary.seconds:.2f} s; results in {summary.folder} "
              f"(results.csv, {len(summary.plots)} plots)")
        return 0 if summary.failed == 0 else EXIT_FAILED
    out = Path(args.target)
    if not (out / "results.sqlite").exists():
        raise StudyError(f"{out}: no study results here (no results.sqlite); run 'taxel study run' first")
    rows = tidy_rows(out)
    if args.action == "status":
        total = None
        if (out / "study.json").exists():
            try:
                spec = StudySpec.model_validate_json((out / "study.json").read_text())
            except ValidationError:
                raise StudyError(f"{out / 'study.json'}: not a study record (corrupt or edited); "
                                 "rerun 'taxel study run' to rewrite it") from None
            total = len(Study(spec, {}, out).points())
        n_done = sum(r["status"] == "done" for r in rows)
        n_failed = sum(r["status"] == "failed" for r in rows)
        print(f"{out}: {n_done} done, {n_failed} failed"
              + (f", {max(total - n_done - n_failed, 0)} pending of {total}" if total is not None else ""))
        for r in rows:
            if r["status"] == "failed":
                print(f"  failed: {', '.join(f'{k}={v}' for k, v in r.items() if k not in ('status', 'error'))[:120]}"
                      f": {r['error']}")
    else:
        if not args.csv:
            raise StudyError("study export needs --csv FILE")
        write_rows(rows, Path(args.csv))
        print(f"{len(rows)} rows written to {args.csv}")


def _optimize(args):
    result = api.optimize(args.file, args.out, workers=args.workers)
    for line in result.summary():
        print(line)
    print(f"written to {Path(args.out or Path('out') / result.name)}")
    return 0 if result.kind == "front" or result.success else EXIT_FAILED


def _report(args):
    index = api.report(args.folders, Path(args.out), pdf=args.pdf, compare=not args.no_compare)
    print(f"report: {index.resolve()}")


def _demo(args):
    from taxel.jobs.main_job import run
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: exists and is not a folder; choose another output folder")
    if args.presses_3d < 0:
        raise InputError(f"--presses-3d {args.presses_3d}: must be 0 or more (front designs pressed in 3D)")
    run(out, small=args.small, full=args.full, presses_3d=args.presses_3d)


def _mesh(args):
    from taxel.analyses.adapter import check, checked_layout
    from taxel.meshing.build import build, export
    import meshio
    scene = api.load(args.scene)
    out = _writable_file(args.output, "-o", tuple(sorted({".msh", *meshio.extension_to_filetypes})))
    lay = checked_layout(scene, check(scene))
    if out.suffix == ".msh":
        tm = build(lay, msh_path=out)
    else:
        tm = build(lay)
        export(tm, out)
    print(f"{out}: {tm.mesh.nelements} elements, {tm.mesh.nvertices} nodes; "
          f"regions {', '.join(tm.regions)}; facet sets {', '.join(tm.facets)}")


def _examples(args):
    for name in examples():
        print(name)


def main(argv=None):
    ap = _Parser(prog="taxel", description="Piezoelectric tactile sensor design tool")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("solve", help="solve a scene and print per-electrode voltage and charge")
    p.add_argument("scene", help="scene TOML file or built-in example name")
    p.add_argument("--json", action="store_true", help="print one JSON record")
    p.add_argument("--estimate", action="store_true", help="estimate the error of each output (discretisation, "
                   "model form, material law; one coarse solve and, for 2D, the cheapest 3D model)")
    p.add_argument("--vtu", metavar="FILE", help="write displacement, potential, strain and stress fields")
    p.add_argument("--solver", default="auto", choices=["auto", "superlu", "pardiso", "umfpack", "krylov"])
    p.add_argument("--out", metavar="DIR", help="folder for the outputs (scene.json, result.json; CSV and PNG "
                   "of frequency/transient analyses; default for those: out/SCENE)")
    p.set_defaults(run=_solve)
    p = sub.add_parser("work-precision", help="the work-precision chart: wall time against error of every model and mesh")
    p.add_argument("scenes", nargs="+", help="scene TOML files or built-in example names")
    p.add_argument("--force", type=float, action="append", metavar="N", help="force in newtons (repeat; "
                   "default 0.2 and 1)")
    p.add_argument("--out", metavar="DIR", default=None, help="output folder (default out/work-precision)")
    p.add_argument("--store", metavar="DIR", help="the solve cache (default DIR/store)")
    p.set_defaults(run=_work_precision)
    p = sub.add_parser("lumped", help="the 3-DoF lumped model's answer to a scene (frequency response)")
    p.add_argument("scene")
    p.add_argument("--out", metavar="DIR")
    p.set_defaults(run=_lumped)
    p = sub.add_parser("mesh", help="mesh a scene and write it")
    p.add_argument("scene")
    p.add_argument("-o", "--output", required=True, help=".msh (gmsh, physical groups) or .vtu/.xdmf")
    p.set_defaults(run=_mesh)
    p = sub.add_parser("study", help="parameter studies: run, status, export")
    p.add_argument("action", choices=["run", "status", "export"])
    p.add_argument("target", help="run: a study TOML file or built-in study name; status/export: a study folder")
    p.add_argument("--out", metavar="DIR", help="run: the study folder (default out/NAME)")
    p.add_argument("--workers", type=int, default=2, help="local Dask workers (1: in-process)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler (tcp://host:8786)")
    p.add_argument("--retry-failed", action="store_true", help="rerun the points that failed before")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--csv", metavar="FILE", help="export: the CSV to write")
    p.set_defaults(run=_study)
    p = sub.add_parser("optimize", help="optimize a design (nlopt), or its sensitivity-crosstalk front")
    p.add_argument("file", help="an optimization TOML file or a built-in name")
    p.add_argument("--out", metavar="DIR", help="results folder (default out/NAME); its store caches every design")
    p.add_argument("--workers", type=int, default=2, help="Dask workers for the front's runs")
    p.set_defaults(run=_optimize)
    p = sub.add_parser("report", help="self-contained HTML reports of result folders, and an index")
    p.add_argument("folders", nargs="+", help="study, optimization or solve folders")
    p.add_argument("--out", required=True, metavar="DIR")
    p.add_argument("--pdf", action="store_true", help="also a PDF of each page (needs Chromium)")
    p.add_argument("--no-compare", action="store_true", help="skip the model comparison (faster)")
    p.set_defaults(run=_report)
    p = sub.add_parser("demo", help="the main job: thesis study, optimization, dynamics and the report")
    p.add_argument("--out", default="out/demo", metavar="DIR")
    p.add_argument("--small", action="store_true", help="a reduced run (for CI)")
    p.add_argument("--full", action="store_true", help="also the thesis-model Fig. 2.5/2.8 studies and the probe fronts verified by 3D presses (slow)")
    p.add_argument("--presses-3d", type=int, default=0, metavar="N",
                   help="press N designs of each probe front in 3D (default 0; --full presses them all)")
    p.set_defaults(run=_demo)
    p = sub.add_parser("examples", help="list the built-in example scenes")
    p.set_defaults(run=_examples)
    cli_material.register(sub)
    cli_measure.register(sub)        # taxel measure ... (taxel/cli_measure.py)
    cli_explore.register(sub)        # taxel explore (taxel/cli_explore.py)
    cli_schema.register(sub)         # taxel schema ... (taxel/cli_schema.py)
    cli_reduce.register(sub)         # taxel reduce ... (taxel/cli_reduce.py)
    try:
        args = ap.parse_args(argv)
    except InputError as exc:
        return _error(str(exc))
    _import_api()
    try:
        code = args.run(args)
    except SceneError as exc:
        return _error(str(exc))
    except BrokenPipeError:              # `taxel ... | head`: the reader left; not an error
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except sqlite3.DatabaseError as exc:
        if "full" in str(exc).lower():    # "database or disk is full": the disk, not the store
            print("taxel: failed: results.sqlite: no space left on the device; free space and run the same "
                  "command again (finished points are kept)", file=sys.stderr)
            return EXIT_FAILED
        return _error(f"{getattr(exc, 'path', 'results.sqlite')}: the results store is corrupt or not a "
                      f"database ({exc}); move it aside and rerun")
    except OSError as exc:
        if exc.errno == errno.ENOSPC:    # not bad input: the machine; what is finished is kept
            print(f"taxel: failed: {exc.filename or 'the output folder'}: no space left on the device; free space "
                  "and run the same command again (finished points and written files are kept)", file=sys.stderr)
            return EXIT_FAILED
        where = exc.filename or ""
        return _error(f"{where}: {exc.strerror or exc}; check the path and its permissions" if where
                      else f"{exc.strerror or exc}; check the paths and their permissions")
    except (ValueError, KeyError) as exc:
        return _error(str(exc.args[0]) if exc.args else type(exc).__name__)
    except RuntimeError as exc:          # includes fem.hyperelastic.NewtonError
        print(f"taxel: failed: {_first_line(exc)}", file=sys.stderr)
        return EXIT_FAILED
    except MemoryError:
        print("taxel: failed: out of memory; coarsen the mesh or model less (a 2D model)", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("taxel: interrupted; finished points are kept, run again to resume", file=sys.stderr)
        return 130
    except Exception as exc:             # a bug: one line (TAXEL_DEBUG=1 shows the traceback)
        if os.environ.get("TAXEL_DEBUG"):
            raise
        print(f"taxel: internal error: {type(exc).__name__}: {_first_line(exc)} (TAXEL_DEBUG=1 for the "
              "traceback; please report it)", file=sys.stderr)
        return EXIT_FAILED
    return code or 0


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2 through main()."""

    def error(self, message):
        raise InputError(f"{message} (taxel {self.prog.partition(' ')[2] or ''} --help for usage)".replace("  ", " "))


def _first_line(exc) -> str:
    text = str(exc)
    return text.splitlines()[0] if text else type(exc).__name__


def _error(message: str) -> int:
    print(f"taxel: error: {message.splitlines()[0] if message else 'bad input'}", file=sys.stderr)
    return EXIT_INPUT


if __name__ == "__main__":
    sys.exit(main())
