"""A press that stops short of its force, kept as its last converged state
(taxel.solve returns it: success False, its stop), against pressing again to the force it reached.

The probe example (thesis-pzt-probe-2d; --3d: thesis-pzt-probe-3d, the default press mesh),
frictionless, asked for FORCE_2D (3 N; 3D: 1 N): where it stops and why (PressError.cause),
the kept state's force, travel and V/F, and the CPU time; then a press of the same scene to
the force it reached, in one target: where that one ends. A study point or `taxel solve`
keeps the first press's state rather than solving again, because a press depends on its
path: the second press need not reach the force the first one did.

RESULT (2026-11-25, one run each, CPU s on the shared 2-core machine): 2D, asked for 3 N:
stops at 1.6217 N (travel 0.6452 mm), cause inversion, kept V/F -0.65216 V/N, 18 s; pressed
again to 1.6217 N in one target: stops at 1.2739 N (0.3960 mm), cause inversion, 6 s. (3D, asked
for 1 N, not run by this script but by `taxel solve --out` on the same scene: 0.7487 N at
0.5013 mm, inversion, V/F -0.8815 V/N, 329 s.)

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/stopped_press.py [--3d]
"""

from __future__ import annotations

import sys
import time

from taxel.analyses import solve
from taxel.scene import load

FORCE_2D = 3.0      # N: past the 2D frictionless press's stop (1.25-1.62 N, the guide's "Frictionless presses")


def attempt(sc):
    """(the result or the kept state, CPU s): a press that stops is kept at its last converged state."""
    c = time.process_time()
    return solve(sc), time.process_time() - c


def show(name, r, cpu):
    stop = f"stops at {r.applied_force:.4f} N, cause {r.stop.cause}" if r.stop else f"reaches {r.applied_force:.4f} N"
    travel = r.contact_record()["travel_m"]
    print(f"{name}: {stop} (travel {1e3 * travel:.4f} mm), V/F {r.voltages()['taxel_0_0'] / r.applied_force:.5f} V/N, "
          f"{cpu:.0f} s CPU", flush=True)


def main():
    three = "--3d" in sys.argv
    sc = load("thesis-pzt-probe-3d" if three else "thesis-pzt-probe-2d").replace(
        **{"load.friction": "frictionless", "load.force": 1.0 if three else FORCE_2D})
    first, cpu = attempt(sc)
    show(f"asked for {sc.load.force:g} N", first, cpu)
    if first.stop is None:
        return
    again, cpu = attempt(first.scene)            # its scene carries the force reached
    show(f"pressed again to {first.applied_force:.4f} N in one target", again, cpu)


if __name__ == "__main__":
    main()
