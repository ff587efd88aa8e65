"""Sampling a surface map: one spline with (ntaxels, 3) values (SurfaceMap.response, scipy's
NdBSpline on FITPACK's knots and coefficients) against one RectBivariateSpline call per
taxel and direction (how response sampled before), on the thesis PZT design's coverage map
(optimize.coverage.design_map: the 3x3 array on its map mesh), side by side in one run.

Two workloads: the single-point presses of coverage's minimum search (Nelder-Mead calls
`best_margin` one point at a time, a footprint's quadrature each) and the averaged map's
grid (one call over every grid point x the quadrature). Reports the medians of REPEATS
timings, their ratio, and the largest difference between the two (relative to the map's
largest |value|).

    python benchmarks/surface_map_sampling.py [--repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from scipy.interpolate import RectBivariateSpline


def per_component(m):
    """The earlier sampling: 3 RectBivariateSpline calls per taxel."""
    k = min(3, len(m.x) - 1, len(m.y) - 1)
    fits = [[RectBivariateSpline(m.y, m.x, m.charge_per_newton[j, d], kx=k, ky=k) for d in range(3)]
            for j in range(len(m.taxels))]

    def response(points):
        pts = np.atleast_2d(np.asarray(points, float))
        x0, x1, y0, y1 = m.bounds
        px, py = np.clip(pts[:, 0], x0, x1), np.clip(pts[:, 1], y0, y1)
        return np.stack([np.stack([s(py, px, grid=False) for s in row], axis=-1) for row in fits], axis=1)
    return response


def timed(f, repeats):
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = f()
        ts.append(time.perf_counter() - t0)
    return statistics.median(ts), out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()
    from taxel.analyses.surface.surface_map import Footprint
    from taxel.optimize import coverage, spec as O
    from taxel.optimize.run import reference_x
    from taxel.scene import parse
    prob = O.load_optimization("thesis-pzt-front")
    m, _ = coverage.design_map(parse({**prob.scene_data(reference_x(prob)), "name": "design"}))
    old = per_component(m)
    off, _ = Footprint(2e-3).quadrature()
    rng = np.random.default_rng(1)
    x0, x1, y0, y1 = m.bounds
    single = [np.array([rng.uniform(x0, x1), rng.uniform(y0, y1)]) + off for _ in range(300)]
    X, Y = np.meshgrid(m.x, m.y)
    grid = (np.column_stack([X.ravel(), Y.ravel()])[:, None, :] + off[None]).reshape(-1, 2)
    scale = np.abs(m.charge_per_newton).max()
    print(f"thesis PZT design's map: {len(m.taxels)} taxels, {len(m.y)} x {len(m.x)} grid; "
          f"footprint quadrature {len(off)} points; medians of {a.repeats}")
    for what, run in (("300 single presses (coverage's search)", lambda f: [f(p) for p in single]),
                      (f"the averaged map's grid ({len(grid)} points, one call)", lambda f: f(grid))):
        t_old, r_old = timed(lambda: run(old), a.repeats)
        t_new, r_new = timed(lambda: run(m.response), a.repeats)
        diff = np.max(np.abs(np.asarray(r_new) - np.asarray(r_old))) / scale
        print(f"  {what}: per taxel and direction {t_old:.3f} s, one spline {t_new:.3f} s, "
              f"ratio {t_old / t_new:.1f}x; largest difference {diff:.1e} of the map's largest value")


if __name__ == "__main__":
    main()
