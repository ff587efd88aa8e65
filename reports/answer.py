"""The answer block on top of the report's index: the design the run recommends and
the thesis design, side by side in engineering units, with the sensitivity,
crosstalk, minimum detectable force and error band of each, the model they come
from, and the trade the recommendation makes.

Where the answer comes from is one function, `headline_front(folder)`: it reads
an optimization folder's headline record (the front under the rig's probe,
probe-front.json, with the linear front beside it; else the 3D-confirmed front,
front-3d.json; else a 2D optimum, optimum.json, as `taxel demo --small` writes)
into a `FrontAnswer`. Point it at another folder (or file) to change what the
index leads with. Nothing is solved here.

Crosstalk is the largest neighbouring taxel's open-circuit |V| divided by the
pressed taxel's (taxel.optimize.metrics), defined once in the block's footnote.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

from taxel.reports.findings import verified_model
from taxel.reports.tables import eng, percent
from taxel.units import magnitude

# The error of the coarse verification mesh (optimize.multifidelity.VERIFY_3D) against the
# 3D reference: 0.2-3.8 % in voltage (taxel.analyses.error_estimate, measured on the thesis
# PZT taxel) and 3-6 % on the 3x3 array (optimize.multifidelity, step 6): the worst of each.
VERIFY_3D_ERROR = {"sensitivity": 0.038, "crosstalk": 0.06}

CROSSTALK_DEFINITION = ("Crosstalk: the largest neighbouring taxel's open-circuit |V| divided by the pressed "
                        "taxel's, for a press on the middle taxel of the 3x3 array.")


MATERIALS = {"PSI-5H4E": "PZT (PSI-5H4E)"}


def _band(value: float, rel: float, unit: str) -> str:
    """A value with its error band in the same unit: "838 ± 4 mV/N", "0.971 ± 0.049 %"."""
    if unit == "%":
        return f"{value:.3g} ± {rel * value:.2g} %"
    v = eng(value, unit)
    number, u = v.split(" ", 1)
    return f"{number} ± {float(number) * rel:.2g} {u}"


@dataclass
class AnswerDesign:
    """One design of the answer, in engineering units (lengths in mm)."""
    role: str                                   # "recommended" or "thesis"
    silicone_above_mm: float
    silicone_below_mm: float
    gap_mm: float
    pitch_mm: float
    material: str
    sensitivity_V_per_N: float
    crosstalk: float
    min_detectable_force_N: float | None = None

    def row(self, error: dict) -> dict:
        """The answer table's row."""
        return {"design": self.role, "material": MATERIALS.get(self.material, self.material),
                "silicone above (mm)": f"{self.silicone_above_mm:.2f}",
                "silicone below (mm)": f"{self.silicone_below_mm:.2f}", "gap (mm)": f"{self.gap_mm:.2f}",
                "pitch (mm)": f"{self.pitch_mm:.2f}",
                "sensitivity": _band(self.sensitivity_V_per_N, error["sensitivity"], "V/N"),
                "crosstalk": _band(100 * self.crosstalk, error["crosstalk"], "%"),
                "min. detectable force": (eng(self.min_detectable_force_N, "N", 3)
                                          if self.min_detectable_force_N else "not computed")}


class NoiseFloor(NamedTuple):
    """A noise budget's minimum detectable force, its model, and the design it is of."""
    force_N: float
    model: str
    piezo: str
    silicone_above_mm: float
    silicone_below_mm: float

    def of(self, d: AnswerDesign) -> bool:
        return (d.material == self.piezo and abs(d.silicone_above_mm - self.silicone_above_mm) < 0.005
                and abs(d.silicone_below_mm - self.silicone_below_mm) < 0.005)


@dataclass
class FrontAnswer:
    """The answer of one optimization folder: the recommended and the thesis design."""
    folder: str
    recommended: AnswerDesign | None
    thesis: AnswerDesign
    model: str                                  # the model both designs' numbers come from
    error: dict                                 # relative error band per output
    verified: bool                              # True: 3D; False: the cheap 2D model only
    notes: list[str] = field(default_factory=list)
    error_source: str = ("the 3D model's own mesh error, measured against the converged 3D reference "
                         "(taxel.analyses.error_estimate: CHEAP_3D_ERROR); the linear silicone holds for small "
                         "presses (the V/N of a light touch)")

    @property
    def trade(self) -> str:
        """What the recommendation gives up or changes against the thesis design."""
        r, t = self.recommended, self.thesis
        if r is None:
            return "The thesis design is on the front: no design found is better in both sensitivity and crosstalk."
        parts = []
        for name, a, b in (("silicone above", t.silicone_above_mm, r.silicone_above_mm),
                           ("silicone below", t.silicone_below_mm, r.silicone_below_mm)):
            if abs(a - b) >= 0.005:
                parts.append(f"{name} {a:.2f} → {b:.2f} mm")
        if abs(r.pitch_mm - t.pitch_mm) >= 0.005:
            density = (t.pitch_mm / r.pitch_mm) ** 2 - 1
            parts.append(f"{'a wider' if r.pitch_mm > t.pitch_mm else 'a narrower'} pitch {t.pitch_mm:.2f} → "
                         f"{r.pitch_mm:.2f} mm ({100 * density:+.0f} % taxels per area)")
        gain = r.sensitivity_V_per_N / t.sensitivity_V_per_N - 1
        xt = r.crosstalk / t.crosstalk - 1
        return (f"The trade: {'; '.join(parts) or 'the same geometry'}; for {100 * gain:+.2g} % sensitivity and "
                f"{100 * xt:+.0f} % crosstalk (relative).")


def headline_front(folder: Path) -> FrontAnswer | None:
    """The answer an optimization folder holds, from its headline record (the probe
    front, else the 3D-confirmed front, else a 2D optimum); None when it holds none."""
    folder = Path(folder)
    scene = json.loads((folder / "scene.json").read_text()) if (folder / "scene.json").exists() else {}
    array = scene.get("array", {})
    width = 1e3 * magnitude(array.get("taxel_width", "4 mm"))
    material = array.get("piezo", "?")
    if (folder / "probe-front.json").exists():     # the headline under the rig's probe (issue: the rig's load)
        linear = (_from_front_3d(folder, json.loads((folder / "front-3d.json").read_text()), width, material)
                  if (folder / "front-3d.json").exists() else None)
        return _from_probe_front(folder, json.loads((folder / "probe-front.json").read_text()), width, material,
                                 linear)
    if (folder / "front-3d.json").exists():
        return _from_front_3d(folder, json.loads((folder / "front-3d.json").read_text()), width, material)
    if (folder / "optimum.json").exists():
        return _from_optimum(folder, json.loads((folder / "optimum.json").read_text()), scene, width, material)
    return None


def _lengths(row: dict) -> dict:
    """A front record row's design variables in mm: {"gap": 3.0, ...} from "gap (mm)" keys."""
    return {k.split(" (")[0]: v for k, v in row.items() if k.endswith("(mm)")}


def _design(role, x: dict, width, material, s, c) -> AnswerDesign:
    gap = x["gap"]
    return AnswerDesign(role, x["silicone_above"], x["silicone_below"], gap, width + gap, material, s, c)


def _from_front_3d(folder: Path, rec: dict, width: float, material: str) -> FrontAnswer:
    from taxel.analyses.error_estimate import CHEAP_3D_ERROR
    a = rec["answer"]
    ref = rec["reference"]
    x_ref = _lengths(ref)
    names = list(x_ref)
    c = a.get("confirmed")
    t, b = (c["thesis"], c.get("best")) if c else (a["thesis_3d"], a.get("best_at_or_below_thesis_crosstalk"))
    model, _ = verified_model(rec)
    thesis = _design("thesis", x_ref, width, material, t["sensitivity_V_per_N"], t["crosstalk"])
    best = (_design("recommended", dict(zip(names, b["x"])), width, material, b["sensitivity_V_per_N"],
                    b["crosstalk"]) if b and not a.get("thesis_on_3d_front") else None)
    error = dict(CHEAP_3D_ERROR) if c else dict(VERIFY_3D_ERROR)
    notes = [f"Recommended: the most sensitive design of the 3D-verified front at or below the thesis design's "
             f"crosstalk; the 3D-verified front holds {len(rec['front_3d'])} of the {len(rec['verified'])} designs solved "
             "in 3D."]
    return FrontAnswer(folder.name, best, thesis, model + ", 3x3 array, 1 N on the middle taxel", error, True, notes)


def _from_probe_front(folder: Path, rec: dict, width: float, material: str,
                      linear: FrontAnswer | None) -> FrontAnswer:
    """The probe front (optimize.probe_front, probe-front.json): the thesis design and the
    most sensitive pressed front design that dominates it, under the rig's probe
    on Yeoh silicone; the linear pressure-patch answer (`linear`) in the notes beside it.
    The error band is the record's estimated error, on sensitivity; crosstalk carries
    the same relative band, a lower bound (the correction's crosstalk misses are larger)."""
    ref = rec["reference"]
    thesis = _design("thesis", _lengths(ref), width, material,
                     ref["sensitivity (V/N)"], ref["crosstalk"])
    from taxel.optimize.probe_front import dominates        # the record's own dominance rule
    key = ("sensitivity (V/N)", "crosstalk")
    better = [d for d in rec["front"] if d["x"] != ref["x"] and dominates([d[k] for k in key], [ref[k] for k in key])]
    b = max(better, key=lambda d: d["sensitivity (V/N)"], default=None)
    best = (_design("recommended", _lengths(b), width, material,
                    b["sensitivity (V/N)"], b["crosstalk"]) if b else None)
    err = max([ref["estimated error"]] + ([b["estimated error"]] if b else []))
    press = rec.get("press", {})
    probe = ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in press.items()
                      if v is not None and k in ("shape", "radius", "edge_radius", "force", "silicone", "friction"))
    notes = [f"Under the rig's probe ({probe or 'flat punch, Yeoh silicone'}): {rec['sentence']}"]
    for role, r in (("thesis", ref), ("recommended", b)):
        if r is not None:
            notes.append(f"The {role} design's estimated error is {100 * r['estimated error']:.2g} % "
                         f"({'within' if r['estimated error'] <= 0.02 else 'above'} 2 %; {r.get('how', '')}).")
    if err > 0.02 and not rec.get("spent", {}).get("product error measured"):
        notes.append("The estimate's product error is the one measured once by 3D presses of front designs "
                     "(optimize.probe_front.PRODUCT_ERROR); taxel demo --presses-3d N (or --full) measures it "
                     "on this run's designs.")
    if linear is not None:
        t = linear.thesis
        r = linear.recommended
        notes.append("Beside it, the linear pressure-patch front (" + linear.model + "): thesis "
                     f"{eng(t.sensitivity_V_per_N, 'V/N', 3)} at {percent(t.crosstalk)}"
                     + (f"; recommended there: silicone {r.silicone_above_mm:.2f} / {r.silicone_below_mm:.2f} mm, "
                        f"gap {r.gap_mm:.2f} mm, {eng(r.sensitivity_V_per_N, 'V/N', 3)} at {percent(r.crosstalk)}"
                        if r else "; the thesis design is on that front") + ".")
    model = f"3D under the rig's probe, Yeoh silicone ({rec['level']})"
    return FrontAnswer(folder.name, best, thesis, model + ", 3x3 array, 1 N on the middle taxel",
                       {"sensitivity": err, "crosstalk": err}, True, notes,
                       "the probe front's estimated error (discretisation + correction + material law, on "
                       "sensitivity; optimize.probe_front), the same relative band drawn on crosstalk")


def _from_optimum(folder: Path, rec: dict, scene: dict, width: float, material: str) -> FrontAnswer | None:
    from taxel.optimize.spec import load_optimization
    m = rec.get("metrics") or {}
    if m.get("sensitivity") is None or m.get("crosstalk") is None:
        return None
    try:
        ref_x = {k: 1e3 * magnitude(v) for k, v in load_optimization(folder.name).spec.reference.items()}
    except Exception:                       # not a built-in problem: no thesis design to compare with
        return None
    names = list(rec["x"])
    start = [m for x, m in _history(folder / "optimum-history.csv", len(names))
             if all(abs(v - ref_x.get(n, float("nan"))) < 1e-6 for n, v in zip(names, x))]
    if not start or start[0].get("sensitivity") is None:
        return None
    tm = start[0]
    thesis = _design("thesis", ref_x, width, material, tm["sensitivity"], tm["crosstalk"])
    best = _design("recommended", rec["x"], width, material, m["sensitivity"], m["crosstalk"])
    from taxel.reports.findings import scene_model_label
    model = (f"{scene_model_label(scene)}, 3x3 array, 1 N on the middle taxel; a short local search, not verified "
             "in 3D")
    # the 2D model's error against 3D is measured on the full run (front-3d.json): unknown here
    return FrontAnswer(folder.name, best, thesis, model, {"sensitivity": float("nan"), "crosstalk": float("nan")},
                       False, ["Recommended: the short local search's best design (taxel demo --small)."])


def _history(path: Path, n: int) -> list[tuple[list[float], dict]]:
    """(design variables, metrics) of each evaluation in an optimum-history.csv: the n
    variables follow the evaluation and phase columns, the metrics after them (a
    metric may share a variable's name: "gap" in mm, then in m)."""
    import csv
    if not path.exists():
        return []
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    head, out = rows[0], []
    for r in rows[1:]:
        x = [float(v) for v in r[2:2 + n]]
        metrics = {k: float(v) for k, v in zip(head[2 + n:], r[2 + n:]) if v != ""}
        out.append((x, metrics))
    return out


def block(answers: list[FrontAnswer], noise: NoiseFloor | None = None) -> dict | None:
    """The index's answer block (template data): one table row per design, the model,
    the trade and the crosstalk definition. `noise`: a noise budget's minimum
    detectable force, shown for the design it is of (a single taxel of that design)."""
    if not answers:
        return None
    rows, lines = [], []
    for a in answers:
        if noise and noise.of(a.thesis):
            a.thesis.min_detectable_force_N = noise.force_N
        for d in (a.recommended, a.thesis):
            if d is None:
                continue
            row = d.row(a.error)
            if not a.verified:
                row["sensitivity"] = eng(d.sensitivity_V_per_N, "V/N", 3) + " (error not estimated)"
                row["crosstalk"] = percent(d.crosstalk)
            rows.append(row)
        lines.append({"folder": a.folder, "model": a.model, "trade": a.trade, "notes": a.notes})
    head = next((a for a in answers if a.recommended), answers[0])
    r = head.recommended or head.thesis
    title = (f"Recommended: {MATERIALS.get(r.material, r.material)}, silicone {r.silicone_above_mm:.2f} mm above and {r.silicone_below_mm:.2f} mm "
             f"below, gap {r.gap_mm:.2f} mm: {eng(r.sensitivity_V_per_N, 'V/N', 3)} at {percent(r.crosstalk)} "
             "crosstalk" if head.recommended else "Keep the thesis design: it is on the front")
    cols = list(rows[0])
    return {"title": title, "cols": cols, "rows": [[row[c] for c in cols] for row in rows],
            "roles": [row["design"] for row in rows], "lines": lines, "definition": CROSSTALK_DEFINITION,
            "verified": any(a.verified for a in answers),
            "error_source": "; ".join(dict.fromkeys(a.error_source for a in answers if a.verified)),
            "noise_model": noise.model if noise else None}
