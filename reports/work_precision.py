"""The work-precision folder and its report page: wall time against error, log-log,
one point per model and mesh (studies.work_precision), the Pareto set of the cheapest
for each accuracy marked, and the cheapest model for 1 %, 5 % and 10 % error.

Folder: work-precision.json (every point: model, time, unknowns, values, errors; the
reference; the cheapest per tolerance), work-precision.csv, and one chart per scene
and force (`<scene>-<force>N.png`, a panel per output).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from taxel.reports.figures import pyplot
from taxel.studies.work_precision import LABELS, OUTPUTS, Level, Point, WorkPrecision, cost

TOLERANCES = (0.01, 0.05, 0.10)
COLOURS = {"lumped": "tab:gray", "plane_stress": "tab:orange", "plane_strain": "tab:blue",
           "axisymmetric": "tab:green", "3d": "tab:red"}


def summary(wp: WorkPrecision) -> dict:
    """The cheapest model within each tolerance, per output, and the Pareto sets."""
    out = {}
    for k in OUTPUTS:
        if k not in wp.reference:
            continue
        ch = {f"{100 * t:g} %": (lambda p: None if p is None else {"model": p.level.label, "seconds": cost(p, k),
                                                                  "error": p.errors[k]})(wp.cheapest(k, t))
              for t in TOLERANCES}
        out[k] = {"cheapest": ch, "pareto": [p.level.label for p in wp.pareto(k)]}
    return out


def _panel(ax, wp: WorkPrecision, k: str):
    for p in wp.points:
        if k not in p.errors:
            continue
        ax.loglog(cost(p, k), max(p.errors[k], 1e-5), "o" if p.level.law == "linear" else "s",
                  color=COLOURS[p.level.model], ms=4 + p.level.order, alpha=0.75,
                  mfc="none" if p.level.order == 1 else COLOURS[p.level.model])
    front = wp.pareto(k)
    xs, ys = [cost(p, k) for p in front], [max(p.errors[k], 1e-5) for p in front]
    ax.loglog(xs, ys, "k-", lw=0.8)
    ax.loglog(xs, ys, "o", mfc="none", mec="k", ms=10)
    for t in TOLERANCES:
        ax.axhline(t, color="0.8", lw=0.6, ls="--")


def _legend(fig):
    plt = pyplot()
    handles = [plt.Line2D([], [], marker="o", ls="", color=c, label=m.replace("_", " ")) for m, c in COLOURS.items()]
    handles += [plt.Line2D([], [], marker="s", ls="", color="k", label="Yeoh silicone"),
                plt.Line2D([], [], marker="o", ls="", mfc="none", color="k", label="order 1 (hollow)"),
                plt.Line2D([], [], marker="o", ls="-", mfc="none", ms=10, color="k", label="Pareto set")]
    fig.legend(handles=handles, loc="outside lower center", ncol=8, fontsize=8)


def chart(wp: WorkPrecision, path: Path) -> Path:
    """Log-log wall time against error, a panel per output, the Pareto set joined."""
    plt = pyplot()
    outs = [k for k in OUTPUTS if k in wp.reference]
    fig, axes = plt.subplots(1, len(outs), figsize=(3.4 * len(outs), 3.6), constrained_layout=True)
    for ax, k in zip(np.atleast_1d(axes), outs):
        _panel(ax, wp, k)
        ax.set_title(LABELS[k], fontsize=9)
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel("error against the 3D reference (ratio)")
    _legend(fig)
    fig.suptitle(f"{wp.scene} at {wp.force:g} N: work against precision", fontsize=10)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def question(wps: list[WorkPrecision], k: str, path: Path) -> Path:
    """One question, one figure: which model is cheapest for output `k`? A panel per
    scene and force (forces in rows), every model in it, the 1/5/10 % lines labelled."""
    plt = pyplot()
    wps = [w for w in wps if k in w.reference]
    scenes = list(dict.fromkeys(w.scene for w in wps))
    forces = sorted({w.force for w in wps})
    fig, axes = plt.subplots(len(forces), len(scenes), figsize=(max(9.0, 3.6 * len(scenes) + 0.5), 3.1 * len(forces) + 0.9),
                             squeeze=False, sharex=True, sharey=True, layout="constrained")
    for ax in axes.flat:
        ax.set_axis_off()
    for w in wps:
        ax = axes[forces.index(w.force)][scenes.index(w.scene)]
        ax.set_axis_on()
        _panel(ax, w, k)
        ax.set_title(f"{w.scene}, {w.force:g} N", fontsize=9)
        ax.grid(True, which="major", alpha=0.3)
    for t in TOLERANCES:
        axes[0][0].annotate(f"{100 * t:g} %", (1, t), xycoords=("axes fraction", "data"), fontsize=7,
                            color="0.5", ha="right", va="bottom")
    for ax in axes[-1]:
        ax.set_xlabel("wall time (s)")
    for ax in axes[:, 0]:
        ax.set_ylabel("error against the 3D reference (ratio)")
    _legend(fig)
    fig.suptitle(f"Which model is cheapest for the {LABELS[k]}?", fontsize=11)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def questions(wps: list[WorkPrecision], folder: Path, stem: str = "work-precision") -> list[Path]:
    """One figure per output (`question`): FOLDER/<stem>-<output>.png."""
    folder = Path(folder)
    return [question(wps, k, folder / f"{stem}-{k.replace('_', '-')}.png") for k in OUTPUTS
            if any(k in w.reference for w in wps)]


def grid(wps: list[WorkPrecision], path: Path) -> Path:
    """Every scene and force in one figure: a row each, a column per output (on
    request: benchmarks/work_precision.py --grid; `questions` is the readable form)."""
    plt = pyplot()
    fig, axes = plt.subplots(len(wps), len(OUTPUTS), figsize=(2.9 * len(OUTPUTS), 2.3 * len(wps)),
                             constrained_layout=True, squeeze=False)
    for row, wp in zip(axes, wps):
        for ax, k in zip(row, OUTPUTS):
            if k in wp.reference:
                _panel(ax, wp, k)
            else:
                ax.set_axis_off()
            ax.set_xlabel("wall time (s)", fontsize=7)
            ax.set_ylabel("error (ratio)", fontsize=7)
            ax.tick_params(labelsize=6)
            ax.set_title(f"{wp.scene} {wp.force:g} N: {LABELS[k]}", fontsize=7)
    _legend(fig)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def write(wps: list[WorkPrecision], out: Path) -> list[Path]:
    """work-precision.json, work-precision.csv and the charts into `out`."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    recs, files = [], []
    with open(out / "work-precision.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scene", "force_N", "model", "order", "mesh", "law", "seconds", "sweep_seconds", "unknowns",
                    *[f"{k}_value" for k in OUTPUTS], *[f"{k}_error" for k in OUTPUTS]])
        for wp in wps:
            for p in wp.points:
                lv = p.level
                w.writerow([wp.scene, wp.force, lv.model, lv.order, lv.mesh, lv.law, f"{p.seconds:.4g}",
                            "" if p.sweep_seconds is None else f"{p.sweep_seconds:.4g}", p.unknowns,
                            *[f"{p.values[k]:.9g}" if k in p.values else "" for k in OUTPUTS],
                            *[f"{p.errors[k]:.6g}" if k in p.errors else "" for k in OUTPUTS]])
            png = chart(wp, out / f"{wp.scene}-{wp.force:g}N.png")
            files.append(png)
            recs.append({"scene": wp.scene, "force_N": wp.force, "reference": wp.reference, "how": wp.how,
                         "summary": summary(wp)})
    (out / "work-precision.json").write_text(json.dumps({"work_precision": recs}, indent=1))
    return [out / "work-precision.json", out / "work-precision.csv", *files]


def cheapest_rows(rec: dict) -> list[dict]:
    """One row per scene, force and output: the cheapest model for 1, 5 and 10 %."""
    rows = []
    for wp in rec["work_precision"]:
        for k, s in wp["summary"].items():
            row = {"scene": wp["scene"], "force (N)": wp["force_N"], "output": LABELS[k]}
            for t, c in s["cheapest"].items():
                row[f"cheapest within {t}"] = "none" if c is None else f"{c['model']} ({c['seconds']:.2g} s)"
            rows.append(row)
    return rows


def lines(rec: dict) -> list[str]:
    out = []
    for r in cheapest_rows(rec):
        out.append(f"{r['scene']} {r['force (N)']:g} N, {r['output']}: " + "; ".join(
            f"{k.removeprefix('cheapest within ')}: {v}" for k, v in r.items() if k.startswith("cheapest")))
    return out


def chart_files(folder: Path) -> tuple[Path, Path] | None:
    """(work-precision.json, work-precision.csv) of a folder, or None when it holds no
    chart."""
    folder = Path(folder)
    if (folder / "work-precision.json").is_file():
        return folder / "work-precision.json", folder / "work-precision.csv"
    return None


def read(folder: Path) -> list[WorkPrecision]:
    """The WorkPrecision of each scene and force, back from a written folder
    (work-precision.json and work-precision.csv): redraws without solving."""
    folder = Path(folder)
    files = chart_files(folder)
    if files is None:
        raise FileNotFoundError(2, "no work-precision chart here (work-precision.json)", str(folder))
    rec = json.loads(files[0].read_text())
    rows = list(csv.DictReader(open(files[1])))
    out = []
    for w in rec["work_precision"]:
        pts = []
        for r in rows:
            if r["scene"] != w["scene"] or float(r["force_N"]) != w["force_N"]:
                continue
            pt = Point(Level(r["model"], int(r["order"]), r["mesh"], r["law"]), float(r["seconds"]),
                       int(r["unknowns"]), {k: float(r[f"{k}_value"]) for k in OUTPUTS if r[f"{k}_value"]},
                       float(r["sweep_seconds"]) if r["sweep_seconds"] else None)
            pt.errors = {k: float(r[f"{k}_error"]) for k in OUTPUTS if r[f"{k}_error"]}
            pts.append(pt)
        out.append(WorkPrecision(w["scene"], w["force_N"], pts, w["reference"], w["how"]))
    return out
