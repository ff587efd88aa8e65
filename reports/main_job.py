"""The main job behind `make demo` (`taxel demo`): on the built-in example, run the
thesis's Fig. 2.5 study, the sensitivity-crosstalk fronts of the thesis PZT and
PVDF designs (2D, then verified in 3D: optimize.multifidelity),
the frequency response through the charge amplifier and the step response
through the 500 MOhm input, the validation loop on the simulated rig (simulate,
capture over a pty, analyze, calibrate, localize: studies.measured.pipeline),
then build the report; `small` is the reduced run
CI uses."""

from __future__ import annotations

import shutil
import time
from pathlib import Path

import numpy as np

from taxel.analyses import solve
from taxel.analyses.results import write_scene
from taxel.optimize import multifidelity as MF
from taxel.optimize import spec as O
from taxel.reports import analysis
from taxel.reports.build import build
from taxel.reports.figures import study_plots
from taxel.reports.multifidelity import write as write_mf
from taxel.reports.optimization import write_front, write_run
from taxel.scene import load, parse
from taxel.studies.execute import run as run_study
from taxel.studies.measured.pipeline import run as validate
from taxel.studies.spec import load_study
from taxel.studies.store import tidy_rows, write_rows


def _front(out: Path, name: str, small: bool) -> Path:
    """The cheap (2D) front of a built-in problem, then its 3D verification
    (optimize.multifidelity); `small`: one short run, no front."""
    out.mkdir(exist_ok=True)
    prob = O.load_optimization(name, out)
    write_scene(out, parse({**prob.scene_data(prob.x0), "name": prob.spec.name}))
    x_ref = np.array([O.magnitude(prob.spec.reference[n], u)[0] for n, u in zip(prob.names, prob.units)])
    reference = {"x": dict(zip(prob.names, x_ref.tolist())), **prob.evaluate(x_ref)}
    if small:
        prob.spec = prob.spec.model_copy(update={"algorithm": prob.spec.algorithm.model_copy(
            update={"max_evaluations": 6, "global_": "none"})})
        write_run(prob, O.optimize(prob), out)
        return out
    plan = MF.plan(prob)
    print(f"      {name}: plan {plan['cheap solves (at most)']} cheap solves at most, "
          f"{plan['3D solves (first round)']} 3D solves, about {plan['estimated seconds']:.0f} s")
    t0 = time.perf_counter()
    runs = O.front(prob, O.BUILTIN / f"{name}.toml", workers=2)
    write_front(prob, runs, reference, out)
    t1 = time.perf_counter()
    mf = MF.confirm(prob, MF.verify(prob, runs, x_ref, max_rounds=2, workers=2), workers=2)
    rec = write_mf(prob, mf, out)
    print(f"      cheap front {t1 - t0:.0f} s; 3D verification {mf.spent['3D solves']} solves in "
          f"{len(mf.rounds)} rounds, {mf.spent['seconds']:.0f} s; confirmation on the finer 3D mesh "
          f"{mf.spent.get('confirmation solves', 0)} solves, {mf.spent.get('confirmation seconds', 0):.0f} s")
    print(f"      {rec['sentence']}")
    return out


def run(root: Path, small: bool = False) -> Path:
    """Run the main job into `root` and return the report's index page."""
    t0 = time.perf_counter()
    started = time.strftime("%Y-%m-%d %H:%M:%S")
    root.mkdir(parents=True, exist_ok=True)
    folders = []
    print("[1/5] thesis Fig. 2.5 study (silicone thickness x force x material, 2D plane stress)")
    st = load_study("fig-2-5")
    if small:
        st.spec = st.spec.model_copy(update={"parameters": [
            p.model_copy(update={"values": p.values[:1], "labels": (p.labels or [None])[:1] if p.labels else None})
            if p.values else p.model_copy(update={"step": None, "num": 2}) for p in st.spec.parameters]})
    out = root / "fig-2-5"
    out.mkdir(exist_ok=True)
    (out / "study.json").write_text(st.spec.model_dump_json(indent=1))
    write_scene(out, parse({**st.base_data(), "name": st.spec.name}))
    summ = run_study(st, out, workers=1 if small else 2, progress=True)
    rows = tidy_rows(out)
    write_rows(rows, out / "results.csv")
    study_plots(rows, [p.name for p in st.spec.parameters], ["voltage_pressed", "max_strain"], out / "plots",
                st.spec.name)
    folders.append(out)
    print(f"      {summ.total} points ({summ.cached} cached) in {summ.seconds:.1f} s")
    print("[2/5] optimization: the thesis designs against the sensitivity-crosstalk front, verified in 3D")
    for name in ("thesis-pzt-front",) if small else ("thesis-pzt-front", "thesis-pvdf-front"):
        folders.append(_front(root / name, name, small))
    print("[3/5] frequency response through the charge amplifier and notch; step through 500 MOhm")
    for name in ("thesis-pzt-frequency", "thesis-pzt-step"):
        scene = load(name)
        if small:
            scene = scene.replace(**{"analysis.points": 20, "analysis.duration": 0.05})
        out = root / name
        files, summary = analysis.write(solve(scene), out)
        for line in summary:
            print(line)
        folders.append(out)
    print("[4/5] validation on the simulated rig: simulate -> capture over a pty -> analyze -> calibrate -> localize")
    shutil.rmtree(root / "validation", ignore_errors=True)
    validate(root / "validation")
    folders.append(root / "validation")
    print("[5/5] report")
    what = ("taxel demo" + (" --small" if small else "") + ": thesis Fig. 2.5 study, sensitivity-crosstalk "
            "front, frequency response, step response, validation on the simulated rig")
    index = build(folders, root / "report", compare=not small,
                  run={"what": what, "started": started, "seconds": time.perf_counter() - t0})
    print(f"done in {time.perf_counter() - t0:.0f} s; open {index.resolve()}")
    return index
