"""Optimization cost (2D 3x3 PZT taxel array, plane strain, linear silicone):
the objective's discretisation noise, the single-objective run (maximize
sensitivity under total thickness <= 2.127 mm), and the 7-point sensitivity /
crosstalk front on 2 workers, each from an empty cache.

Run: python benchmarks/optimize_front.py
"""

import shutil
import tempfile
import time
from pathlib import Path

from taxel.optimize.front import front, noise
from taxel.optimize.spec import BUILTIN, load_optimization, optimize
from taxel.studies.store import Store


def main():
    tmp = Path(tempfile.mkdtemp())
    try:
        p = load_optimization("thesis-pzt-front", tmp / "single")
        print("noise of the sensitivity (second difference / value) along the gap:")
        for h, v in noise(p, "gap").items():
            print(f"  step {h:g} of the range: {v:.1e}")
        t = time.perf_counter()
        r = optimize(p)
        ts = time.perf_counter() - t
        print(f"single objective: {r.nfev} evaluations, {ts:.1f} s, sensitivity {r.metrics['sensitivity']:.4g} V/N "
              f"at {', '.join(f'{n} {x:.3g} {u}' for n, x, u in zip(p.names, r.x, p.units))} ({r.message})")
        pf = load_optimization("thesis-pzt-front", tmp / "front")
        t = time.perf_counter()
        runs = front(pf, BUILTIN / "thesis-pzt-front.toml", workers=2)
        tf = time.perf_counter() - t
        solves = len(Store(tmp / "front").rows())
        print(f"7-point front on 2 workers: {tf:.1f} s, {sum(r.result.nfev for r in runs)} optimizer evaluations, "
              f"{solves} distinct FEM solves")
    finally:
        shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
