"""Which outer radius makes the axisymmetric taxel closest to 3D?

The square sensor (taxel width w, margin m, outline w + 2 m) becomes a disk in
an axisymmetric model. Two mappings of the outline: (a) the taxel's equal-area
disk plus the margin, R = w / sqrt(pi) + m (what the code did), (b) the outline's
equal-area disk, R = (w + 2 m) / sqrt(pi). Both against the 3D taxel (default
mesh, two elements through the PZT: 0.1 % from converged per issue 11's
independent reference), pressed-taxel voltage and capacitance.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/axisymmetric_radius.py  (3D: a few minutes, ~8 GB)
"""

from __future__ import annotations

import math

from taxel.analyses import solve_static as solve
from taxel.scene import load


def main():
    base = load("thesis-pzt-single-2d").replace(**{"mesh.piezo_layers": 2})
    w, m = base.array.taxel_width, base.array.margin
    ref = solve(base.replace(**{"model.type": "3d"}))
    v3, c3 = ref.voltages()["taxel_0_0"], ref.electrodes["taxel_0_0"].capacitance
    print(f"3D: {v3:.6f} V, {c3 * 1e9:.5f} nF ({ref.unknowns} unknowns)")
    r_taxel = w / math.sqrt(math.pi)
    for label, R in (("taxel disk + margin", r_taxel + m), ("outline equal area", (w + 2 * m) / math.sqrt(math.pi))):
        s = base.replace(**{"model.type": "axisymmetric", "array.margin": R - r_taxel})
        sol = solve(s)
        v, c = sol.voltages()["taxel_0_0"], sol.electrodes["taxel_0_0"].capacitance
        print(f"axisymmetric, {label:<20} R = {R * 1e3:.3f} mm: {v:.6f} V ({100 * (v / v3 - 1):+.2f} % vs 3D), "
              f"{c * 1e9:.5f} nF ({100 * (c / c3 - 1):+.2f} %)")


if __name__ == "__main__":
    main()
