"""Evaluating one design point: a pure function of its scene, runs on any worker."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from taxel.analyses import StaticResult, frequency, solve_static, stopped_result
from taxel.fem.hyperelastic import NewtonError
from taxel.fem.contact import ContactError
from taxel.scene import Scene, parse, replace

OUTPUTS = ("voltage", "charge", "crosstalk", "max_strain", "frequency_response")


def evaluate(scene_data: dict, outputs: tuple[str, ...]) -> dict:
    """Solve one design point and return its outputs (JSON-ready, SI units): the
    per-taxel voltages and charges asked for, and the result's named outputs
    (`StaticResult.outputs()`) under "outputs"."""
    scene = parse({**scene_data, "name": "point"})
    t0 = time.perf_counter()
    sol = solve_reached(scene)
    res: dict[str, Any] = {}
    taxels = {k: e for k, e in sol.electrodes.items() if e.state != "reference"}
    pressed = sol.pressed
    if "voltage" in outputs:
        res["voltage"] = {k: e.voltage for k, e in taxels.items()}
    if "charge" in outputs:
        res["charge"] = {k: e.short_circuit_charge for k, e in taxels.items()}
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


def solve_reached(scene: Scene) -> StaticResult:
    """The static solve or, where it stops short of the load (a Yeoh silicone under a
    pressure patch creases at the patch edge; a press stops where it measured a cause), its
    last converged state, saying so (`StaticResult.stop`: the load asked for, why it
    stopped; taxel.analyses.stopped_result)."""
    try:
        return solve_static(scene)
    except (NewtonError, ContactError) as exc:
        reached = stopped_result(scene, exc)
        if reached is None:
            raise
        return reached


def evaluate_safely(scene_data: dict, outputs) -> tuple[str, dict | None, str | None]:
    """(status, result, error): a failure is recorded with the point, the study goes on."""
    try:
        return "done", evaluate(scene_data, outputs), None
    except Exception as exc:            # recorded with the point; the study goes on
        return "failed", None, f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
