"""The answer's designs through the thesis bench's readout (main job): for the recommended
and the thesis design of an optimization folder, the charge per newton, the volts per
newton at the readout's output, the minimum detectable force and the force range to
saturation, from the answer's own sensitivity (optimize.answer_folder.FolderAnswer) through
the bench's chain: the charge amplifier and notch of the thesis-pzt-frequency scene
with the simulated rig's mains hum, on the thesis bench's ADC.

Physics: below the first resonance a taxel is a charge source, Q_sc = C_p V_oc; the
answer gives V_oc per newton (its model: the rig's probe on Yeoh silicone, 3D), C_p is
the 3D model's capacitance of the taxel, which is the free parallel plate
eps33^T A / t (fem.readout's lumped model): the piezo is free in its plane under
silicone seven orders softer, and the 3D FEM gives the thesis PZT and PVDF taxels the
plate's value within 0.01 % (benchmarks/capacitance_models.py;
tests/test_piezo_plate.py checks the free plate). The 2D section's |Q_sc / V_oc| is
recorded beside it (capacitance_2d_F, one static solve of the design on the base
scene): the plane section holds the piezo's strain along the depth at zero, about
19 % less for PZT, and is not the answer's model. The chain is
taxel.analyses.solves.noise.quasi_static_noise on (V_oc, C_p V_oc) per newton. Written to
OUT/answer-readout.json by the answer's owner (FolderAnswer.write_readout); the owner, the
report's answer and its model ladder read it. Cost: one
2D solve per design.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

CHAIN_SCENE = "thesis-pzt-frequency"       # its [readout]: the thesis's charge amplifier and notch
RIG = "thesis-bench"


def bench_chain() -> dict:
    """The bench's readout as scene data: CHAIN_SCENE's [readout] (the thesis's charge
    amplifier and notch) with the simulated rig's mains hum."""
    from taxel import api
    from taxel.schema import to_data
    from taxel.studies.bench.signals import Settings
    chain = to_data(api.load(CHAIN_SCENE))["readout"]
    chain["hum"] = [f"{v:g} V" for v in Settings().hum_V]          # the simulated rig's mains pickup
    return chain


def answer_readout(front_dir: Path) -> Path | None:
    """Write OUT/answer-readout.json for the answer of `front_dir` (a built-in optimization's folder)."""
    from taxel import api
    from taxel.analyses import lumped_model
    from taxel.analyses.solves.noise import quasi_static_noise
    from taxel.optimize import spec as O
    from taxel.optimize.answer_folder import FolderAnswer
    from taxel.scene import parse
    from taxel.studies.bench.rig import load_rig
    t0 = time.perf_counter()
    a = FolderAnswer.read(front_dir)
    if a is None:
        return None
    prob = O.load_optimization(front_dir.name)
    chain = bench_chain()
    rig = load_rig(RIG)
    r = api.load(CHAIN_SCENE).readout
    rows = []
    for d in a.answer_designs(("recommended", a.reference.label)):
        data = prob.scene_data(d.vector(prob.names))
        data["readout"] = chain
        scene = parse({**data, "name": f"{front_dir.name}-{d.label}"})
        res = api.solve(scene)
        e = res.electrodes[res.pressed]
        c_2d = abs(e.short_circuit_charge / e.voltage)
        c_p = lumped_model(scene).C_p                  # the 3D model's: the free parallel plate (docstring)
        s = abs(d.metrics["sensitivity"])
        nr = quasi_static_noise(scene, s, s * c_p, rig)
        shares = nr.shares()
        rows.append({"role": d.label, "x_mm": d.in_units(), "capacitance_F": c_p, "charge_sensitivity_C_per_N": s * c_p,
                     "capacitance_2d_F": c_2d,
                     "readout_V_per_N": float(np.max(nr.gain)), "band_Hz": list(nr.band),
                     "min_detectable_force_N": nr.min_detectable_force, "force_range_N": nr.saturation_force,
                     "saturation_by": nr.saturation_by, "hum_share": shares.get("hum residual", 0.0),
                     # the charge amplifier's corners: 1 / (2 pi R_f C_f) and 1 / (2 pi R_i (C_p + C_c))
                     "bandwidth_Hz": [1 / (2 * np.pi * r.R_f * r.C_f), 1 / (2 * np.pi * r.R_i * (c_p + r.C_c))],
                     "largest_noise_source": max(shares, key=shares.get)})
    return a.write_readout({"chain": f"{CHAIN_SCENE} readout with the simulated rig's hum, {RIG} ADC",
                            "readout": chain, "adc": {"rig": RIG, "bits": rig.adc.bits, "range_V": list(rig.adc.range)},
                            "designs": rows, "seconds": time.perf_counter() - t0})
