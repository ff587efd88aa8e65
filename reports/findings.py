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
from taxel.analyses.static import LINEAR_ERROR_PER_STRAIN
from taxel.reports.tables import percent
from taxel.units import engineering, magnitude


def _linear_limit(tol: float) -> float:
    """The largest silicone strain at which the linear model stays within `tol`."""
    return tol / LINEAR_ERROR_PER_STRAIN


def static_numbers(sol) -> list[tuple[str, str]]:
    """Sensitivity (V/N), crosstalk (%) and capacitance (pF) of the pressed taxel."""
    out = []
    p = sol.pressed
    if p is not None and sol.applied_force:
        e = sol.electrodes[p]
        out.append(("sensitivity", engineering(abs(e.voltage) / sol.applied_force, "V/N", 3)))
        if sol.crosstalk is not None:
            out.append(("crosstalk", percent(sol.crosstalk)))
        out.append(("capacitance", f"{e.capacitance * 1e12:.4g} pF"))
    out.append(("largest silicone strain", percent(sol.max_silicone_strain)))
    return out


def static_banners(sol) -> list[str]:
    scene = sol.scene
    out = []
    tol = scene.model.tolerance
    linear = scene.model.silicone == "linear" or "returning the LINEAR" in sol.model_note
    est = linear_error(sol.max_silicone_strain)
    if linear and est > tol:
        out.append(f"Linear silicone outside its range: largest strain {100 * sol.max_silicone_strain:.3g} % "
                   f"(estimated voltage error {100 * est:.2g} % > tolerance {100 * tol:g} %; the linear model "
                   f"holds below {100 * _linear_limit(tol):.2g} % strain). Fix: set model.silicone = \"yeoh\" "
                   "(or \"auto\"), or a smaller force.")
    if "returning the LINEAR" in sol.model_note:
        out.append(f"Newton stopped: {sol.model_note}. Fix: a smaller force, or a stiffer silicone.")
    return out


def study_banners(rows: list[dict], scene_data: dict) -> list[str]:
    """Banners for a study's rows (tidy rows: max_strain SI, status, error)."""
    model = scene_data.get("model", {}) or {}
    silicone = model.get("silicone", "linear")
    tol = float(model.get("tolerance", 0.02))
    out = []
    done = [r for r in rows if r.get("status") == "done" and _num(r.get("max_strain")) is not None]
    if silicone == "linear" and done:
        bad = [r for r in done if linear_error(_num(r["max_strain"])) > tol]
        if bad:
            worst = max(bad, key=lambda r: _num(r["max_strain"]))
            s = _num(worst["max_strain"])
            where = ", ".join(str(v) for k, v in worst.items() if k not in _OUTPUT_KEYS and not k.startswith(
                ("voltage_", "charge_")))
            out.append(f"Linear silicone outside its range at {len(bad)} of {len(done)} points: up to "
                       f"{100 * s:.3g} % strain ({where}), an estimated voltage error of {100 * linear_error(s):.2g} % "
                       f"against a tolerance of {100 * tol:g} % (valid below {100 * _linear_limit(tol):.2g} % strain). "
                       "Fix: rerun with model.silicone = \"auto\" (Yeoh where needed) or read these points as "
                       "trends only.")
    newton = [r for r in rows if r.get("status") == "failed" and "Newton" in str(r.get("error", ""))]
    if newton:
        out.append(f"Newton stopped at {len(newton)} points ({str(newton[0]['error'])[:120]}). Fix: smaller "
                   "forces, or model.silicone = \"auto\" to fall back to linear with its error stated.")
    return out


_OUTPUT_KEYS = {"status", "pressed_voltage", "voltage_pressed", "sensitivity", "max_strain", "seconds", "error",
                "crosstalk"}


def frequency_banners(result) -> list[str]:
    """A reduced sweep (a FrequencyResult, read from its folder) whose measured error
    exceeds its scene's analysis.tolerance."""
    if getattr(result, "kind", None) != "frequency":
        return []
    err, tol = result.measured_error, result.scene.analysis.tolerance
    if err > tol:
        return [f"Reduced (Krylov) sweep above its error bound: measured error {err:.2g} > "
                f"tolerance {tol:g}. Fix: set analysis.method = \"direct\", or a smaller analysis.tolerance."]
    return []


def study_numbers(rows: list[dict]) -> list[tuple[str, str]]:
    done = [r for r in rows if r.get("status") == "done"]
    out = [("points", f"{len(done)} of {len(rows)} solved")]
    v = [abs(_num(_pressed(r))) for r in done if _num(_pressed(r)) is not None]
    if v:
        out.append(("pressed |V|", f"{engineering(min(v), 'V', 3)} to {engineering(max(v), 'V', 3)}"))
    return out


def front_numbers(front: dict) -> list[tuple[str, str]]:
    """The front's span and the thesis design's place against it."""
    pts = sorted((r["crosstalk"], r["sensitivity_V_per_N"]) for r in front.get("front", []))
    out = []
    if pts:
        best = max(pts, key=lambda p: p[1])
        out.append(("front", f"{len(pts)} designs, up to {engineering(best[1], 'V/N', 3)} "
                             f"at {100 * best[0]:.2g} % crosstalk"))
    ref = front.get("reference")
    if ref and pts:
        out.append(("thesis design", f"{engineering(ref['sensitivity'], 'V/N', 3)}, {100 * ref['crosstalk']:.2g} % "
                                     "crosstalk"))
        s0, c0 = ref["sensitivity"], ref["crosstalk"]
        below = [p for p in pts if p[0] <= c0]
        best_below = max(below, key=lambda p: p[1]) if below else None
        if best_below and best_below[1] >= s0:
            out.append(("thesis vs front", f"dominated: the front gives {engineering(best_below[1], 'V/N', 3)} "
                                           f"({100 * (best_below[1] / s0 - 1):+.0f} %) at {100 * best_below[0]:.2g} % "
                                           "crosstalk"))
            same = min((p for p in pts if p[1] >= s0), key=lambda p: p[0])
            out.append(("same sensitivity", f"at {100 * same[0]:.2g} % crosstalk on the front "
                                            f"(thesis {100 * c0:.2g} %)"))
        else:
            out.append(("thesis vs front", "on or beyond the front (no front design is better in both)"))
    return out


def front_3d_numbers(rec: dict) -> list[tuple[str, str]]:
    """A 3D-verified front's card lines (front-3d.json): the confirmed (finer-mesh)
    pair when there is one, else the coarse verification's."""
    a = rec["answer"]
    c = a.get("confirmed")
    t, b = (c["thesis"], c.get("best")) if c else (a["thesis_3d"], a.get("best_at_or_below_thesis_crosstalk"))
    label = "in 3D (1.5 mm)" if c else "in 3D (coarse)"
    out = [(f"thesis {label}", f"{engineering(t['sensitivity_V_per_N'], 'V/N', 3)}, "
                               f"{100 * t['crosstalk']:.2f} % crosstalk")]
    if b:
        gain = b.get("sensitivity_gain")
        out.append((f"3D front {label}", engineering(b["sensitivity_V_per_N"], "V/N", 3)
                    + (f" ({100 * gain:+.1f} %)" if gain is not None else "") + f", {100 * b['crosstalk']:.2f} %"))
    return out


def optimum_numbers(rec: dict) -> list[tuple[str, str]]:
    units = rec.get("units", {})
    x = ", ".join(f"{k.replace('_', ' ')} {v:.3g} {units.get(k, '')}".strip() for k, v in rec["x"].items())
    out = [("optimum", x)]
    m = rec.get("metrics") or {}
    if m.get("sensitivity") is not None:
        out.append(("optimum sensitivity", engineering(m["sensitivity"], "V/N", 3)))
    if m.get("crosstalk") is not None:
        out.append(("optimum crosstalk", f"{100 * m['crosstalk']:.3g} %"))
    out.append(("evaluations", f"{rec['evaluations']} ({'converged' if rec['success'] else 'not converged'})"))
    return out


def analysis_numbers(result) -> list[tuple[str, str]]:
    """Peak response (frequency) or peak and final output (transient) of a result
    read from its folder (`result.outputs()`)."""
    kind = getattr(result, "kind", None)
    out = []
    if kind == "frequency":
        o = result.outputs()                  # the pressed (or first) taxel's
        out.append(("peak response", f"{engineering(o['readout_sensitivity'], 'V/N', 3)} at "
                                     f"{o['peak_frequency']:.4g} Hz"))
        c = result.capacitance.get(result.pressed)
        if c:
            out.append(("capacitance", f"{c * 1e12:.4g} pF"))
    elif kind == "transient":
        o = result.outputs()
        out.append(("peak output", engineering(o["peak_output"], "V", 3)))
        out.append(("final output", engineering(o["final_output"], "V", 3)))
    return out


def _pressed(row: dict):
    """A row's pressed_voltage (voltage_pressed in a results.csv of an older release)."""
    return row.get("pressed_voltage", row.get("voltage_pressed"))


def _num(v):
    m = magnitude(v)
    return m if isinstance(m, float) and np.isfinite(m) else None
