"""The main job behind `make demo` (`taxel demo`): on the built-in example, run the
thesis's Fig. 2.5 study, the sensitivity-crosstalk fronts of the thesis PZT and
PVDF designs (2D, then verified in 3D: optimize.multifidelity; under the rig's probe:
optimize.probe_front), the answer's designs pressed in 3D by the probe (taxel.jobs.answer_3d),
the frequency
response through the charge amplifier and the step response through the 500 MOhm
input, the validation loop on the simulated rig (simulate, capture over a pty,
analyze, calibrate, localize: studies.measured.pipeline), then build the report;
`small` is the small run CI uses. Each step is a call of the API (taxel.api:
run_study, run_optimization, solve, report).

Scheduling (the job's time: benchmarks/demo_time.py, docs/getting-started.md): the validation
runs in a process of its own from the start (its capture waits on the wall clock); the two
materials' fronts run side by side in two more, each with its own Dask pools; their cheap
fronts judge the coverage of the reference design only, the answer's designs are judged by
taxel.jobs.answer_coverage; the answer's coverage and 3D presses share one pool
(taxel.jobs.answer_3d), both materials' friction bands another (taxel.jobs.friction_band)."""

from __future__ import annotations

import os
import shutil
import time
from pathlib import Path

from taxel import api
from taxel.optimize import multifidelity as MF
from taxel.optimize import probe_front as PF
from taxel.optimize import spec as O
from taxel.optimize.run import reference_x
from taxel.reports.multifidelity import draw as draw_verified_front, draw_probe as draw_probe_front
from taxel import measure
from taxel.jobs.friction_band import friction_bands
from taxel.studies.spec import Study, load_study

STUDY_PLOTS = ("pressed_voltage", "max_strain")
THESIS_MODEL_STUDIES = ("fig-2-5-thesis", "fig-2-8-thesis")     # about an hour each on 2 workers: --full


def small_study(st: Study) -> Study:
    """The study cut down for `--small`: the first value of each listed parameter, two of each range."""
    st.spec = st.spec.model_copy(update={"parameters": [
        p.model_copy(update={"values": p.values[:1], "labels": (p.labels or [None])[:1] if p.labels else None})
        if p.values else p.model_copy(update={"step": None, "num": 2}) for p in st.spec.parameters]})
    return st


def small_optimization(name: str) -> O.Optimization:
    """A built-in optimization cut down to one short local run (6 evaluations, no front)."""
    prob = O.load_optimization(name)
    prob.spec = prob.spec.model_copy(update={"pareto": None, "algorithm": prob.spec.algorithm.model_copy(
        update={"max_evaluations": 6, "global_": "none"})})
    return prob


def front(out: Path, name: str, small: bool, full: bool = False, presses_3d: int = PF.RUN_3D_PRESSES) -> Path:
    """The cheap (2D) front of a built-in problem (taxel.optimize), its 3D
    verification (optimize.multifidelity), then the headline: the same designs under
    the rig's probe on Yeoh silicone (optimize.probe_front, the built-in
    NAME-probe-front spec; `presses_3d` of its front designs pressed in 3D, every
    front design and the thesis design with `full`), written to OUT/probe-front.json;
    `small`: one short run, no front."""
    if small:
        api.run_optimization(small_optimization(name), out)
        return out
    plan = MF.plan(O.load_optimization(name))
    print(f"      {name}: plan {plan['cheap solves (at most)']} cheap solves at most, "
          f"{plan['3D solves (first round)']} 3D solves, about {plan['estimated seconds']:.0f} s")
    t0 = time.perf_counter()
    result = api.run_optimization(name, out, workers=2, influence="reference")   # the answer's: answer_coverage
    t1 = time.perf_counter()
    prob = O.load_optimization(name, out)
    mf = MF.verify(prob, result.runs, reference_x(prob), max_rounds=2, workers=2)
    if full:                           # the answer is the 3D probe presses' (answer_3d): the finer linear mesh only with --full
        mf = MF.confirm(prob, mf, workers=2)
    rec = mf.to_folder(out, prob)
    draw_verified_front(mf, prob.spec.name, out)
    print(f"      cheap front {t1 - t0:.0f} s; " + "; ".join(mf.summary()))
    print(f"      {rec['sentence']}")
    probe = O.load_optimization(name.replace("-front", "-probe-front"), out)
    pf = PF.probe_front(probe, mf, result.runs, reference_x(prob), presses_3d=None if full else presses_3d,
                        workers=2, max_rounds=2)
    prec = pf.to_folder(out, probe)
    draw_probe_front(pf, mf, probe.spec.name, out)
    s = pf.spent
    print(f"      probe front ({pf.level}): {s['2D presses']} 2D presses in {s['2D press seconds']:.0f} s, "
          f"{s['3D presses']} 3D presses in {s['3D press seconds']:.0f} s, against "
          f"{s['3D solves if every candidate were pressed in 3D']} 3D presses for every candidate")
    for line in pf.summary(probe):
        print("      " + line)
    print(f"      {prec['sentence']}", flush=True)
    return out


def noise_budget(out: Path, small: bool = False) -> Path:
    """The noise budget of the thesis PZT taxel (FEM transfer function, charge amplifier and
    notch) on the thesis bench's ADC, with the simulated rig's hum (5, 1.5, 0.5 mV at 50, 150,
    250 Hz) as the mains pickup: result folder and figure (taxel.analyses.solves.noise, reports.noise)."""
    from taxel.analyses.solves.noise import noise
    from taxel.reports.noise import figure
    from taxel.studies.bench.rig import load_rig
    t0 = time.perf_counter()
    from taxel.studies.bench.signals import Settings
    scene = api.load("thesis-pzt-frequency").replace(**{"readout.hum": list(Settings().hum_V)})   # the rig's hum
    res = noise(scene, load_rig("thesis-bench"), model="lumped" if small else "fem")
    shutil.rmtree(out, ignore_errors=True)
    res.to_folder(out)
    figure(out)
    for line in res.summary()[:3]:
        print("      " + line)
    print(f"      noise budget in {time.perf_counter() - t0:.1f} s")
    return out


def tolerances(out: Path) -> Path:
    """The yield and Sobol' indices of the thesis PZT design (2D row, 16 parts on the study
    store: silicone above +-0.1 mm uniform, gap +-0.2 mm and piezo thickness +-5 % normal;
    studies.tolerance, studies.yield_analysis): OUT/tolerance.json."""
    from taxel.studies.execute import run as run_points
    from taxel.studies.store import Store
    from taxel.studies.yield_analysis import from_study
    t0 = time.perf_counter()
    out.mkdir(parents=True, exist_ok=True)
    st = load_study("thesis-pzt-tolerances")          # studies/builtin/thesis-pzt-tolerances.toml
    run_points(st, out / "points", workers=1, progress=False)
    store = Store(out / "points")
    try:
        res = from_study(st, store)
    finally:
        store.close()
    res.to_folder(out)
    for line in res.summary():
        print("      " + line)
    print(f"      tolerances in {time.perf_counter() - t0:.1f} s")
    return out


def front_logged(out: Path, name: str, full: bool, presses_3d: int) -> tuple[Path, str]:
    """`front` (not small) with its stage lines returned, not printed: the main job runs the
    two materials' fronts side by side (`run`), each in a process with its own Dask pools, so
    that one's serial steps (its reference design's map, its figures, a pool's last task)
    overlap the other's solves; their lines are printed whole, one front after the other."""
    import contextlib
    import io
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        path = front(out, name, False, full, presses_3d)
    return path, buf.getvalue()


def validation(out: Path) -> tuple[list[str], float]:
    """The validation loop on the simulated rig (measure.validate) into `out`: its progress
    lines and seconds. The main job runs it in a process of its own from the start (`run`):
    its capture waits on the wall clock (the simulated rig streams in real time: 54 s of
    wall, 34 s of CPU alone), which the other steps' compute fills."""
    t0 = time.perf_counter()
    lines: list[str] = []
    shutil.rmtree(out, ignore_errors=True)
    measure.validate(out, progress=lines.append)
    return lines, time.perf_counter() - t0


def _cpu() -> str:
    """" (CPU 123 s)": this process's CPU seconds and its finished workers' (os.times), for the stage log."""
    t = os.times()
    return f" (CPU so far {t.user + t.system + t.children_user + t.children_system:.0f} s)"


def run(root: Path, small: bool = False, full: bool = False, presses_3d: int = PF.RUN_3D_PRESSES,
        answer_3d: bool = True) -> Path:
    """Run the main job into `root` and return the report's index page; `full`: also the
    thesis-model Fig. 2.5 and 2.8 studies (plane stress, Yeoh beside linear silicone; about
    10 minutes each), the probe fronts verified by 3D presses and the linear front's
    confirmation on a finer mesh; `answer_3d` (off with `taxel demo --no-answer-3d`): the
    answer's designs, the recommended and the thesis design of each material, pressed in 3D
    by the rig's probe beside their coverage's 3D maps (taxel.jobs.answer_3d; the step's time
    in docs/getting-started.md); without them the answer is the candidate-selection model's,
    and says so."""
    from concurrent.futures import ProcessPoolExecutor
    from multiprocessing import get_context
    root.mkdir(parents=True, exist_ok=True)
    with ProcessPoolExecutor(3, mp_context=get_context("spawn")) as side:   # the validation and the fronts
        return _run(root, small, full, presses_3d, answer_3d, side, side.submit(validation, root / "validation"))


def _run(root: Path, small: bool, full: bool, presses_3d: int, answer_3d: bool, side, validated) -> Path:
    t0 = time.perf_counter()
    started = time.strftime("%Y-%m-%d %H:%M:%S")
    root.mkdir(parents=True, exist_ok=True)
    folders = []
    print("[1/5] thesis Fig. 2.5 study (silicone thickness x force x material, 2D plane stress)")
    st = load_study("fig-2-5")
    st = small_study(st) if small else st
    summ = api.run_study(st, root / "fig-2-5", workers=1 if small else 2, progress=True, plots=STUDY_PLOTS)
    folders.append(summ.folder)
    print(f"      {summ.total} points ({summ.cached} cached) in {summ.seconds:.1f} s")
    for name in THESIS_MODEL_STUDIES:  # the thesis's own model: plane stress, Yeoh beside linear
        if full:
            summ = api.run_study(load_study(name), root / name, workers=2, progress=True)
            folders.append(summ.folder)
            print(f"      {name}: {summ.total} points ({summ.cached} cached) in {summ.seconds:.1f} s")
        elif not small and (root / name / "results.csv").exists():     # from an earlier --full (or taxel study run)
            folders.append(root / name)
            print(f"      {name}: from an earlier run in {root / name} (taxel demo --full runs it)")
    print("[2/5] optimization: the thesis designs against the sensitivity-crosstalk front, verified in 3D" + _cpu())
    if small:
        folders.append(front(root / "thesis-pzt-front", "thesis-pzt-front", small, full, presses_3d))
    else:                              # the two materials side by side, each in a process of its own
        done = [side.submit(front_logged, root / n, n, full, presses_3d) for n in ("thesis-pzt-front",
                                                                                    "thesis-pvdf-front")]
        for fut in done:
            path, log = fut.result()
            print(log, end="", flush=True)
            folders.append(path)
    if not small:                      # the answer's coverage decides its designs, pressed in 3D (their 3D views)
        from taxel.jobs.answer_3d import answer_designs
        folders += answer_designs(root, ["thesis-pzt-front", "thesis-pvdf-front"], workers=2, press=answer_3d)
        print(f"     {_cpu()}")
    if not small:                      # the answer's designs through the bench's readout (one 2D solve each)
        from taxel.jobs.answer_readout import answer_readout
        t3 = time.perf_counter()
        for name in ("thesis-pzt-front", "thesis-pvdf-front"):
            answer_readout(root / name)
        print(f"      the answer's designs through the bench's readout in {time.perf_counter() - t3:.0f} s")
        friction_bands([root / "thesis-pzt-front", root / "thesis-pvdf-front"], workers=2)   # frictionless to sticking
    from taxel.jobs.warm_touch import warm_touch      # a warm finger on each thesis design (2D, a few s each)
    print(f"      the answer's warm touch in {sum(warm_touch(f) for f in folders if f.name.endswith('-front')):.0f} s")
    print("[3/5] frequency response through the charge amplifier and notch; step through 500 MOhm" + _cpu())
    for name in ("thesis-pzt-frequency", "thesis-pzt-step"):
        scene = api.load(name)
        if small:
            scene = scene.replace(**{"analysis.points": 20, "analysis.duration": 0.05})
        out = root / name
        for line in api.solve(scene, out=out).summary():
            print(line)
        folders.append(out)
    folders.append(noise_budget(root / "noise-budget", small))
    tolerances(root / "tolerances")
    print("[4/5] validation on the simulated rig: simulate -> capture over a pty -> analyze -> calibrate -> localize" + _cpu())
    lines, seconds = validated.result()
    for line in lines:
        print(line)
    print(f"      validation on the simulated rig in {seconds:.0f} s (its own process, from the job's start)")
    folders.append(root / "validation")
    print("[5/5] report" + _cpu())
    what = ("taxel demo" + (" --small" if small else "") + ": thesis Fig. 2.5 study, sensitivity-crosstalk "
            "front, frequency response, step response, validation on the simulated rig")
    index = api.report(folders, root / "report", compare=not small,
                       run={"what": what, "started": started, "seconds": time.perf_counter() - t0})
    print(f"done in {time.perf_counter() - t0:.0f} s{_cpu()}; open {index.resolve()}")
    return index
