"""A warm finger on the thesis's taxels: the false press it makes at the bench's charge
amplifier, and how the silicone above changes it (issue 58).

1. Conduction against closed forms (fem.thermal): a 6 mm silicone column under a step
   surface temperature (erfc) and through h = 300 W/(m^2 K) (Carslaw and Jaeger), 1 mm
   down; 1 mm silicone on a 0.127 mm PSI-5H4E film (two-layer series), the film's mean
   temperature; plane strain, axisymmetric, 3D; the largest error over t = 0.5, 1, 3 s.
2. Both thesis designs (PSI-5H4E 0.127 mm, PVDF 52 um; 4 x 4 mm, 1 mm silicone above and
   below) through the bench's chain (the thesis-bench rig: charge amplifier C_f 820 pF,
   R_f 10 MOhm, 50 Hz notch; its 16-bit converter and the simulated rig's hum in the noise budget): a 34 C finger held
   1 s on the taxel's footprint of a 23 C skin (1000 W/(m^2 K); air 10 W/(m^2 K)); 2D plane
   strain and axisymmetric (PZT: PVDF's drawn film is not axisymmetric) and 3D (PZT);
   the false force beside the minimum detectable force, and the warm press (1 N and the
   finger together).
3. The silicone above from 0.25 to 3 mm (2D, 20 s simulated: under 3 mm the film's
   response peaks seconds after the lift): false force, press sensitivity at the readout,
   minimum detectable force.
4. Convergence of the 2D PZT false force: mesh refined 2x and 4x, the time step halved.
5. The main job's cost (`taxel demo`, taxel.jobs.warm_touch): each thesis design's warm touch
   into its optimization folder, three times, the median seconds; and the sensitivity drift
   it reports (0 to 50 C).

Run: OMP_NUM_THREADS=1 python benchmarks/warm_touch.py [out.json]   (about 2 min)
Writes benchmarks/results/warm_touch.json (or out.json).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from taxel.analyses import mesh
from taxel.analyses.solves.warm_touch import warm_touch
from taxel.fem import constitution, thermal
from taxel.scene import load, refined
from taxel.studies.bench.rig import load_rig

OUT = Path(__file__).resolve().parent / "results" / "warm_touch.json"
from taxel.studies.bench.signals import Settings
# the bench's chain with the simulated rig's mains hum: the answer's (taxel.jobs.answer_readout) and the main job's
BENCH = {"readout.circuit": "charge_amplifier", "readout.notch": True, "readout.hum": list(Settings().hum_V)}


def column(layers, model, width=0.4e-3, size=0.25e-3):
    shape = {"shape": "disk", "radius": width} if model == "axisymmetric" else {"width": width, "length": width}
    data = {"model": {"type": model}, "plate": {**shape, "layers": [{"material": m, "thickness": t} for m, t in layers]},
            "load": {"kind": "pressure", "pressure": 1e3}, "mesh": {"size": size, "piezo_layers": 8}}
    tm = mesh(load(data))
    heat = {r: thermal.Heat(constitution.get(n).conductivity, constitution.get(n).rho * constitution.get(n).specific_heat)
            for r, (n, _) in tm.materials.items()}
    return thermal.ThermalModel(tm.mesh, tm.regions, heat, constitution.kinematics(model, tm.layout.depth)), tm


def closed_forms() -> dict:
    sil, pzt = constitution.get("Ecoflex-00-30"), constitution.get("PSI-5H4E")
    out = {}
    m, tm = column([("Ecoflex-00-30", 0.5e-3)] * 12, "plane_strain", size=0.1e-3)
    alpha = sil.conductivity / (sil.rho * sil.specific_heat)
    t = np.linspace(0, 2.0, 201)
    probe = m.probe(np.array([[1e-4], [5e-3]]))
    for name, h in (("erfc (step surface temperature)", np.inf), ("Robin, h = 300 W/(m^2 K)", 300.0)):
        c = thermal.conduct(m, t, [thermal.Surface(tm.facets["top"], 1e9 if np.isinf(h) else h, lambda s: 307.15)], 295.15)
        fem = (probe @ c.T.T).ravel() - 295.15
        ref = 12 * thermal.semi_infinite(1e-3, t[1:], sil.conductivity, alpha, h)
        k = [50, 100, 200]
        out[f"semi-infinite silicone, 1 mm down: {name}"] = float(max(abs(fem[i] / ref[i - 1] - 1) for i in k))
    for model in ("plane_strain", "axisymmetric", "3d"):
        m, tm = column([("PSI-5H4E", 0.127e-3)] + [("Ecoflex-00-30", 0.25e-3)] * 4, model,
                       size=0.25e-3 if model != "3d" else 0.4e-3)
        t = np.linspace(0, 3.0, 481)
        c = thermal.conduct(m, t, [thermal.Surface(tm.facets["top"], 1e9, lambda s: 307.15)], 295.15)
        fem = (thermal.mean_temperature(c, tm.regions["layer0"]) - 295.15) / 12
        ref = thermal.two_layer_film_mean(t[1:], 1e-3, sil.conductivity, sil.rho * sil.specific_heat,
                                          0.127e-3, pzt.conductivity, pzt.rho * pzt.specific_heat)
        idx = [int(np.argmin(abs(t - x))) for x in (0.5, 1.0, 3.0)]
        out[f"two-layer slab, film mean, {model} ({m.n} DOFs)"] = float(max(abs(fem[i] / ref[i - 1] - 1) for i in idx))
    return out


def row(scene, rig) -> dict:
    t0 = time.perf_counter()
    r = warm_touch(scene, rig=rig)
    s = r.summary()
    return {"model": scene.model.type, "silicone_above_mm": scene.array.silicone_above * 1e3,
            "film_rise_K": s["film_rise_K"], "film_max_rate_K_per_s": s["film_max_rate_K_per_s"],
            "false_force_mN": 1e3 * s["false_force_N"],
            "min_detectable_force_mN": 1e3 * s["min_detectable_force_N"] if s["min_detectable_force_N"] else None,
            "ratio": s["ratio"], "press_peak_V_per_N": s["press_peak"] / s["force_N"],
            "touch_peak_time_s": s["touch_peak_time_s"], "peak_at_end": s["peak_at_end"],
            "touch_peak_V": s["touch_peak"], "warm_press_peak_V": s["warm_press_peak"],
            "warm_press_change_pct": 100 * (s["warm_press_peak"] / s["press_peak"] - 1),
            "wall_s": time.perf_counter() - t0}


def job_cost(repeats: int = 3) -> dict:
    """The main job's warm touch of each thesis design (taxel.jobs.warm_touch): median seconds
    of `repeats` runs (the first of a process pays the imports), its numbers and drift."""
    import tempfile
    from taxel.jobs.warm_touch import warm_touch as job
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for m in ("pzt", "pvdf"):
            folder = Path(tmp) / f"thesis-{m}-front"
            folder.mkdir()
            secs = [job(folder) for _ in range(repeats)]
            rec = json.loads((folder / "warm-touch.json").read_text())
            out[m] = {"seconds": secs, "median_s": float(np.median(secs)), "false_force_mN": 1e3 * rec["false_force_N"],
                      "min_detectable_force_mN": 1e3 * rec["min_detectable_force_N"], "ratio": rec["ratio"],
                      "drift": rec["drift"]}
    return out


def main(out=OUT):
    rig = load_rig("thesis-bench")
    res = {"closed_forms_max_rel_error": closed_forms()}
    print(json.dumps(res, indent=1))
    designs = {"PZT": "thesis-pzt-single", "PVDF": "thesis-pvdf-single"}
    res["designs"] = []
    for name, ex in designs.items():
        for model in ("plane_strain", "axisymmetric", "3d"):
            if name == "PVDF" and model != "plane_strain":
                continue
            base = load(f"{ex}-2d") if model != "3d" else load(f"{ex}-3d")
            if model == "axisymmetric":
                base = base.replace(**{"model.type": "axisymmetric", "load.kind": "probe", "load.radius": "2 mm"})
            r = {"design": name, **row(base.replace(**BENCH), rig)}
            res["designs"].append(r)
            print(json.dumps(r))
    res["silicone_above"] = []
    for name, ex in designs.items():
        for above in (0.25, 0.5, 1.0, 1.5, 2.0, 3.0):
            # the film's response peaks later under more silicone (L^2 / alpha: 50 s for 3 mm): 20 s simulated
            sc = load(f"{ex}-2d").replace(**BENCH, **{"array.silicone_above": f"{above} mm", "warm_touch.time": 20.0})
            r = {"design": name, **row(sc, rig)}
            res["silicone_above"].append(r)
            print(json.dumps(r))
    res["convergence"] = []
    base = load("thesis-pzt-single-2d").replace(**BENCH)
    for f, dt in ((1, 0.01), (1, 0.005), (2, 0.01), (4, 0.005)):
        sc = (refined(base, f) if f > 1 else base).replace(**{"warm_touch.dt": dt})
        r = {"refinement": f, "dt_s": dt, **row(sc, rig)}
        res["convergence"].append(r)
        print(json.dumps(r))
    res["main_job"] = job_cost()
    print(json.dumps(res["main_job"]))
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(res, indent=1))
    print(f"wrote {out}")


if __name__ == "__main__":
    main(*(sys.argv[1:2] or [OUT]))
