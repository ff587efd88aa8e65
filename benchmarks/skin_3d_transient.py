"""The 3D skin's transient against the 3D model's own dynamics at three off-centre presses.

A 2 x 2 PZT array (thesis-pzt-3x3-3d with array.rows = array.cols = 2, every electrode on
the scene's resistor, a coarse 3 mm / 1.2 mm mesh: the check is consistent-mesh); its skin
(taxel.skin.build at dt = 0.25 ms: the 3D surface map's W times h of the 2D section);
the reference, the Krylov-reduced 3D model of the same array driven by 1 N pressing on
the top-surface nodes within 1.6 mm of each point (tests/skin_3d_transient.py: its basis
checked against direct 3D frequency solves within 1e-4, its state space simulated by
first-order hold). Three points (a quarter pitch along the diagonal, mid-gap, in the
edge margin) x three histories (a 5 ms ramp held, a 10 ms half-sine, a 0-100 Hz chirp
over 0.5 s). Per case: max |v_skin - v_3D| over the four taxels and time, of the pressed
taxel's peak (the largest |v_3D| of the same history pressed by the same nodes on the
nearest taxel's centre, a fourth column of the reduced model) and of the press's own
largest |v_3D|, and whether every taxel above 1 % of the pressed peak has the 3D model's
sign at its own peak. First, why a static map times h can hold: the 3D
model's first resonance (the lowest oscillatory pole of its realization) against the
skin's band. Writes benchmarks/results/skin_3d_transient.json.

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/skin_3d_transient.py [--reference FILE]

(--reference FILE: the reduced 3D model kept in FILE, pickled, and read from it when there:
its reduction takes 5-7 minutes of CPU; the skin is built anew either way.)
"""

from __future__ import annotations

import json
import os
import pickle
import resource
import sys
import time
from pathlib import Path


import taxel
from taxel.skin.build import build

sys.path.insert(0, str(Path(__file__).parent.parent / "tests"))
from skin_3d_transient import HISTORIES, POINTS, SMALL, Reference, centres, errors  # noqa: E402


def main():
    t0, c0 = time.perf_counter(), time.process_time()
    scene = taxel.load("thesis-pzt-3x3-3d").replace(**SMALL)
    sk = build(scene, dt=2.5e-4, checks=0)
    t1 = time.process_time()
    keep = Path(sys.argv[sys.argv.index("--reference") + 1]) if "--reference" in sys.argv else None
    if keep is not None and keep.exists():
        ref = pickle.loads(keep.read_bytes())
        ref.sk = sk
    else:
        ref = Reference(scene, sk, centres(sk.pitch, sk.taxel_width))
        if keep is not None:
            keep.write_bytes(pickle.dumps(ref))
    out = {"load_average_start": os.getloadavg()[0], "mesh": [SMALL["mesh.size"], SMALL["mesh.piezo_size"]],
           "unknowns": ref.unknowns, "reduced_order": ref.red.order, "reduction_error": float(ref.red.error),
           "first_resonance_hz": ref.first_resonance(), "skin_band_hz": float(sk.band), "dt": sk.dt,
           "skin_build_cpu_s": t1 - c0, "reference_cpu_s": time.process_time() - t1, "cases": {}}
    print(f"3D model: {ref.unknowns} unknowns, reduced to {ref.red.order} (error {ref.red.error:.1e}); first "
          f"resonance {out['first_resonance_hz']:.0f} Hz against the skin's band {sk.band:.0f} Hz", flush=True)
    print("| press | history | max error, of the pressed taxel's peak | of this press's own peak | pressed peak, own peak (V) | signs |")
    print("|---|---|---|---|---|---|")
    for h in HISTORIES:
        peak = float(abs(ref.compare("centre", h)["fem"]).max())
        for where in POINTS:
            r = errors(ref.compare(where, h), peak)
            out["cases"][f"{where}/{h}"] = r
            print(f"| {where} | {h} | {100 * r['error']:.2f} % | {100 * r['error_of_own_peak']:.2f} % | {r['peak']:.3f}, "
                  f"{r['own_peak']:.4f} | {'agree' if r['signs'] else 'DIFFER'} |", flush=True)
    out.update(wall_s=time.perf_counter() - t0, cpu_s=time.process_time() - c0,
               max_rss_gb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6,
               load_average_end=os.getloadavg()[0])
    (Path(__file__).parent / "results").mkdir(exist_ok=True)
    (Path(__file__).parent / "results" / "skin_3d_transient.json").write_text(json.dumps(out, indent=1))
    print(f"wrote results/skin_3d_transient.json ({out['cpu_s']:.0f} s CPU, {out['max_rss_gb']:.2f} GB)")


if __name__ == "__main__":
    main()
