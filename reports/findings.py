"""What a page found, in a few numbers, and where its results leave their model's range.

Headline numbers (label, value in an engineering unit) go on the page and on its
index card; banners (one sentence naming the number and the fix) go on top of the
page and into the index's run summary. The ranges checked:

- a linear silicone above the strain at which its estimated voltage error
  (`taxel.analyses.linear_error`) exceeds the scene's `model.tolerance`;
- a Newton stop (a Yeoh solve that returned the linear result, a study point
  that failed in Newton);
- a reduced (Krylov) sweep whose measured error is above its tolerance.

The numbers come from the results read back from their folders
(`taxel.analyses.read`), never from summary text.
"""

from __future__ import annotations

import numpy as np

from taxel.analyses import linear_error
from taxel.analyses import LINEAR_ERROR_PER_STRAIN
from taxel.reports.page import Banner, Headline
from taxel.reports.tables import eng, percent
from taxel.units import magnitude

MODEL_NAMES = {"plane_strain": "2D plane strain", "plane_stress": "2D plane stress", "axisymmetric": "axisymmetric",
               "3d": "3D"}


def model_label(scene) -> str:
    """The model a number comes from, for a person: model type, mesh and silicone law
    of a parsed scene (taxel.scene.Scene), e.g. "2D plane strain FEM, 0.5 mm mesh
    (0.1 mm at the piezo), linear silicone"."""
    m, mesh = scene.model, scene.mesh
    piezo = f" ({1e3 * mesh.piezo_size:.2g} mm at the piezo)" if mesh.piezo_size else ""
    return (f"{MODEL_NAMES.get(m.type, m.type)} FEM, {1e3 * mesh.size:.2g} mm mesh{piezo}, "
            f"{m.silicone} silicone")


def scene_model_label(scene_data: dict | None) -> str:
    """model_label of a folder's scene.json (its data); "" without one."""
    if not scene_data:
        return ""
    from taxel.scene import parse
    return model_label(parse({**scene_data, "name": scene_data.get("name", "scene")}))


def _linear_limit(tol: float) -> float:
    """The largest silicone strain at which the linear model stays within `tol`."""
    return tol / LINEAR_ERROR_PER_STRAIN


def static_numbers(sol) -> list[Headline]:
    """Sensitivity (V/N), crosstalk (%) and capacitance (pF) of the pressed taxel."""
    out = []
    p = sol.pressed
    model = model_label(sol.scene)
    if p is not None and sol.applied_force:
        e = sol.electrodes[p]
        out.append(Headline("open-circuit sensitivity", eng(abs(e.voltage) / sol.applied_force, "V/N", 3),
                            model))
        if sol.crosstalk is not None:
            out.append(Headline("crosstalk", percent(sol.crosstalk), model))
        out.append(Headline("capacitance", eng(e.capacitance, "F"), model))
    out.append(Headline("largest silicone strain", percent(sol.max_strain), model))
    return out


def static_banners(sol) -> list[Banner]:
    scene = sol.scene
    out = []
    tol = scene.model.tolerance
    linear = scene.model.silicone == "linear" or "returning the LINEAR" in sol.model_note
    est = linear_error(sol.max_strain)
    if linear and est > tol:
        out.append(Banner("range", f"Linear silicone outside its range: largest strain {100 * sol.max_strain:.3g} % "
                   f"(estimated voltage error {100 * est:.2g} % > tolerance {100 * tol:g} %; the linear model "
                   f"holds below {100 * _linear_limit(tol):.2g} % strain). Fix: set model.silicone = \"yeoh\" "
                   "(or \"auto\"), or a smaller force."))
    user = _user_silicone(scene)
    if user and sol.max_strain > _linear_limit(tol):
        out.append(Banner("range", _unfitted(user, sol.max_strain)))
    if "returning the LINEAR" in sol.model_note:
        out.append(Banner("range", f"Newton stopped: {sol.model_note}. Fix: a smaller force, or a stiffer silicone."))
    if sol.stop is not None:
        st = sol.stop
        fix = ("the penalty as the message says" if st.cause == "penalty" else "a smaller load"
               + (", or friction = \"sticking\" (the rig's probe on tacky silicone)"
                  if scene.load.contact and scene.load.friction == "frictionless" else ""))
        out.append(Banner("range", f"Stopped short of load.{st.load} = {eng(st.requested, st.unit)}: {st.message}. "
                          f"The numbers here are its last converged state, at {eng(getattr(scene.load, st.load), st.unit)}. "
                          f"Fix: {fix}."))
    return out


def _user_silicone(scene) -> str | None:
    """The name of the scene's silicone when it is the user's own law (a [materials] table)."""
    name = scene.array.silicone if scene.array is not None else None
    return name if name and name in scene.materials else None


def _unfitted(name: str, strain: float) -> str:
    return (f"Your silicone '{name}' is unfitted here: its law states no strain range it was fitted over, and the "
            f"largest strain reaches {100 * strain:.3g} %. A Yeoh law holds only over the strains of its test data. "
            "Fix: check the strain against the strain range of your tension test, or give a law fitted beyond it.")


def study_banners(rows: list[dict], scene_data: dict) -> list[Banner]:
    """Banners for a study's rows (tidy rows: max_strain SI, status, error)."""
    model = scene_data.get("model", {}) or {}
    silicone = model.get("silicone", "linear")
    tol = float(model.get("tolerance", 0.02))
    out = []
    done = [r for r in rows if r.get("status") == "done" and finite_number(r.get("max_strain")) is not None]
    user = (scene_data.get("array") or {}).get("silicone")
    if user in (scene_data.get("materials") or {}) and done:
        s = max(finite_number(r["max_strain"]) for r in done)
        if s > _linear_limit(tol):
            out.append(Banner("range", _unfitted(user, s)))
    if silicone == "linear" and done:
        bad = [r for r in done if linear_error(finite_number(r["max_strain"])) > tol]
        if bad:
            worst = max(bad, key=lambda r: finite_number(r["max_strain"]))
            s = finite_number(worst["max_strain"])
            where = ", ".join(str(v) for k, v in worst.items() if k not in _OUTPUT_KEYS and not k.startswith(
                ("voltage_", "short_circuit_charge_")))
            out.append(Banner("range", f"Linear silicone outside its range at {len(bad)} of {len(done)} points: up to "
                       f"{100 * s:.3g} % strain ({where}), an estimated voltage error of {100 * linear_error(s):.2g} % "
                       f"against a tolerance of {100 * tol:g} % (valid below {100 * _linear_limit(tol):.2g} % strain). "
                       "Fix: rerun with model.silicone = \"auto\" (Yeoh where needed) or read these points as "
                       "trends only. Out-of-range rows are shaded in the results table."))
    newton = [r for r in rows if r.get("status") == "failed" and "Newton" in str(r.get("error", ""))]
    if newton:
        out.append(Banner("range", f"Newton stopped at {len(newton)} points ({str(newton[0]['error'])[:120]}). Fix: "
                   "smaller forces, or model.silicone = \"auto\" to fall back to linear with its error stated."))
    return out


_OUTPUT_KEYS = {"status", "pressed_voltage", "sensitivity", "max_strain", "seconds", "error",
                "crosstalk", "charge_sensitivity", "readout_sensitivity", "readout_crosstalk", "min_detectable_force",
                "force_range"}


def frequency_banners(result) -> list[Banner]:
    """A reduced sweep (a FrequencyResult, read from its folder) whose measured error
    exceeds its scene's analysis.tolerance."""
    if getattr(result, "kind", None) != "frequency":
        return []
    err, tol = result.measured_error, result.scene.analysis.tolerance
    if err > tol:
        return [Banner("verification", f"Reduced (Krylov) sweep above its error bound: measured error {err:.2g} > "
                f"tolerance {tol:g}. Fix: set analysis.method = \"direct\", or a smaller analysis.tolerance.")]
    return []


def study_numbers(rows: list[dict], model: str) -> list[Headline]:
    done = [r for r in rows if r.get("status") == "done"]
    out = [Headline("points", f"{len(done)} of {len(rows)} solved", model)]
    v = [abs(finite_number(_pressed(r))) for r in done if finite_number(_pressed(r)) is not None]
    if v:
        out.append(Headline("pressed-taxel open-circuit |V|", f"{eng(min(v), 'V', 3)} to "
                                                              f"{eng(max(v), 'V', 3)}", model))
    return out


def front_numbers(front: dict, model: str) -> list[Headline]:
    """The cheap front's span and the thesis design's place against it (`model`: the
    cheap model's label)."""
    pts = sorted((r["crosstalk"], r["sensitivity_V_per_N"]) for r in front.get("front", []))
    out = []
    if pts:
        best = max(pts, key=lambda p: p[1])
        out.append(Headline("2D front", f"{len(pts)} designs, up to {eng(best[1], 'V/N', 3)} "
                                        f"at {percent(best[0])} crosstalk", model))
    ref = front.get("reference")
    if ref and pts:
        out.append(Headline("thesis design, 2D", f"{eng(ref['sensitivity'], 'V/N', 3)}, "
                                                 f"{percent(ref['crosstalk'])} crosstalk", model))
    return out


def verified_model(rec: dict) -> tuple[str, dict]:
    """(label, model settings) of the 3D model a verified front's answer (front-3d.json)
    stands on: the confirmation's finer mesh when there is one, else the coarse
    verification's."""
    confirmed = rec["answer"].get("confirmed")
    m = confirmed["model"] if confirmed else {k: str(v) for k, v in rec["verify_3d"].items()}
    law = "linear silicone"
    return (f"3D FEM, {m['mesh.size']} mesh ({m['mesh.piezo_size']} at the taxels, {m['mesh.piezo_layers']} "
            f"elements through the piezo), {law}"), m


def front_3d_numbers(rec: dict) -> list[Headline]:
    """A 3D-verified front's card lines (front-3d.json): the confirmed (finer-mesh)
    pair when there is one, else the coarse verification's."""
    a = rec["answer"]
    c = a.get("confirmed")
    t, b = (c["thesis"], c.get("best")) if c else (a["thesis_3d"], a.get("best_at_or_below_thesis_crosstalk"))
    model, _ = verified_model(rec)
    model += f" — ladder row {4 if c else 3}"            # reports.ladder.ROW: the finer mesh, else the verification's
    out = [Headline("thesis design, 3D", f"{eng(t['sensitivity_V_per_N'], 'V/N', 3)}, "
                                         f"{percent(t['crosstalk'])} crosstalk", model)]
    if b:
        gain = b.get("sensitivity_gain")
        out.append(Headline("best 3D-front design at or below the thesis crosstalk",
                            eng(b["sensitivity_V_per_N"], "V/N", 3)
                            + (f" ({100 * gain:+.1f} %)" if gain is not None else "")
                            + f", {percent(b['crosstalk'])} crosstalk", model))
    return out


def front_3d_banners(rec: dict) -> list[Banner]:
    """The 2D front against its 3D verification (front-3d.json): a 2D/3D disagreement
    in crosstalk larger than the 3D model's own error, and a corrected prediction that
    missed its 3D check by more than that."""
    from taxel.analyses.accuracy.error_estimate import CHEAP_3D_ERROR
    out = []
    ref = rec["reference"]
    c2, c3 = ref.get("crosstalk 2D"), ref.get("crosstalk 3D")
    s2, s3 = ref.get("sensitivity 2D (V/N)"), ref.get("sensitivity 3D (V/N)")
    if c2 and c3 and abs(c2 / c3 - 1) > CHEAP_3D_ERROR["crosstalk"]:
        out.append(Banner("disagreement", f"2D and 3D crosstalk differ {c2 / c3:.2g}x for the thesis design "
                          f"({percent(c2)} in 2D plane strain, ladder row 1; {percent(c3)} in 3D, ladder row 3; the 3D mesh's own crosstalk "
                          f"error is about {100 * CHEAP_3D_ERROR['crosstalk']:g} %); sensitivity "
                          f"{100 * (s2 / s3 - 1):+.1f} %. Trust the 3D values: the 2D front only ranks designs."))
    worst = None
    for d in rec.get("verified", []):
        pc, fc = d.get("predicted crosstalk"), d.get("crosstalk 3D")
        if pc and fc:
            miss = abs(pc / fc - 1)
            if worst is None or miss > worst[0]:
                worst = (miss, pc, fc, d)
    if worst and worst[0] > 2 * CHEAP_3D_ERROR["crosstalk"]:
        miss, pc, fc, d = worst
        x = ", ".join(f"{k.split(' (')[0].replace('_', ' ')} {v:.2f} mm" for k, v in d.items() if k.endswith("(mm)"))
        out.append(Banner("verification", f"The corrected (2D x 3D ratio) prediction failed its 3D check: it "
                          f"predicted {percent(pc)} crosstalk (ladder row 2) where 3D gives {percent(fc)} (ladder row 3; {x}). Only the "
                          "3D-verified values are shown as results; the predictions pick which designs to verify."))
    return out


def optimum_numbers(rec: dict, model: str) -> list[Headline]:
    units = rec.get("units", {})
    x = ", ".join(f"{k.replace('_', ' ')} {v:.3g} {units.get(k, '')}".strip() for k, v in rec["x"].items())
    out = [Headline("optimum", x, model)]
    m = rec.get("metrics") or {}
    if m.get("sensitivity") is not None:
        out.append(Headline("optimum sensitivity", eng(m["sensitivity"], "V/N", 3), model))
    if m.get("crosstalk") is not None:
        out.append(Headline("optimum crosstalk", percent(m["crosstalk"]), model))
    out.append(Headline("evaluations", f"{rec['evaluations']} ({'converged' if rec['success'] else 'not converged'})",
                        model))
    return out


def analysis_numbers(result) -> list[Headline]:
    """Peak response (frequency) or peak and final output (transient) of a result
    read from its folder (`result.outputs()`)."""
    kind = getattr(result, "kind", None)
    out = []
    if kind not in ("frequency", "transient"):
        return out
    from taxel.analyses.results.figures import readable
    model = model_label(result.scene) + f", {readable(result.label)}"
    o = result.outputs()                  # the pressed (or first) taxel's
    if kind == "frequency":
        out.append(Headline("readout output per newton at its peak",
                            f"{eng(o['readout_sensitivity'], 'V/N', 3)} at {o['peak_frequency']:.3g} Hz",
                            model))
        c = result.capacitance.get(result.pressed)
        if c:
            out.append(Headline("taxel capacitance", eng(c, "F"), model_label(result.scene)))
    else:
        out.append(Headline("peak output", eng(o["peak_output"], "V", 3), model))
        out.append(Headline("final output", eng(o["final_output"], "V", 3), model))
    return out


def comparison_banners(rows: list[dict], tol: float = 0.05) -> list[Banner]:
    """The model comparison (rows: model, sensitivity V/N; the last is 3D): a model off
    the 3D one by more than `tol` (the 3D mesh's own error and the estimator's
    model-form spread are about 1 %; 5 % is well beyond them)."""
    ref = next((r["v"] for r in rows if r["model"] == "3D" and r.get("v")), None)
    if not ref:
        return []
    bad = [(r["model"], r["v"] / ref - 1) for r in rows if r.get("v") and r["model"] != "3D"
           and abs(r["v"] / ref - 1) > tol]
    if not bad:
        return []
    return [Banner("disagreement", "Models disagree with 3D on this design: " + ", ".join(
        f"{m} {100 * d:+.0f} %" for m, d in bad) + " (the 3D model's own error is about 1 %). Trust 3D, or a "
        "model within a few % of it (2D plane strain, axisymmetric); a 2D plane-stress study (the thesis's Fig. 2.5) "
        "gives trends, not the sensor's voltage.")]


def _pressed(row: dict):
    """A row's pressed_voltage."""
    return row.get("pressed_voltage")


def finite_number(v):
    m = magnitude(v)
    return m if isinstance(m, float) and np.isfinite(m) else None
