"""The nominal optimum against the robust one, on the thesis PZT array (2D 3x3, plane
strain, the row through the pressed middle taxel; mesh 1 mm for speed), over the
silicone above the taxels (thickness) and the edge-to-edge gap (pitch = 4 mm + gap).

- nominal: maximize sensitivity subject to crosstalk <= LIMIT (one point per design);
- robust:  maximize the 5th percentile of sensitivity subject to
           yield(crosstalk <= LIMIT) >= 90 %, each design on 16 parts (silicone above
           +-0.1 mm uniform, gap +-0.2 mm normal (3 sigma), piezo thickness +-5 %
           normal).

Both optima are then checked on 64 fresh parts (another seed): the 5th percentile
of sensitivity and the yield with its 95 % interval. Same budget for both runs
(DIRECT then COBYLA). Run: python benchmarks/robust_optimum.py [OUT]
"""

import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from taxel.optimize.robust import Robust, robust_metrics
from taxel.optimize.spec import load_optimization, optimize
from taxel.studies.yield_analysis import yield_of
from taxel.studies.tolerance import meets

LIMIT = "5 %"
COMMON = '''
[variables]
silicone_above = {path = "array.silicone_above", min = "0.3 mm", max = "1.7 mm", start = "1 mm"}
gap = {path = "array.gap", min = "1 mm", max = "5 mm", start = "3 mm"}
[algorithm]
global = "DIRECT"
local = "COBYLA"
max_evaluations = 24
xtol = 0.02
[requirements]
crosstalk = "<= LIMIT"
[robust]
percentile = 5
samples = 16
seed = 0
[[robust.parameters]]
path = "array.silicone_above"
tolerance = "0.1 mm"
distribution = "uniform"
[[robust.parameters]]
path = "array.gap"
tolerance = "0.2 mm"
distribution = "normal"
[[robust.parameters]]
path = "array.piezo_thickness"
tolerance = "5 %"
distribution = "normal"
'''.replace("LIMIT", LIMIT)
NOMINAL = 'name = "nominal"\nbase = "thesis-pzt-3x3-2d"\n[objective]\nmaximize = "sensitivity"\n[requirements]\ncrosstalk = "<= 0.05"\n'
ROBUST = 'name = "robust"\nbase = "thesis-pzt-3x3-2d"\n[objective]\nmaximize = "robust_sensitivity"\n[requirements]\nyield = ">= 0.9"\n'


def load(folder: Path, head: str):
    f = folder / "spec.toml"
    f.write_text(head.replace("LIMIT", LIMIT) + COMMON)
    p = load_optimization(f, folder / "store")
    p.base.setdefault("mesh", {})["size"] = "1 mm"        # coarse: minutes on 2 cores
    return p


def check(p, x, samples=64, seed=7):
    """5th percentile of sensitivity and yield on `samples` fresh parts about design x."""
    rb = Robust.model_validate({**p.spec.robust.model_dump(), "samples": samples, "seed": seed})
    got = []
    m = robust_metrics(rb, p.requirements, p.scene_data(x), lambda d, params: got.append(p.point(d, params))
                       or got[-1])
    ok = np.logical_and.reduce([meets([g.get(k) if g.get(k) is not None else np.nan for g in got], op, b)
                                for k, (op, b) in p.requirements.items()])
    return m["robust_sensitivity"], yield_of(ok)


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    rows = []
    try:
        for head in (NOMINAL, ROBUST):
            folder = out / head.split('"')[1]
            folder.mkdir(parents=True, exist_ok=True)
            p = load(folder, head)
            t = time.perf_counter()
            r = optimize(p)
            secs = time.perf_counter() - t
            p5, y = check(p, r.x)
            rows.append((p.spec.name, r, secs, p5, y, p))
        print(f"thesis PZT 3x3 (2D, mesh 1 mm): silicone above and gap; crosstalk <= {LIMIT}; tolerances "
              "silicone above +-0.1 mm uniform, gap +-0.2 mm normal (3 sigma), piezo thickness +-5 % normal")
        print("| optimum | silicone above | gap | sensitivity (V/N) | crosstalk | p5 sensitivity (V/N, 64 parts) "
              "| yield (64 parts, 95 % CI) | evaluations | FEM solves | seconds |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for name, r, secs, p5, y, p in rows:
            x = dict(zip(p.names, r.x))
            from taxel.studies.store import Store
            st = Store(p.out)
            solves = len(st.rows())
            st.close()
            print(f"| {name} | {x['silicone_above']:.3f} mm | {x['gap']:.3f} mm | "
                  f"{r.metrics['sensitivity']:.4f} | {100 * r.metrics['crosstalk']:.2f} % | {p5:.4f} | "
                  f"{100 * y['yield']:.0f} % ({100 * y['low']:.0f}-{100 * y['high']:.0f} %) | {r.nfev} | "
                  f"{solves} | {secs:.0f} |")
    finally:
        if len(sys.argv) <= 1:
            shutil.rmtree(out)


if __name__ == "__main__":
    main()
