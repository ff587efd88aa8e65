"""The 3D cost table: mesh, assembly and solve time, unknowns and peak memory of the
built-in 3D taxel scenes, one fresh process per row (so the peak memory is the
row's own), solvers side by side.

Each row runs `taxel.analyses.model.problem` (gmsh mesh), `fem.assembly.assemble`
(vectorised, fem.assembly) and `fem.static.solve_linear` (elimination, scaling,
factorization or GMRES for the load and every unit electrode charge, fields) with the solver and
MKL thread count of the row, and prints the pressed taxel's open-circuit voltage,
so the solvers can be compared on the same answer.

The "model" column is model.symmetry: "quarter" (fem.static) or "full"; the
error is against benchmarks/reference_3d.py's Richardson value (docs/reference_3d.json).

Times are wall-clock medians; "cpu s" is the row's process CPU time (time.process_time),
which a loaded machine inflates less. Run: python benchmarks/taxel_3d.py [--solvers pardiso superlu krylov] [--threads 1 2] [--symmetry quarter full]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

REFERENCE = Path(__file__).resolve().parents[1] / "docs" / "reference_3d.json"

ROW = r"""
import json, resource, sys, time
import taxel
from taxel.analyses import problem
from taxel.fem.assembly import assemble
from taxel.fem.static import solve_linear
name, solver, symmetry = sys.argv[1], sys.argv[2], sys.argv[3]
c0 = time.process_time(); t0 = time.perf_counter(); p = problem(taxel.load(name).replace(**{"model.symmetry": symmetry}))
t1 = time.perf_counter(); sy = assemble(p)
t2 = time.perf_counter(); sol = solve_linear(sy, solver)
t3 = time.perf_counter(); cpu = time.process_time() - c0
v = sol.voltages()
pressed = "taxel_1_1" if "taxel_1_1" in v else "taxel_0_0"
print(json.dumps(dict(unknowns=sol.unknowns, mesh=t1 - t0, assemble=t2 - t1, solve=t3 - t2, total=t3 - t0, cpu=cpu,
                      solver=sol.solver, residual=sol.residual, voltage=v[pressed], pressed=pressed,
                      peak_gb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6)))
"""


def row(name, solver, threads, symmetry):
    env = dict(os.environ, MKL_NUM_THREADS=str(threads), OMP_NUM_THREADS=str(threads))
    out = subprocess.run([sys.executable, "-c", ROW, name, solver, symmetry], env=env, capture_output=True, text=True)
    if out.returncode:
        return {"error": out.stderr.strip().splitlines()[-1]}
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="*", default=["thesis-pzt-single-3d", "thesis-pzt-3x3-3d"])
    ap.add_argument("--solvers", nargs="*", default=["pardiso"])
    ap.add_argument("--threads", nargs="*", type=int, default=[1])
    ap.add_argument("--symmetry", nargs="*", default=["quarter", "full"])
    ap.add_argument("--repeat", type=int, default=3, help="rows repeated; medians of the times")
    args = ap.parse_args()
    refs = json.loads(REFERENCE.read_text()) if REFERENCE.exists() else {}
    refs = {v["scene"]: v for v in refs.values()}
    print(f"{'scene':<22} {'model':<8} {'solver':<8} {'thr':>3} {'unknowns':>8} {'mesh s':>7} {'asm s':>6} "
          f"{'solve s':>8} {'total s':>8} {'cpu s':>6} {'peak GB':>8} {'residual':>9} {'V pressed':>12} {'error %':>8}")
    for name in args.scenes:
        for symmetry in args.symmetry:
            for solver in args.solvers:
                for threads in (args.threads if solver == "pardiso" else [1]):
                    runs = [row(name, solver, threads, symmetry) for _ in range(args.repeat if solver != "krylov" else 1)]
                    bad = [r for r in runs if "error" in r]
                    if bad:
                        print(f"{name:<22} {symmetry:<8} {solver:<8} {threads:>3} failed: {bad[0]['error']}", flush=True)
                        continue
                    r = {k: (statistics.median(x[k] for x in runs) if isinstance(runs[0][k], float) else runs[0][k])
                         for k in runs[0]}
                    err = f"{100 * abs(r['voltage'] / refs[name]['reference'] - 1):.2f}" if name in refs else "-"
                    print(f"{name:<22} {symmetry:<8} {solver:<8} {threads:>3} {r['unknowns']:>8} {r['mesh']:>7.2f} "
                          f"{r['assemble']:>6.2f} {r['solve']:>8.2f} {r['total']:>8.2f} {r['cpu']:>6.2f} {r['peak_gb']:>8.2f} "
                          f"{r['residual']:>9.1e} {r['voltage']:>12.9f} {err:>8}", flush=True)


if __name__ == "__main__":
    main()
