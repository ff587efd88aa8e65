"""The `taxel` command.

    taxel solve SCENE [--json] [--vtu FILE] [--solver NAME] [--out DIR]
    taxel lumped SCENE [--out DIR]
    taxel mesh SCENE -o FILE          (.msh with physical groups, or .vtu/.xdmf via meshio)
    taxel study run STUDY [--out DIR] [--workers N] [--scheduler ADDR] [--retry-failed]
    taxel study status DIR | taxel study export DIR --csv FILE
    taxel optimize OPT [--out DIR] [--workers N]
    taxel report DIR... --out OUT [--pdf]
    taxel demo [--out DIR] [--small]
    taxel examples

SCENE is a TOML file or the name of a built-in example. Bad input exits with
code 2 and one line naming the problem and the fix.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from taxel import api
from taxel.scene import SceneError, examples
from taxel.units import engineering as si

EXIT_INPUT, EXIT_FAILED = 2, 1


def _print_output(files, summary):
    for line in summary:
        print(line)
    for f in files:
        print(f"wrote {f}")


def _out_dir(args, scene):
    out = Path(args.out or Path("out") / scene.name)
    out.mkdir(parents=True, exist_ok=True)
    return out


def _solve(args):
    from taxel.meshing.build import export
    from taxel.reports import analysis
    scene = api.load(args.scene)
    if scene.analysis.type != "static":
        _print_output(*analysis.write(api.solve(scene), _out_dir(args, scene)))
        return
    sol = api.solve(scene, solver=args.solver)
    if args.vtu:
        export(sol.mesh, args.vtu, point_data={"u": sol.fields.u, "phi": sol.fields.phi},
               cell_data={"strain": sol.fields.strain, "stress": sol.fields.stress})
    if args.out:
        sol.to_folder(_out_dir(args, scene))
    if args.json:
        print(json.dumps(sol.record()))
        return
    print(sol)
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
        linear = sol.newton is None
        print(f"largest silicone strain {100 * sol.max_silicone_strain:.1f} %"
              + (f" (a linear silicone errs by about {100 * est:.2g} % here; model.silicone = 'auto' or "
                 "'yeoh' to do better)" if linear and est > 0.02 else ""))
    if args.vtu:
        print(f"fields written to {args.vtu}")


def _lumped(args):
    from taxel.analyses import lumped_response
    from taxel.reports import analysis
    scene = api.load(args.scene)
    _print_output(*analysis.write(lumped_response(scene), _out_dir(args, scene)))


def _study(args):

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
            spec = StudySpec.model_validate_json((out / "study.json").read_text())
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
    import numpy as np

    from taxel.analyses.results import write_scene
    from taxel.optimize import problem as O
    from taxel.reports.optimization import write_front, write_run
    from taxel.scene import parse
    from taxel.studies.store import Store
    path = args.file
    probe = O.load_problem(path)
    out = Path(args.out or Path("out") / probe.spec.name)
    out.mkdir(parents=True, exist_ok=True)
    prob = O.load_problem(path, out)
    write_scene(out, parse({**prob.scene_data(prob.x0), "name": prob.spec.name}))
    resolved = path if Path(path).is_file() else O.BUILTIN / f"{path}.toml"
    reference = None
    if prob.spec.reference:
        x_ref = np.array([O.magnitude(prob.spec.reference[n], u, f"reference.{n}")[0]
                          for n, u in zip(prob.names, prob.units)])
        reference = {"x": dict(zip(prob.names, x_ref.tolist())), **prob.evaluate(x_ref)}
        print(f"reference design {reference['x']}: sensitivity {reference['sensitivity']:.4g} V/N, "
              f"crosstalk {100 * reference['crosstalk']:.2f} %")
    if prob.spec.pareto:
        runs = O.front(prob, resolved, workers=args.workers)
        rows, nd = write_front(prob, runs, reference, out)
        for r in rows:
            print(f"  crosstalk <= {100 * r['crosstalk_bound']:.2f} %: sensitivity {r['sensitivity_V_per_N']:.4g} V/N, "
                  f"crosstalk {100 * r['crosstalk']:.2f} %, "
                  + ", ".join(f"{n} {r[f'{n} ({u})']:.3g} {u}" for n, u in zip(prob.names, prob.units)))
        if reference:
            dominated = any(s >= reference["sensitivity"] * (1 + 1e-3) and c <= reference["crosstalk"] * (1 - 1e-3)
                            for s, c in nd)
            print(f"the reference design is {'DOMINATED (not on the front)' if dominated else 'on the front'}")
        store = Store(out)
        solves = len(store.rows())
        store.close()
        print(f"front: {len(rows)} runs, {sum(r.nfev for _, r in runs)} optimizer evaluations, "
              f"{solves} distinct FEM solves in the store; {out / 'pareto.png'}")
        return 0
    result = O.optimize(prob)
    rec = write_run(prob, result, out)
    print(f"{'optimum' if result.success else 'best found (constraints violated)'}: "
          + ", ".join(f"{n} = {v:.4g}" for n, v in rec["x"].items())
          + f"; {result.nfev} evaluations; {result.message}")
    print("metrics: " + ", ".join(f"{k} {v:.4g}" for k, v in result.metrics.items() if v is not None))
    return 0 if result.success else EXIT_FAILED


def _report(args):
    index = api.report(args.folders, Path(args.out), pdf=args.pdf, compare=not args.no_compare)
    print(f"report: {index.resolve()}")


def _demo(args):
    from taxel.reports.main_job import run
    run(Path(args.out), small=args.small)


def _mesh(args):
    from taxel.analyses.geometry import layout
    from taxel.analyses.problem import scene_materials
    from taxel.meshing.build import build, export
    scene = api.load(args.scene)
    out = Path(args.output)
    lay = layout(scene, scene_materials(scene))
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


def _material_fit_yeoh(args):
    from taxel.fem.yeoh_fit import COMPRESSION_STRETCH, fit_yeoh, stability_losses
    from taxel.reports.figures import yeoh_fit as plot_fit
    from taxel.studies.uniaxial import read_uniaxial
    max_strain = parse_strain("--max-strain", args.max_strain)
    check = parse_strain("--check-strain", args.check_strain) if args.check_strain else 2.0 * max_strain
    strain, stress = read_uniaxial(args.file)
    fit = fit_yeoh(strain, stress, max_strain)
    lost = stability_losses(fit, (COMPRESSION_STRETCH, 1.0 + check))
    span = f"{100 * (COMPRESSION_STRETCH - 1):+.0f} % (stretch {COMPRESSION_STRETCH:g}) to {100 * check:+.0f} % strain"
    warnings = [f"WARNING: unstable in {r['mode']} {r['direction']} beyond {100 * r['strain']:+.1f} % strain "
                f"(stretch {r['stretch']:.3f}, {r['reason']}), inside the checked range {span}"
                for r in lost]
    if args.plot:
        try:
            plot_fit(strain, stress, fit, args.plot, check_strain=check,
                     title=f"{Path(args.file).name}: Yeoh fit to {100 * max_strain:g} %")
        except OSError as exc:
            raise ValueError(f"cannot write plot {args.plot}: {exc.strerror or exc}") from None
    if args.json:
        rec = {"file": str(args.file), "C10_Pa": fit.C10, "C20_Pa": fit.C20, "C30_Pa": fit.C30,
               "r2": fit.r2, "n_points": fit.n_points, "rms_Pa": fit.rms_Pa, "max_strain": fit.max_strain,
               "check_strain": check, "check_stretch_min": COMPRESSION_STRETCH,
               "stability_lost": lost, "plot": args.plot}
        print(json.dumps(rec))
        for w in warnings:
            print(w, file=sys.stderr)
        return
    print(f"Yeoh fit to {args.file}: engineering strain vs nominal stress, "
          f"{fit.n_points} points with 0 < strain <= {100 * max_strain:g} %")
    print(f"C10 = {fit.C10 / 1e3:.4g} kPa, C20 = {fit.C20 / 1e3:.4g} kPa, C30 = {fit.C30 / 1e3:.4g} kPa"
          f"  (mu = 2 C10 = {2 * fit.C10 / 1e3:.4g} kPa)")
    print(f"R^2 = {fit.r2:.5f}, RMS error {si(fit.rms_Pa, 'Pa')} over {fit.n_points} points")
    if not lost:
        print(f"stable in uniaxial, equibiaxial and pure shear from {span}")
    for w in warnings:
        print(w)
    if args.plot:
        print(f"plot written to {args.plot}")


def parse_strain(option: str, text) -> float:
    """A strain given as a fraction ('0.5') or a percentage ('50%', '50 %'); must be finite and > 0.

    Raises ValueError with one line naming `option` otherwise.
    """
    import math
    t = str(text).strip()
    pct = t.endswith("%")
    try:
        value = float(t.rstrip("%").strip()) / (100.0 if pct else 1.0)
    except ValueError:
        raise ValueError(f"{option} must be a number such as 0.5 or '50%', got '{text}'") from None
    if not (value > 0 and math.isfinite(value)):
        raise ValueError(f"{option} must be a positive strain (0.5 = 50 %), got '{text}'")
    return value


def main(argv=None):
    ap = argparse.ArgumentParser(prog="taxel", description="Piezoelectric tactile sensor design tool")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("solve", help="solve a scene and print per-electrode voltage and charge")
    p.add_argument("scene", help="scene TOML file or built-in example name")
    p.add_argument("--json", action="store_true", help="print one JSON record")
    p.add_argument("--vtu", metavar="FILE", help="write displacement, potential, strain and stress fields")
    p.add_argument("--solver", default="auto", choices=["auto", "superlu", "pardiso", "umfpack", "krylov"])
    p.add_argument("--out", metavar="DIR", help="folder for the outputs (scene.json, result.json; CSV and PNG "
                   "of frequency/transient analyses; default for those: out/SCENE)")
    p.set_defaults(run=_solve)
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
    p.set_defaults(run=_demo)
    p = sub.add_parser("examples", help="list the built-in example scenes")
    p.set_defaults(run=_examples)
    p = sub.add_parser("material", help="material tools (hyperelastic fits)")
    msub = p.add_subparsers(dest="material_command", required=True)
    p = msub.add_parser("fit-yeoh", help="fit an incompressible Yeoh law to a uniaxial tensile test")
    p.add_argument("file", help="CSV with engineering strain and engineering (nominal) stress columns")
    p.add_argument("--max-strain", default="0.5", metavar="S",
                   help="fit points with 0 < strain <= S (fraction, or percent as '50%%'); default 0.5")
    p.add_argument("--check-strain", metavar="S", default=None,
                   help="check stability up to this tensile strain (default 2 x max strain) "
                        "and down to stretch 0.5 in compression")
    p.add_argument("--plot", metavar="OUT.png", help="write a plot of the data and the fit")
    p.add_argument("--json", action="store_true", help="print one JSON record")
    p.set_defaults(run=_material_fit_yeoh)
    args = ap.parse_args(argv)
    try:
        code = args.run(args)
    except SceneError as exc:
        print(f"taxel: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except (ValueError, KeyError) as exc:
        print(f"taxel: error: {exc.args[0] if exc.args else exc}", file=sys.stderr)
        return EXIT_INPUT
    except RuntimeError as exc:          # includes fem.newton.NewtonError
        print(f"taxel: failed: {exc}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("taxel: interrupted; finished points are kept, run again to resume", file=sys.stderr)
        return 130
    return code or 0


if __name__ == "__main__":
    sys.exit(main())
