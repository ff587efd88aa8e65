"""How the one default noise band moves the numbers: the CHANGELOG's entry (issue 56).

    python benchmarks/default_band.py

Before, `taxel solve` took the readout's numbers over the scene's analysis band (1-1000 Hz)
and `taxel optimize` its noise metrics over [resolution] band (1-100 Hz); both now take the
scene's readout.band (taxel.scene.NOISE_BAND, 1-300 Hz: what human mechanoreceptors sense).
On the thesis PZT taxel (`thesis-pzt-frequency`: charge amplifier and 50 Hz notch; its static
solve) the quasi-static budget (taxel.analyses.solves.at_readout, the optimizer's route) over
each band, and the FEM sweep's budget (taxel.analyses.solves.noise.noise) over the new default
against it: the quasi-static route's error at the band's top.
"""

from __future__ import annotations

from taxel import load
from taxel.analyses import solve_static
from taxel.analyses.solves.noise import noise, quasi_static_noise


def main() -> None:
    scene = load("thesis-pzt-frequency")
    o = solve_static(scene.replace(**{"analysis.type": "static"})).outputs()
    print(f"{'band':<22}{'S_r max (V/N)':>14}{'S_B (V/N)':>11}{'min. force':>12}{'force range':>13}")
    for label, band in (("1-1000 Hz (old solve)", (1.0, 1000.0)), ("1-100 Hz (old optimize)", (1.0, 100.0)),
                        ("1-300 Hz (the default)", None)):
        q = quasi_static_noise(scene, o["sensitivity"], o["charge_sensitivity"], band=band)
        print(f"{label:<22}{q.gain.max():>14.4g}{q.band_sensitivity:>11.4g}{1e6 * q.min_detectable_force:>9.4g} uN"
              f"{q.saturation_force:>11.4g} N")
    q = quasi_static_noise(scene, o["sensitivity"], o["charge_sensitivity"])
    f = noise(scene)
    print(f"quasi-static / FEM sweep over {f.band[0]:g}-{f.band[1]:g} Hz: band sensitivity "
          f"{q.band_sensitivity / f.band_sensitivity - 1:+.2%}, min. force {q.min_detectable_force / f.min_detectable_force - 1:+.2%}")


if __name__ == "__main__":
    main()
