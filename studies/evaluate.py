"""Evaluating one design point: a pure function of its scene, runs on any worker."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from taxel.analyses import frequency, solve_static
from taxel.fem.newton import NewtonError
from taxel.scene import Scene, parse, replace

OUTPUTS = ("voltage", "charge", "crosstalk", "max_strain", "frequency_response")


def evaluate(scene_data: dict, outputs: tuple[str, ...]) -> dict:
    """Solve one design point and return its outputs (JSON-ready, SI units): the
    per-taxel voltages and charges asked for, and the result's named outputs
    (`StaticResult.outputs()`) under "outputs"."""
    scene = parse({**scene_data, "name": "point"})
    t0 = time.perf_counter()
    sol, requested = solve_reached(scene)
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
    if requested is not None:             # Newton stopped short: the outputs are at the last converged load
        res["requested_load"] = requested
    res["seconds"] = time.perf_counter() - t0
    return res


def solve_reached(scene: Scene, tries: int = 3):
    """(result, requested load or None): the static solve, or, where Newton stops short
    of the load (a Yeoh silicone under a pressure patch creases at the patch edge,
    fem.newton), the solve at the last converged load it names (load.force, or
    load.pressure for kind = "pressure"), with the load asked for."""
    key = "pressure" if scene.load.kind == "pressure" else "force"
    requested = getattr(scene.load, key)
    for _ in range(tries):
        try:
            sol = solve_static(scene)
            return sol, (None if getattr(scene.load, key) == requested else requested)
        except NewtonError as exc:
            last = exc.result.load_factors[-1] if exc.result is not None and exc.result.load_factors else 0.0
            if last <= 0:
                raise
            scene = replace(scene, **{f"load.{key}": last * getattr(scene.load, key)})
    raise NewtonError(f"Newton stopped short of the load {tries} times (last at {getattr(scene.load, key):.4g}); "
                      "lower the load")


def evaluate_safely(scene_data: dict, outputs) -> tuple[str, dict | None, str | None]:
    """(status, result, error): a failure is recorded with the point, the study goes on."""
    try:
        return "done", evaluate(scene_data, outputs), None
    except Exception as exc:            # recorded with the point; the study goes on
        return "failed", None, f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
