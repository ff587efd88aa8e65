"""`taxel study`, `taxel optimize`, `taxel report`, `taxel demo`: many solves, each
command a thin shell over taxel.api (and the main job, taxel.jobs)."""

from __future__ import annotations

from pathlib import Path

from taxel.cli.files import EXIT_FAILED, InputError, number

WORKERS = number(1, 256, integer=True)   # --workers: local Dask workers


def register(sub) -> None:
    p = sub.add_parser("study", help="parameter studies: run, status, export")
    p.add_argument("action", choices=["run", "status", "export"])
    p.add_argument("target", help="run: a study TOML file or built-in study name; status/export: a study folder")
    p.add_argument("--out", metavar="DIR", help="run: the study folder (default out/NAME)")
    p.add_argument("--workers", type=WORKERS, default=2, help="local Dask workers (1: in-process)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler (tcp://host:8786)")
    p.add_argument("--retry-failed", action="store_true", help="rerun the points that failed before")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--csv", metavar="FILE", help="export: the CSV to write")
    p.set_defaults(run=_study)
    p = sub.add_parser("optimize", help="optimize a design (nlopt), or its sensitivity-crosstalk front")
    p.add_argument("file", help="an optimization TOML file or a built-in name")
    p.add_argument("--out", metavar="DIR", help="results folder (default out/NAME); its store caches every design")
    p.add_argument("--workers", type=WORKERS, default=2, help="Dask workers for the front's runs")
    p.set_defaults(run=_optimize)
    p = sub.add_parser("report", help="self-contained HTML reports of result folders, and an index")
    p.add_argument("folders", nargs="+", help="study, optimization or solve folders")
    p.add_argument("--out", required=True, metavar="DIR")
    p.add_argument("--pdf", action="store_true", help="also a PDF of each page (needs Chromium)")
    p.add_argument("--no-compare", action="store_true", help="skip the model comparison (faster)")
    p.set_defaults(run=_report)
    p = sub.add_parser("demo", help="the main job: thesis study, optimization, dynamics and the report")
    p.add_argument("--out", default="out/demo", metavar="DIR")
    p.add_argument("--small", action="store_true", help="a small run (for CI)")
    p.add_argument("--full", action="store_true", help="also the thesis-model Fig. 2.5/2.8 studies and the probe fronts verified by 3D presses (slow)")
    p.add_argument("--presses-3d", type=number(0, integer=True), default=0, metavar="N",
                   help="press N designs of each probe front in 3D (default 0; --full presses them all)")
    p.add_argument("--no-answer-3d", dest="answer_3d", action="store_false",
                   help="skip the answer's 3D presses by the rig's probe (about 50 s on 2 cores): the answer's "
                        "numbers are then the candidate selection's estimate, and it says so")
    p.set_defaults(run=_demo)


def _study(args):
    import taxel.api as api
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
    import taxel.api as api
    result = api.run_optimization(args.file, args.out, workers=args.workers)
    for line in result.summary():
        print(line)
    print(f"written to {Path(args.out or Path('out') / result.name)}")
    return 0 if result.kind == "front" or result.success else EXIT_FAILED


def _report(args):
    import taxel.api as api
    index = api.report(args.folders, Path(args.out), pdf=args.pdf, compare=not args.no_compare)
    print(f"report: {index.resolve()}")


def _demo(args):
    from taxel.jobs.main_job import run
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: exists and is not a folder; choose another output folder")
    run(out, small=args.small, full=args.full, presses_3d=args.presses_3d, answer_3d=args.answer_3d)
