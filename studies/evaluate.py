"""Evaluating one design point: a pure function of its scene, runs on any worker."""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from taxel.analyses import StaticResult, frequency, solve_static
from taxel.fem.newton import NewtonError
from taxel.fem.press_result import ContactError
from taxel.scene import Scene, parse, replace

OUTPUTS = ("voltage", "charge", "crosstalk", "max_strain", "frequency_response")


def evaluate(scene_data: dict, outputs: tuple[str, ...]) -> dict:
    """Solve one design point and return its outputs (JSON-ready, SI units): the
    per-taxel voltages and charges asked for, and the result's named outputs
    (`StaticResult.outputs()`) under "outputs"."""
    scene = parse({**scene_data, "name": "point"})
    t0 = time.perf_counter()
    reached = solve_reached(scene)
    sol = reached.result
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
    if reached.requested is not None:     # stopped short: the outputs are at the last converged load
        res["requested_load"] = reached.requested
        res["stop"] = reached.stop
    res["seconds"] = time.perf_counter() - t0
    return res


@dataclass
class Reached:
    """A static solve at the load asked for or, where it stopped short, at the last load it reached."""

    result: StaticResult
    requested: float | None = None   # the load asked for (N; Pa for a pressure patch; m for a travel), if stopped short
    stop: str | None = None          # why the solve stopped short (its message), if it did


def solve_reached(scene: Scene) -> Reached:
    """The static solve or, where it stops short of the load, its last converged state, with
    the load asked for and why it stopped: a Yeoh silicone under a pressure patch creases at
    the patch edge (fem.newton.NewtonError: the last converged load factor), a press stops
    where it measured a cause (fem.press_result.ContactError: its last converged state). The
    state is the stopped solve's own (the error's `.solution`), not a solve again at that
    load: a press depends on its path, and the 2D probe example, frictionless, pressed to its
    last converged 1.62 N in one target stops again, at 1.27 N. The result's scene carries
    the load reached (load.pressure, load.travel or load.force)."""
    try:
        return Reached(solve_static(scene))
    except (NewtonError, ContactError) as exc:
        if exc.solution is None:
            raise
        key = ("pressure" if scene.load.kind == "pressure" else
               "travel" if getattr(scene.load, "travel", None) is not None else "force")
        requested = getattr(scene.load, key)
        at = _reached_load(exc, key, requested)
        result = StaticResult(replace(scene, **{f"load.{key}": at}), exc.solution,
                              yeoh=scene.model.silicone != "linear")
        return Reached(result, requested, str(exc).splitlines()[0])


def _reached_load(exc: NewtonError | ContactError, key: str, requested: float) -> float:
    """The load at a stopped solve's last converged state, in the load's units."""
    if isinstance(exc, NewtonError):
        return exc.result.load_factors[-1] * requested
    last = exc.result.points[-1]
    return last.travel if key == "travel" else last.force


def evaluate_safely(scene_data: dict, outputs) -> tuple[str, dict | None, str | None]:
    """(status, result, error): a failure is recorded with the point, the study goes on."""
    try:
        return "done", evaluate(scene_data, outputs), None
    except Exception as exc:            # recorded with the point; the study goes on
        return "failed", None, f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
