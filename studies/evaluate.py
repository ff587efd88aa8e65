"""Evaluating one design point: a pure function of its scene, runs on any worker."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from taxel.analyses import frequency, solve
from taxel.scene import parse, replace

OUTPUTS = ("voltage", "short_circuit_charge", "crosstalk", "max_strain", "frequency_response")


def evaluate(scene_data: dict, outputs: tuple[str, ...]) -> dict:
    """Solve one design point and return its outputs (JSON-ready, SI units): the
    per-taxel voltages and charges asked for, and the result's named outputs
    (`StaticResult.outputs()`) under "outputs"."""
    scene = parse({**scene_data, "name": "point"})
    t0 = time.perf_counter()
    # a point that stops short of its load is kept at its last converged state (sol.stop)
    sol = solve(scene if scene.analysis.type == "static" else replace(scene, **{"analysis.type": "static"}))
    res: dict[str, Any] = {}
    taxels = {k: e for k, e in sol.electrodes.items() if e.state != "reference"}
    pressed = sol.pressed
    if "voltage" in outputs:
        res["voltage"] = {k: e.voltage for k, e in taxels.items()}
    if "short_circuit_charge" in outputs:
        res["short_circuit_charge"] = {k: e.short_circuit_charge for k, e in taxels.items()}
    named = sol.outputs()
    if "crosstalk" in outputs and "crosstalk" in named and pressed in taxels and len(taxels) > 1:
        res["crosstalk"] = named["crosstalk"]
    if "max_strain" in outputs:
        res["max_strain"] = named["max_strain"]
    # the named outputs (StaticResult.outputs: sensitivity, charge_sensitivity, pressed_voltage, ...)
    res["outputs"] = named
    if "frequency_response" in outputs:
        fr = frequency(replace(scene, **{"analysis.method": "reduced"}))
        res["frequency_response"] = {"freqs": fr.freqs.tolist(),
                                     **{k: np.abs(fr.output[:, i]).tolist() for i, k in enumerate(fr.names)}}
    res["pressed"] = pressed
    res["force"] = sol.applied_force
    res["model_note"] = sol.model_note
    if sol.stop is not None:              # stopped short: the outputs are at the last converged load
        res["requested_load"] = sol.stop.requested
        res["stop"] = sol.stop.message
    res["seconds"] = time.perf_counter() - t0
    return res


def evaluate_safely(scene_data: dict, outputs) -> tuple[str, dict | None, str | None]:
    """(status, result, error): a failure is recorded with the point, the study goes on."""
    try:
        return "done", evaluate(scene_data, outputs), None
    except Exception as exc:            # recorded with the point; the study goes on
        return "failed", None, f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
