"""Where the pressed silicone is nonlinear (issue 57, "nonlinear only where the silicone is
nonlinear"): the element-mean largest principal strain of the silicone after the default probe
press (sticking, Yeoh, 1 N), and how much of the silicone (elements, volume, P2 nodes) lies above
each strain threshold, with the zone's reach from the punch's axis. The linear silicone's voltage
error is about 0.257 x its largest strain (taxel.analyses.results.static.LINEAR_ERROR_PER_STRAIN),
so a zone keeping the far field linear within 0.1 % of the answer needs the elements above about
0.4 % strain nonlinear: this measures that zone's size, the first number of a condensed far field.

    python benchmarks/press_zone.py [--case single|3x3]

RESULT: docs/benchmarks.md ("The 3D press's reference settled").
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from press_directions import scene  # noqa: E402

THRESHOLDS = (0.002, 0.004, 0.01, 0.02, 0.05)


def main():
    from taxel.analyses.model.problem import solve_model
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", choices=("single", "3x3"), default="single")
    a = ap.parse_args()
    sc = scene(a.case)
    res = solve_model(sc)
    sol = res.solution
    tm = sol.mesh
    m = tm.mesh
    f = sol.fields
    sil = tm.regions["silicone"]
    E = f.strain[sil]                         # (ne, 6) Voigt, engineering shears
    T = np.zeros((len(sil), 3, 3))
    for (i, j), k in zip(((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)), range(6)):
        T[:, i, j] = T[:, j, i] = E[:, k] * (1.0 if i == j else 0.5)
    eps = np.abs(np.linalg.eigvalsh(T)).max(axis=1)
    P = m.p[:, m.t[:, sil]]
    vol = np.abs(np.einsum("ij,ij->j", P[:, 1] - P[:, 0], np.cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 0], axis=0))) / 6
    c = P.mean(axis=1)
    lay = tm.layout
    r = np.hypot(c[0] - lay.load.x, c[1] - lay.load.y)
    rows = []
    for t in THRESHOLDS:
        z = eps > t
        rows.append(dict(threshold=t, elements=float(z.mean()), volume=float(vol[z].sum() / vol.sum()),
                         reach_mm=float(1e3 * r[z].max()) if z.any() else 0.0,
                         depth_mm=float(1e3 * (lay.height - c[2][z].min())) if z.any() else 0.0))
        print(f"strain > {100 * t:g} %: {100 * rows[-1]['elements']:.1f} % of the silicone's elements, "
              f"{100 * rows[-1]['volume']:.1f} % of its volume, out to {rows[-1]['reach_mm']:.2f} mm from the axis, "
              f"{rows[-1]['depth_mm']:.2f} mm deep", flush=True)
    out = Path(__file__).parent / "results" / f"press_zone_{a.case}.json"
    out.write_text(json.dumps(dict(case=a.case, unknowns=res.unknowns, elements=len(sil), max_strain=float(eps.max()),
                                   zones=rows), indent=1) + "\n")


if __name__ == "__main__":
    main()
