"""The model side of thesis chapter 4, in one run: figures and the statements.

    python -m taxel.jobs.thesis_ch4 [OUT_DIR]      (default out/thesis-ch4)

1. step force through the 500 MOhm input: first-order decay, tau = R C_p (Fig. 4.4);
2. half-sine impulse (Fig. 4.8);
3. chirp 0-100 Hz over 8 s through the charge amplifier, with and without the
   50 Hz notch: FFT(output) / FFT(force) against the frequency sweep (Fig. 4.13-4.16);
4. silicone thickness 0, 1 and 2 mm in total (0, 0.5 + 0.5, 1 + 1 mm) on the
   frequency response (Fig. 4.19);
5. FEM against the lumped 3-DoF model (Fig. 4.21).

Every model run is an analysis of a scene (taxel.analyses: frequency, transient,
lumped_response); the figures are drawn from those results (taxel.reports.thesis_ch4).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from taxel import analyses
from taxel.reports import thesis_ch4 as figures
from taxel.scene import Scene, load


def sweep_scene(scene: Scene, freqs: np.ndarray, spacing: str, **changes) -> Scene:
    """`scene` as a frequency analysis over `freqs` (evenly spaced in `spacing`)."""
    return scene.replace(**{"analysis.f_min": float(freqs[0]), "analysis.f_max": float(freqs[-1]),
                            "analysis.points": len(freqs), "analysis.spacing": spacing, **changes})


def capacitance(scene: Scene) -> float:
    """|C| of the first electrode's port at 0.1 Hz (a direct frequency analysis)."""
    res = analyses.frequency(sweep_scene(scene, np.array([0.1, 0.2]), "linear", **{"analysis.method": "direct"}))
    return abs(res.port.C[0, 0, 0])


def time_constant(res: analyses.TransientResult) -> float:
    """The first-order decay time (s) of a step's voltage between 0.3 and 4 s."""
    t, v = res.t, res.output[:, 0]
    late = (t > 0.3) & (t < 4)
    return -1 / np.polyfit(t[late], np.log(np.abs(v[late])), 1)[0]


def main(out="out/thesis-ch4"):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    base = load("thesis-pzt-frequency")
    lines = []

    # 1, 2: step and impulse through the resistor
    C_p = capacitance(base)
    step, impulse = (analyses.transient(load(n)) for n in ("thesis-pzt-step", "thesis-pzt-impulse"))
    figures.step_impulse([step, impulse], out / "step-impulse.png")
    lines.append(f"step response: first order, tau = {time_constant(step):.2f} s (R C_p = "
                 f"{step.scene.readout.R * C_p:.2f} s; thesis measured 1.7 and 3.1 s on two taxels)")
    lines.append(f"impulse response: peak {impulse.output[:, 0].min() * 1e3:.1f} mV, then a decay with the same tau")

    # 3: chirp through the charge amplifier, with and without the notch
    chirp = load("thesis-pzt-chirp")
    transients = {notch: analyses.transient(chirp.replace(**{"readout.notch": notch})) for notch in (False, True)}
    band, _ = figures.chirp_ratio(transients[False])
    sweeps = {notch: analyses.frequency(sweep_scene(base, band, "linear", **{"readout.notch": notch}))
              for notch in (False, True)}
    figures.chirp(transients, sweeps, out / "chirp.png")
    lines.append("chirp 0-100 Hz / 8 s: the FFT ratio follows the sweep; the notch removes 50 Hz (Fig. 4.16)")

    # 4: silicone thickness
    fq = np.geomspace(1, 100, 60)
    thick = {2 * k: analyses.frequency(sweep_scene(base, fq, "log", **{"array.silicone_above": k,
                                                                       "array.silicone_below": k}))
             for k in (0.0, 0.5e-3, 1e-3)}
    figures.silicone_thickness(thick, out / "silicone-thickness.png")
    g0, g1, g2 = (abs(thick[k].output[np.argmin(abs(fq - 30)), 0]) for k in (0.0, 1e-3, 2e-3))
    lines.append(f"silicone 0 / 1 / 2 mm in total at 30 Hz: {g0:.3g} / {g1:.3g} / {g2:.3g} V/N. Thesis: "
                 f"silicone lowers the output, 1 -> 2 mm raises it again. Model: "
                 f"{'agrees' if g1 < g0 and g2 > g1 else 'does not agree'}"
                 + ("" if g1 < g0 and g2 > g1 else " (in the model the embedded taxel gives MORE charge than "
                    "the bare one: the silicone flowing sideways stretches the piezo in its plane, a d31 "
                    "contribution of the same sign as d33, while the bare patch, bonded to the rigid base "
                    "in this model, is held laterally; the experiment's bare taxel sat on other supports)"))

    # 5: FEM vs lumped
    fem = analyses.frequency(sweep_scene(base, fq, "log"))
    lumped = analyses.lumped_response(sweep_scene(base, fq, "log"))
    figures.fem_vs_lumped(fem, lumped, out / "fem-vs-lumped.png")
    ratio = np.median(np.abs(fem.output[:, 0]) / np.abs(lumped.output))
    lines.append(f"FEM / lumped gain: {ratio:.2f} (median over 1-100 Hz): same shape (the amplifier sets "
                 "it below the silicone resonances), level set by the lateral flow the 1-D model lacks")
    (out / "statements.txt").write_text("\n".join(lines) + "\n")
    for line in lines:
        print(line)
    print(f"figures in {out}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
