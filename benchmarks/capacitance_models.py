"""The pressed taxel's capacitance in each model of the thesis PZT and PVDF designs: the
2D section (plane strain, thesis-*-3x3-2d), the 3D array (thesis-*-3x3-3d) and the free
parallel plate eps33^T A / t (fem.readout's lumped model), as the model ladder shows them.

    python benchmarks/capacitance_models.py      # about 2 minutes on 2 cores (two 3D solves)

Printed: each capacitance, its ratio to the parallel plate, and the check Q_sc / V_oc = C
of each static solve.
"""

from __future__ import annotations

import os
import time

import taxel
from taxel.analyses import lumped_model


def main():
    print("scene                 C (model)      C / plate - 1    |Q_sc/V_oc| / C - 1   seconds")
    for piezo in ("pzt", "pvdf"):
        plate = None
        for model in ("2d", "3d"):
            t0 = time.perf_counter()
            r = taxel.solve(taxel.load(f"thesis-{piezo}-3x3-{model}"))
            e = r.electrodes[r.pressed]
            plate = lumped_model(r.scene).C_p
            print(f"thesis-{piezo}-3x3-{model:3s}  {e.capacitance:.5g} F  {e.capacitance / plate - 1:+12.5%}   "
                  f"{abs(e.short_circuit_charge / e.voltage) / e.capacitance - 1:+12.2e}        "
                  f"{time.perf_counter() - t0:.0f}", flush=True)
        print(f"parallel plate {piezo:5s}  {plate:.5g} F")
    print(f"load average {os.getloadavg()}")


if __name__ == "__main__":
    main()
