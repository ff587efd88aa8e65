"""The direct frequency-domain solve of a damped model, side by side: SuperLU on the
complex matrix against PARDISO on its real equivalent (fem.linalg._factorize_complex).
The case is the work-precision chart's costliest point kind: the thesis PZT 3x3 array
as a full 3D model (dynamics are not mirrored), P2, the chart's 3D mesh level, the
charge amplifier at 10 Hz and 300 Hz (studies.work_precision.sweep_values). Each method
runs in its own process; prints wall time, peak resident memory and the outputs.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/complex_solve.py [MESH]
(MESH: a studies.work_precision.MESH_3D level, default "3 mm")
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time


def child(mesh: str, method: str):
    from taxel.fem import linalg
    from taxel.scene import load
    from taxel.studies import work_precision as W
    if method == "superlu":                       # the sweep's solver before: SuperLU for every complex matrix
        real_resolve = linalg.resolve
        linalg.resolve = lambda m, n=0, iterative=False, dim=None: ("superlu" if m == "auto" else
                                                                     real_resolve(m, n, iterative, dim))
    base = load("thesis-pzt-3x3-2d").replace(**{"load.force": 1.0, "analysis.type": "static"})
    sc = W.Level("3d", 2, mesh, "linear").scene(base)
    t = time.perf_counter()
    values = W.sweep_values(sc)["values"]
    print(json.dumps(dict(wall=time.perf_counter() - t, peak_gb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6,
                          **values)))


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "--child":
        child(sys.argv[2], sys.argv[3])
        return
    mesh = sys.argv[1] if len(sys.argv) > 1 else "3 mm"
    rows = {}
    for method in ("pardiso", "superlu"):
        out = subprocess.run([sys.executable, __file__, "--child", mesh, method], capture_output=True, text=True,
                             check=True).stdout
        rows[method] = json.loads(out.strip().splitlines()[-1])
    print(f"thesis PZT 3x3, full 3D model, P2, {mesh}: charge amplifier at 10 and 300 Hz, direct")
    print("| solver | wall s | peak GB | output 10 Hz | output 300 Hz |\n|---|---|---|---|---|")
    for m, r in rows.items():
        print(f"| {m} | {r['wall']:.1f} | {r['peak_gb']:.2f} | {r['charge_amp_10Hz']:.10g} | {r['charge_amp_300Hz']:.10g} |")
    p, s = rows["pardiso"], rows["superlu"]
    dev = max(abs(p[k] / s[k] - 1) for k in ("charge_amp_10Hz", "charge_amp_300Hz"))
    print(f"SuperLU / PARDISO wall time {s['wall'] / p['wall']:.2f}x, memory {s['peak_gb'] / p['peak_gb']:.2f}x; "
          f"outputs within {dev:.1e}")


if __name__ == "__main__":
    main()
