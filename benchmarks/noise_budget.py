"""The noise floor of the thesis PZT taxel, chain by chain: the noise guide's table
(docs/guide/noise-and-tolerances.md).

    python benchmarks/noise_budget.py

The thesis PZT taxel (`thesis-pzt-frequency`: FEM transfer function, charge amplifier
and 50 Hz notch) over the default band (readout.band, 1-300 Hz), three chains: the analog chain alone, the thesis
bench's ADC (`thesis-bench` rig: 16 bit, +-10 V, 2 kHz), and the bench with the
simulated rig's mains pickup (5, 1.5, 0.5 mV at 50, 150, 250 Hz; the main job's
noise-budget step). Prints the rms noise, the minimum detectable force, the dynamic
range and the largest shares (taxel.analyses.solves.noise).
"""

from __future__ import annotations

import time

from taxel import load
from taxel.analyses.solves.noise import noise
from taxel.studies.bench.rig import load_rig
from taxel.studies.bench.signals import Settings


def main() -> None:
    base = load("thesis-pzt-frequency")
    bench = load_rig("thesis-bench")
    cases = [("amplifier only (no ADC)", base, None),
             ("thesis bench ADC", base, bench),
             ("+ the simulated rig's hum", base.replace(**{"readout.hum": list(Settings().hum_V)}), bench)]
    print(f"{'chain':<26}{'noise rms':>12}{'min. force':>12}{'dyn. range':>12}  largest shares   (time)")
    for label, scene, rig in cases:
        t0 = time.perf_counter()
        res = noise(scene, rig)
        out = res.outputs()
        shares = sorted(res.shares().items(), key=lambda kv: -kv[1])[:3]
        share_text = ", ".join(f"{k} {100 * v:.3g} %" for k, v in shares)
        print(f"{label:<26}{1e6 * out['noise_rms']:>9.3g} uV{1e6 * out['min_detectable_force']:>9.3g} uN"
              f"{out['dynamic_range']:>9.3g} dB  {share_text}   ({time.perf_counter() - t0:.1f} s)")


if __name__ == "__main__":
    main()
