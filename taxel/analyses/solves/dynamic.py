"""Frequency and transient analyses of a scene, through its readout chain.

frequency: fem.dynamics on the scene's dynamic model (per newton), then the readout
(fem.readout: resistor, charge amplifier, notch) as exact port post-processing.
transient: the force history in newtons (step, impulse, chirp of the scene's
force, or a CSV of time and force), then
  - open circuit or a resistor: fem.dynamics.transient (the resistor coupled in);
  - charge amplifier: the short-circuit charges, then the amplifier's ODE;
  - Yeoh silicone: full-order Newmark-Newton (open circuit);
and the notch as a digital filter.
"""

from __future__ import annotations

import numpy as np

from taxel.fem import readout as circuits
from taxel.fem import dynamics
from taxel.fem.assembly import assemble
from taxel.scene import AnalysisTable, Scene, SceneError
from taxel.analyses.model.problem import damping, problem, readout, scene_materials, with_silicone
from taxel.analyses.results import FrequencyResult, LumpedResult, TransientResult


def frequencies(a: AnalysisTable) -> np.ndarray:
    """The sweep frequencies of a scene's [analysis] table, Hz."""
    if a.spacing == "log":
        return np.geomspace(a.f_min, a.f_max, a.points)
    return np.linspace(a.f_min, a.f_max, a.points)


def force_history(a: AnalysisTable, amplitude: float) -> tuple[np.ndarray, np.ndarray]:
    """(t in s, force in N) of the scene's [analysis] input: a step (smooth ramp over
    `rise`), a half-sine impulse of `width`, a chirp from f0 to f1 over the duration
    (phase 2 pi (f0 t + (f1 - f0) t^2 / (2 T))), all of peak `amplitude`; or the
    CSV file's (time, force) resampled at dt."""
    if a.input == "csv":
        try:
            data = np.loadtxt(a.file, delimiter=",", comments="#", ndmin=2)
        except (OSError, ValueError) as exc:
            raise SceneError(f"analysis.file = '{a.file}': cannot read it as CSV of time (s), force (N): "
                             f"{str(exc).splitlines()[0]}") from None
        t = np.arange(0.0, data[-1, 0] + a.dt / 2, a.dt)
        return t, np.interp(t, data[:, 0], data[:, 1])
    t = np.arange(0.0, a.duration + a.dt / 2, a.dt)
    if a.input == "step":
        shape = np.clip(t / a.rise, 0, 1)
    elif a.input == "impulse":
        shape = np.where(t < a.width, np.sin(np.pi * t / a.width), 0.0)
    else:
        shape = np.sin(2 * np.pi * (a.f0 * t + (a.f1 - a.f0) * t ** 2 / (2 * a.duration)))
    return t, amplitude * shape


def frequency(scene: Scene, dm: dynamics.DynamicModel | None = None) -> FrequencyResult:
    """The scene's frequency sweep through its readout chain (per newton)."""
    dm = dm or dynamics.model(problem(scene))
    a = scene.analysis
    port = dynamics.sweep(dm, frequencies(a), a.method, a.tolerance)
    r = readout(scene)
    return FrequencyResult.from_port(scene, port, circuits.readout(port, r), r.label)


def transient(scene: Scene) -> TransientResult:
    """The scene's transient through its readout chain."""
    r = readout(scene)
    prob = problem(scene)
    if scene.model.silicone == "yeoh":
        amplitude = _amplitude(scene, prob)
        t, force = force_history(scene.analysis, amplitude)
        tr, iters = dynamics.transient_hyperelastic(prob, t, force)
        y = tr.V
    else:
        short = r.circuit == "charge_amplifier"
        dm = dynamics.model(prob, short=short)
        t, force = force_history(scene.analysis, dm.sy.applied_force)
        iters = None
        if short:
            tr = dynamics.transient(dm, t, force)
            C_p = np.diag(dynamics.direct(dynamics.model(prob), 1.0)[1].real)
            y = circuits.amplifier_in_time(t, tr.Q, 1 / C_p, r)
        else:
            tr = dynamics.transient(dm, t, force, R=r.R if r.circuit == "resistor" else None)
            y = tr.V
    if r.notch:
        y = circuits.notch_in_time(t, y, r)
    return TransientResult.from_transient(scene, tr, y, r.label, iters)


def _amplitude(scene: Scene, prob) -> float:
    """The load's total force in N (a pressure load: pressure x loaded area)."""
    if scene.load.kind != "pressure":
        return scene.load.force
    return assemble(with_silicone(prob, "linear")).applied_force


def lumped_model(scene: Scene, confined: bool = False) -> circuits.Lumped:
    """The 3-DoF lumped model of a taxel-array scene's taxel (fem.readout)."""
    a = scene.array
    if a is None:
        raise SceneError("the lumped model describes a taxel array scene ([array])")
    mats = scene_materials(scene)
    force = scene.load.force if scene.load.kind != "pressure" else scene.load.pressure * a.taxel_width ** 2
    return circuits.taxel_model(mats[a.piezo], mats[a.silicone], a.taxel_width, a.silicone_above,
                              a.piezo_thickness, a.silicone_below, force, damping(scene), confined)


def lumped_response(scene: Scene) -> LumpedResult:
    """The 3-DoF lumped model's answer to a single-taxel scene, through its readout."""
    lm = lumped_model(scene)
    f = frequencies(scene.analysis)
    port = dynamics.PortResponse(f, lm.V_oc(f)[:, None] / lm.force, np.full((len(f), 1, 1), 1 / lm.C_p),
                              ["lumped"], "lumped", 0.0)
    r = readout(scene)
    return LumpedResult(scene, lm, f, circuits.readout(port, r)[:, 0], r.label)
