"""The estimator's cheapest 3D model (taxel.analyses.accuracy.error_estimate.CHEAP_3D) as a quarter
model (model.symmetry = "auto" picks it) and as the full model, side by side: wall
time, pressed-taxel voltage against the 3D reference (docs/reference_3d.json, made
by benchmarks/reference_3d.py) and crosstalk, for the single thesis taxel and the
3x3 array. The estimator's allowance for this model's own error (CHEAP_3D_ERROR)
was measured with full models; this checks the quarter stays inside it.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/cheap_3d_symmetry.py
"""

import json
import time
from pathlib import Path

import taxel
from taxel.analyses.accuracy.error_estimate import CHEAP_3D, CHEAP_3D_ERROR, output_values

REFERENCE = json.loads((Path(__file__).parent.parent / "docs" / "reference_3d.json").read_text())


def main():
    print(f"allowance: voltage {100 * CHEAP_3D_ERROR['sensitivity']:.2f} %, "
          f"crosstalk {100 * CHEAP_3D_ERROR['crosstalk']:.1f} %")
    for name, key in (("thesis-pzt-single-3d", "single"), ("thesis-pzt-3x3-3d", "3x3")):
        ref = REFERENCE.get(key, {}).get("reference")
        for sym in ("quarter", "full"):
            scene = taxel.load(name).replace(**{**CHEAP_3D, "model.symmetry": sym})
            t = time.perf_counter()
            res = taxel.solve(scene)
            dt = time.perf_counter() - t
            out = output_values(res)
            v = out["sensitivity"] * abs(res.applied_force)
            err = f"{100 * (v / ref - 1):+.3f} %" if ref else "no reference"
            xt = f"{100 * out['crosstalk']:.3f} %" if "crosstalk" in out else "-"
            print(f"{name:<22} {sym:<8} {dt:6.1f} s   V = {v:.6f} V ({err})   crosstalk {xt}", flush=True)


if __name__ == "__main__":
    main()
