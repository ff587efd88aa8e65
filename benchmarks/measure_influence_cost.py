"""What the localization_error metric costs per design, and what fewer press positions lose.

    python benchmarks/measure_influence_cost.py

For the thesis scene (thesis-pzt-3x3-2d) and two variants (silicone_above 0.5 mm;
gap 1.5 mm): the influence functions over the taxels' span sampled every pitch / 8
with every position solved (the reference), and every pitch / 2, / 4 and / 8 with
the mirror symmetry (taxel.analyses.surface.influence). Printed: the static solves, the
wall time relative to the reference, the largest |G - G_ref| at the reference's
positions (the cubic spline between coarser samples), the mirror's own error
(per_pitch 8 against the reference at the same positions), and the metric
localization_error (taxel.analyses.surface.localization, 1 mV, rms over the map) relative to
the reference's. One run, no cache (a fresh XDG_CACHE_HOME).
"""

from __future__ import annotations

import os
import tempfile
import time

import numpy as np

import taxel
from taxel.analyses import solve_static
from taxel.schema import electrode_name


def main():
    os.environ["XDG_CACHE_HOME"] = tempfile.mkdtemp()
    from taxel.analyses.surface import influence as I
    from taxel.analyses.surface.localization import localization_error
    base = taxel.load("thesis-pzt-3x3-2d")
    designs = {"thesis": base, "silicone_above 0.5 mm": base.replace(**{"array.silicone_above": "0.5 mm"}),
               "gap 1.5 mm": base.replace(**{"array.gap": "1.5 mm"})}
    print("design                  per_pitch  mirror  solves  time_ratio  max_dG      metric_mm  metric_ratio")
    for name, sc in designs.items():
        count = {"n": 0}

        def solve(s):
            count["n"] += 1
            return solve_static(s).voltages()

        t0 = time.perf_counter()
        ref = _no_mirror(I, sc, solve)
        t_ref = time.perf_counter() - t0
        e_ref = _metric(sc, ref)
        print(f"{name:22s}  {8:9d}  {'no':6s}  {count['n']:6d}  {1.0:10.2f}  {0.0:9.2e}  {1e3 * e_ref:9.4f}  {1.0:12.3f}")
        for pp in (2, 4, 8):
            count["n"] = 0
            t0 = time.perf_counter()
            infl = I.influence(sc, per_pitch=pp, edges=False, solve=solve)
            t = time.perf_counter() - t0
            dG = np.abs(infl.at(ref.x) - ref.G).max()
            e = localization_error(sc, solve=solve, per_pitch=pp).rms_m
            print(f"{name:22s}  {pp:9d}  {'yes':6s}  {infl.solves:6d}  {t / t_ref:10.2f}  {dG:9.2e}  {1e3 * e:9.4f}  "
                  f"{e / e_ref:12.3f}", flush=True)


def _no_mirror(I, sc, solve):
    """The reference: every pitch / 8 over the span, each position solved."""
    arr = sc.array
    pitch = arr.pitch
    xs = I.samples(sc, 8, False)
    V = []
    for x in xs:
        c = int(np.clip(np.round(x / pitch), 0, arr.cols - 1))
        s = sc.replace(**{"load.kind": "probe", "load.taxel": [arr.rows // 2, c], "load.radius": arr.taxel_width / 2,
                          "load.offset": [float(x - c * pitch), 0.0], "load.profile": "flat"})
        v = solve(s)
        V.append([v[electrode_name(arr.rows // 2, k)] for k in range(arr.cols)])
    V = np.array(V)
    centre = [int(np.argmin(np.abs(xs - c * pitch))) for c in range(arr.cols)]
    return I.Influence(pitch, xs, V / V[centre, np.arange(arr.cols)][None, :], len(xs),
                       V[centre, np.arange(arr.cols)] / float(sc.load.force))


def _metric(sc, infl):
    from taxel.analyses.surface.localization import accuracy_map
    arr = sc.array
    amap = accuracy_map(infl, arr.rows, arr.cols, float(np.mean(np.abs(infl.sensitivity))), 1e-3, float(sc.load.force))
    e = amap.position_error_mm[np.isfinite(amap.position_error_mm)]
    return 1e-3 * float(np.sqrt(np.mean(e ** 2)))


if __name__ == "__main__":
    main()
