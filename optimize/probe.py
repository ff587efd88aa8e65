"""The rig's press as an optimizer's model: a rigid probe pressed into (Yeoh) silicone.

An optimization takes it with a [press] table:

    [press]
    shape = "flat"              # flat | sphere (3D) | cylinder (2D): the probe
    radius = "2 mm"             # punch radius (half-width in 2D) or sphere radius
    edge_radius = "0.2 mm"      # a flat punch's rounded edge
    force = "1 N"               # the operating force (default: the base scene's load.force)
    silicone = "yeoh"           # the silicone law under the probe (yeoh | linear)
    friction = "sticking"       # sticking | frictionless
    step = 0.05                 # the tangent's force step, relative
    force_range = ["0.5 N", "2 N"]   # optional: the objectives over a force range instead
    range_points = 4            # forces in the range, evenly spaced, ends included

The default probe is the one the project's contact benchmarks and the thesis bench's
press use (benchmarks/contact_taxel.py): a 4 mm flat punch with a 0.2 mm edge radius,
centred on the pressed taxel (the base scene's load.taxel), sticking, on Yeoh silicone.
The rig file (studies/bench) describes the electronics, not the probe; a scene with a
contact indenter (load.kind = "probe", load.contact = true) as the base gives its own
probe, which then wins over these defaults for every key the table does not set.

Objectives of a press, for the pressed taxel's open-circuit voltage V(F) along the
force-controlled press (fem.contact, every state converged):

    sensitivity          = |V(F)| / F               (V/N, the secant at the operating force F)
    tangent_sensitivity  = |dV/dF| at F             (V/N, the small-signal slope there)
    crosstalk            = max_j |V_j(F)| / |V(F)|  (neighbours j, the same press at F)
    max_strain           = the silicone's largest principal strain at F

Over a force range (force_range = [F_lo, F_hi], range_points forces F_i evenly spaced,
ends included) one press continues through every F_i; the secant |V(F_i)| / F_i and the
crosstalk at each F_i are recorded (`range`), and the objectives are the worst of them:

    sensitivity          = min_i |V(F_i)| / F_i     (the least sensitive force of the range)
    crosstalk            = max_i crosstalk(F_i)
    tangent_sensitivity  = |dV/dF| at F_hi, max_strain at F_hi

so a design is ranked by its worst force, not by one force. The scene's load.force is
F_hi (its `taxel solve` is the range's last state); force is not then read.

At one force, the secant, crosstalk and largest strain are those of `taxel solve` of the same scene
(the same press to F, the same StaticResult). The tangent continues the press to
F (1 + h) and F (1 + 2 h) and differentiates the quadratic through the three states at
F (second order in h). h = 0.05, not smaller: two presses of the same scene to nearby
forces from zero differ by about 5e-4 in voltage (the sticking set depends on the
force-control steps; measured on the thesis row, coarse mesh), which a difference over
h = 0.02 would turn into 2.5 % of the slope; along one continued press the states share
their path. Still, under sticking contact the states depend on the load steps: the
central difference along a press through 0.9, 1 and 1.1 F is 0.85 % below this tangent,
the chord of independent presses to 0.9 and 1.1 F 1.1 % (thesis row, coarse mesh;
tests/test_probe_front.py), so the tangent is good to about 1 %. On linear silicone the tangent equals the secant only when the contact area does
not change; under a flat punch it hardly does.
"""

from __future__ import annotations

import json
import time
from typing import Any, Literal

import numpy as np
from pydantic import Field

from taxel import units as U
from taxel.schema import Strict

PROBE_METRICS = ("sensitivity", "tangent_sensitivity", "crosstalk", "max_strain")


class ProbePress(Strict):
    """The [press] table of an optimization: the rigid probe, its force and the silicone."""
    shape: Literal["flat", "sphere", "cylinder"] | None = None
    radius: Any = None
    edge_radius: Any = None
    force: Any = None
    silicone: Literal["yeoh", "linear"] = "yeoh"
    friction: Literal["sticking", "frictionless"] | None = None
    step: float = Field(0.05, gt=0, le=0.2)
    force_range: list[Any] | None = Field(None, min_length=2, max_length=2)
    range_points: int = Field(4, ge=2, le=20)


def range_forces(press: ProbePress) -> list[float] | None:
    """The forces (N) of the press's force range, lowest first; None at one force."""
    if press.force_range is None:
        return None
    lo, hi = (U.in_unit(v, "N")[0] for v in press.force_range)
    return [float(f) for f in np.linspace(lo, hi, press.range_points)]


DEFAULT_PROBE = {"shape": "flat", "radius": "2 mm", "edge_radius": "0.2 mm", "friction": "sticking"}


def press_scene(data: dict, press: ProbePress) -> dict:
    """The scene data `data` pressed by the [press] probe at its force: load.kind =
    "probe", contact = true, centred on the scene's pressed taxel; the silicone law
    set; static. A base scene's own contact indenter keeps what the table leaves unset."""
    data = json.loads(json.dumps(data))
    load = data.setdefault("load", {})
    own = load.get("kind") == "probe" and load.get("contact")
    for key, default in DEFAULT_PROBE.items():
        value = getattr(press, key)
        if value is not None:
            load[key] = value
        elif not own or key not in load:
            load[key] = default
    if press.force_range is not None:
        load["force"] = press.force_range[1]
    elif press.force is not None:
        load["force"] = press.force
    load.update(kind="probe", contact=True)
    load.pop("pressure", None)
    load.pop("profile", None)
    data.setdefault("model", {})["silicone"] = press.silicone
    data.setdefault("analysis", {})["type"] = "static"
    return data


def check(press: ProbePress, error) -> None:
    """One-line `error` when the table's lengths or force are not quantities."""
    for key, unit in (("radius", "m"), ("edge_radius", "m"), ("force", "N")):
        v = getattr(press, key)
        if v is not None:
            try:
                if not U.in_unit(v, unit)[0] > 0 and key != "edge_radius":
                    raise error(f"press.{key} must be positive, got {v!r}")
            except U.UnitError as exc:
                raise error(f"press.{key}: {exc}") from None
    if press.force_range is not None:
        try:
            forces = range_forces(press)
        except U.UnitError as exc:
            raise error(f"press.force_range: {exc}") from None
        if not 0 < forces[0] < forces[-1]:
            raise error(f"press.force_range must be two forces, the lower first and above 0 N, got "
                        f"{press.force_range!r}; write e.g. [\"0.5 N\", \"2 N\"]")


def press_metrics(data: dict, press: ProbePress | None = None, estimate: bool = False) -> dict:
    """PROBE_METRICS of a pressed scene's data (press_scene's output) under the [press]
    table `press` (its tangent step and force range; defaults without), the voltage-force
    states of the press, its force and the seconds it took (JSON-ready, SI). With
    `estimate`, also the result's estimated error (taxel.analyses.accuracy.error_estimate.estimate:
    discretisation by the estimator's route for this mesh, no model form, the material law
    0 on Yeoh), as "error": {output: {discretisation, model_form, material, total}}."""
    from taxel.analyses import problem
    from taxel.analyses.results import StaticResult
    from taxel.fem.assembly import assemble
    from taxel.fem.contact import Press
    from taxel.scene import parse
    press = press or ProbePress()
    step = press.step
    t0 = time.perf_counter()
    scene = parse({**data, "name": "press"})
    prob = problem(scene)
    pr = Press(assemble(prob), prob.indenter)
    F = float(scene.load.force)
    span = []
    for Fi in range_forces(press) or []:        # a force range: one press through its forces
        if Fi < F * (1 - 1e-9):
            pr.force(Fi)
            r = StaticResult(scene, pr.solution(), {}, yeoh=prob.hyperelastic).outputs()
            span.append({"force": pr.res.points[-1].force, "sensitivity": abs(r["sensitivity"]),
                         "crosstalk": r.get("crosstalk"), "max_strain": r["max_strain"]})
    pr.force(F)                                  # as taxel solve: one force-controlled press to F
    sol = pr.solution()
    res = StaticResult(scene, sol, {}, yeoh=prob.hyperelastic)
    out = res.outputs()
    pressed = res.pressed
    f0, v0 = pr.res.points[-1].force, pr.res.points[-1].voltages[pressed]
    states = [(f0, v0)]
    for k in (1, 2):
        p = pr.force(F * (1 + k * step))
        states.append((p.force, p.voltages[pressed]))
    m = {"sensitivity": abs(out["sensitivity"]), "tangent_sensitivity": abs(tangent(states)),
         "crosstalk": out.get("crosstalk"), "max_strain": out["max_strain"], "force": f0,
         "pressed": pressed, "voltage": v0, "states": states,
         "curve": [(p.force, p.voltages[pressed]) for p in sorted(pr.res.points, key=lambda q: q.travel)]}
    if span:
        span.append({"force": f0, "sensitivity": m["sensitivity"], "crosstalk": m["crosstalk"],
                     "max_strain": m["max_strain"]})
        m["range"] = span
        m["sensitivity"] = min(r["sensitivity"] for r in span)
        if all(r["crosstalk"] is not None for r in span):
            m["crosstalk"] = max(r["crosstalk"] for r in span)
        m["worst force (sensitivity, crosstalk)"] = (
            min(span, key=lambda r: r["sensitivity"])["force"],
            max(span, key=lambda r: r["crosstalk"] or 0.0)["force"])
    if estimate:
        from taxel.analyses.accuracy.error_estimate import estimate as error_of
        e = error_of(scene, res, model_form=False)
        m["error"] = {k: {**o.record(), "total": o.total} for k, o in e.outputs.items()}
        m["error method"] = e.method
    m["seconds"] = time.perf_counter() - t0
    return m


def tangent(states) -> float:
    """dV/dF at the first of three (F, V) states: the derivative of the quadratic through them."""
    (f0, v0), (f1, v1), (f2, v2) = states
    c = np.polyfit(np.array([f0, f1, f2]) - f0, [v0, v1, v2], 2)
    return float(c[1])


def press_safely(data: dict, press: ProbePress | None = None, estimate: bool = False) -> tuple[str, dict | None, str | None]:
    """(status, result, error) of press_metrics: a failed press is recorded, the search goes on."""
    try:
        return "done", press_metrics(data, press, estimate), None
    except Exception as exc:            # recorded with the design; the optimizer treats it as missing
        return "failed", None, f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"


def press_key(data: dict, press: ProbePress | None = None, estimate: bool = False) -> str:
    """The store key of a press: the pressed scene's point key with the tangent's step
    (and the force range and the error estimate, when asked)."""
    import hashlib
    from taxel.studies.store import point_key
    press = press or ProbePress()
    forces = range_forces(press)
    tail = (f" range {','.join(f'{f:.9g}' for f in forces)}" if forces else "") + (" estimate" if estimate else "")
    return hashlib.sha256(f"{point_key(data)} probe-press step {press.step:g}{tail}".encode()).hexdigest()


def stored_press(store, data: dict, press: ProbePress | None = None, params=None,
                 estimate: bool = False) -> tuple[str, dict | None, str | None]:
    """press_safely through a study store (studies.store.Store): the key is the pressed
    scene's point key with the press's step and range, so a design is pressed once."""
    from taxel.scene import SceneError
    try:
        key = press_key(data, press, estimate)
    except SceneError as exc:
        return "failed", None, f"SceneError: {exc}"
    if store is not None:
        row = store.get(key)
        if row is not None and row["status"] == "done":
            return "done", row["result"], None
    status, result, error = press_safely(data, press, estimate)
    if store is not None:
        store.put(key, {**(params or {}), "probe press": True}, status, result, error,
                  (result or {}).get("seconds", 0.0))
    return status, result, error
