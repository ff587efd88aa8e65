"""The coverage metric (taxel.analyses.surface.coverage, optimize.coverage): what it costs per
design, how it moves with the gap, what a finer or coarser line scan changes, and how
the 2D section's line scan compares with 3D presses at one design.

    python benchmarks/coverage_metric.py            # 2D parts (about 2 minutes on 2 cores)
    python benchmarks/coverage_metric.py --3d       # also the 3D presses (about 15 more minutes)
    python benchmarks/coverage_metric.py --3d-only 3   # the 3D presses at one gap (mm) alone

Parts, each printed as a table and written to benchmarks/results/coverage_metric.json:

1. cost: the influence functions of the thesis PZT design (thesis-pzt-3x3-2d) from a
   fresh cache, per_pitch 4 and 8 (5 and 9 static 2D solves), `repeats` times each:
   median wall seconds (the coverage computation itself on the splines: median of 20).
2. gap sweep (limits): coverage on the surface and on the line through the taxel
   centres at the seed's smallest force 0.2 N, 1 mV on each open-circuit peak, k = 3,
   for the PZT and PVDF designs at gaps from 0.01 mm (the taxels almost touch: full
   coverage expected) to 14 mm (much wider than the 1 mm silicone: a dead zone
   expected), and the smallest best-taxel peak over the surface in units of k sigma.
3. scan resolution: coverage at per_pitch 4, 8 and 16 at the gaps where the PZT design
   has a dead zone.
4. with --3d: the thesis PZT design at gaps 5 and 3 mm pressed in 3D (thesis-pzt-3x3-3d,
   the same patch: a flat pressure patch of radius taxel_width / 2) at its taxel's
   centre, its edge, the gap's middle along the middle row and the corner between four
   taxels: the best taxel's peak relative to the centre's, and in units of 3 sigma at
   0.2 N and 1 mV, beside the 2D model's at the same points (separable at the corner).
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import taxel
from taxel.analyses.surface.coverage import SIGMAS, best_peak, coverage
from taxel.analyses.surface.influence import influence
from taxel.schema import electrode_name

FORCE, NOISE = 0.2, 1e-3
GAPS_MM = (0.01, 1, 3, 5, 8, 10, 14)


def fresh():
    os.environ["XDG_CACHE_HOME"] = tempfile.mkdtemp()


def cost(repeats: int = 3) -> dict:
    sc = taxel.load("thesis-pzt-3x3-2d")
    out = {}
    for pp in (4, 8):
        ts = []
        for _ in range(repeats):
            fresh()
            t0 = time.perf_counter()
            infl = influence(sc, per_pitch=pp, edges=False)
            ts.append(time.perf_counter() - t0)
        tc = []
        for _ in range(20):
            t0 = time.perf_counter()
            coverage(infl, FORCE, NOISE)
            tc.append(time.perf_counter() - t0)
        out[pp] = {"solves": infl.solves, "median_s": statistics.median(ts), "runs_s": ts,
                   "coverage_median_s": statistics.median(tc)}
        print(f"cost  per_pitch {pp:2d}: {infl.solves} 2D solves, median {statistics.median(ts):.2f} s "
              f"(runs {', '.join(f'{t:.2f}' for t in ts)}); coverage on the splines {1e3 * statistics.median(tc):.1f} ms",
              flush=True)
    return out


def sweep(per_pitch=(8,)) -> dict:
    fresh()
    out = {}
    print("piezo  gap_mm  per_pitch  coverage  line_coverage  worst_peak_over_k_sigma  dead_zone_mm (worst line)")
    for base in ("thesis-pzt-3x3-2d", "thesis-pvdf-3x3-2d"):
        for gap in GAPS_MM:
            sc = taxel.load(base).replace(**{"array.gap": f"{gap} mm"})
            for pp in per_pitch:
                infl = influence(sc, per_pitch=pp, edges=False)
                c = coverage(infl, FORCE, NOISE)
                x = np.linspace(0, infl.x[-1], 401)
                b = best_peak(infl, x)
                g = np.max(np.abs(infl.at(x)), axis=1)
                worst = FORCE * b.min() * g.min() / (SIGMAS * NOISE)     # the separable surface's smallest peak
                key = f"{base} gap {gap} mm per_pitch {pp}"
                out[key] = {"coverage": c.fraction, "line_coverage": c.line_fraction, "worst_over_threshold": worst,
                            "dead_mm": [[1e3 * a, 1e3 * b_] for a, b_ in c.dead_m]}
                print(f"{base.split('-')[1]:5s}  {gap:6g}  {pp:9d}  {100 * c.fraction:7.2f} %  {100 * c.line_fraction:11.2f} %"
                      f"  {worst:23.3g}  {[(round(1e3 * a, 2), round(1e3 * b_, 2)) for a, b_ in c.dead_m]}", flush=True)
    return out


def three_d(gap_mm: float, corner_only: bool = False) -> dict:
    """2D line scan vs 3D presses of the middle row (module docstring, part 4), and the corner
    between four taxels (the surface's worst point in the separable model: g(y*) b(x*))."""
    from taxel.analyses import solve_static
    fresh()
    sc2 = taxel.load("thesis-pzt-3x3-2d").replace(**{"array.gap": f"{gap_mm} mm"})
    sc3 = taxel.load("thesis-pzt-3x3-3d").replace(**{"array.gap": f"{gap_mm} mm"})
    arr = sc3.array
    pitch = arr.pitch
    infl = influence(sc2, per_pitch=8, edges=False)
    positions = {"taxel centre": (0.0, 0.0), "taxel edge": (arr.taxel_width / 2, 0.0),
                 "gap middle": (pitch / 2, 0.0), "corner of four taxels": (pitch / 2, pitch / 2)}
    if corner_only:
        positions = {k: v for k, v in positions.items() if k in ("taxel centre", "corner of four taxels")}
    out = {}
    for name, (x, y) in positions.items():
        s = sc3.replace(**{"load.kind": "probe", "load.taxel": [1, 0], "load.radius": arr.taxel_width / 2,
                           "load.offset": [float(x), float(y)], "load.profile": "flat"})
        t0 = time.perf_counter()
        v = solve_static(s).voltages()
        peak3 = max(abs(v[electrode_name(r, c)]) for r in range(arr.rows) for c in range(arr.cols))
        g = float(np.max(np.abs(infl.at([y])))) if y else 1.0         # the separable model's other factor
        out[name] = {"x_mm": 1e3 * x, "y_mm": 1e3 * y, "3D best peak V/N": peak3 / float(s.load.force),
                     "3D seconds": time.perf_counter() - t0, "2D best peak V/N": float(best_peak(infl, [x])[0]) * g}
    base = out["taxel centre"]
    print(f"3D vs 2D at gap {gap_mm} mm (thesis PZT; the best taxel's peak relative to a press on a taxel's centre; "
          f"at 0.2 N against 3 x 1 mV)")
    for name, r in out.items():
        r["3D relative"] = r["3D best peak V/N"] / base["3D best peak V/N"]
        r["2D relative"] = r["2D best peak V/N"] / base["2D best peak V/N"]
        print(f"  {name:22s} ({r['x_mm']:.2f}, {r['y_mm']:.2f}) mm: 3D {r['3D relative']:.3f} "
              f"({FORCE * r['3D best peak V/N'] / (SIGMAS * NOISE):.3g} x 3 sigma, {r['3D seconds']:.0f} s), "
              f"2D {r['2D relative']:.3f} ({FORCE * r['2D best peak V/N'] / (SIGMAS * NOISE):.3g} x 3 sigma)",
              flush=True)
    return out


def main():
    if "--3d-only" in sys.argv:            # part 4 alone: python benchmarks/coverage_metric.py --3d-only GAP_MM
        gap = float(sys.argv[sys.argv.index("--3d-only") + 1])
        res = three_d(gap)
        out = Path(__file__).parent / "results" / f"coverage_metric_3d_{gap:g}mm.json"
        out.parent.mkdir(exist_ok=True)
        out.write_text(json.dumps(res, indent=1))
        print(f"written {out}; load average {os.getloadavg()}")
        return
    t0 = time.time()
    res = {"force_N": FORCE, "noise_V": NOISE, "sigmas": SIGMAS, "load": os.getloadavg()}
    res["cost"] = cost()
    res["sweep"] = sweep()
    print("scan resolution (PZT, the gaps with a dead zone)")
    fresh()
    res["resolution"] = {}
    for gap in (8, 10, 14):
        sc = taxel.load("thesis-pzt-3x3-2d").replace(**{"array.gap": f"{gap} mm"})
        row = {pp: coverage(influence(sc, per_pitch=pp, edges=False), FORCE, NOISE).fraction for pp in (4, 8, 16)}
        res["resolution"][gap] = row
        print(f"  gap {gap:2d} mm: " + ", ".join(f"per_pitch {pp} {100 * v:.2f} %" for pp, v in row.items()), flush=True)
    if "--3d" in sys.argv:
        res["3d"] = {"5 mm": three_d(5.0), "3 mm": three_d(3.0)}
    res["seconds"] = time.time() - t0
    out = Path(__file__).parent / "results" / "coverage_metric.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(res, indent=1, default=str))
    print(f"written {out}; load average {os.getloadavg()}")


if __name__ == "__main__":
    main()
