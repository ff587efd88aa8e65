"""One number per quantity: a page that shows a quantity of an answer design (the
thesis or the recommended design of a run's optimization: its minimum detectable force,
saturation, capacitance, open-circuit sensitivity) from another model than the answer's
names that model and links the ladder row (reports.ladder, on page one) that explains
the difference, beside the answer's own value.

    answers = of_answers(fronts)              # reports.answer.headline_front's, before the pages
    numbers, note = annotate(numbers, scene_data, answers)

A page's scene is an answer design when its array is one: the same piezo, silicone above
and below, gap, taxel width and piezo thickness. Its headline numbers that differ from the
answer's (as shown, 3 significant figures) get "— ladder row N; the answer's: X (ladder
row 7)" and a link to that ladder row; the page gets one note with the answer's values
(its summary text keeps its own model's numbers). The ladder row of a page's model: a
2D plane section is row 1 (2D, pressure patch; the noise budget and the frequency sweep
solve it), a 3D pressure patch row 3, the 3D press by the rig's probe row 7, the answer's.
Nothing is solved here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from taxel.reports.ladder import ANSWER_MODEL, ROW, anchor
from taxel.reports.tables import eng

# a headline's label -> the answer design's value it shows (AnswerDesign.values), unit
QUANTITIES = {"minimum detectable force": ("min_detectable_force", "N"),
              "taxel capacitance": ("capacitance", "F"), "capacitance": ("capacitance", "F"),
              "open-circuit sensitivity": ("sensitivity", "V/N"),
              "force range to saturation": ("force_range", "N")}
UNITS = {"min_detectable_force": "N", "capacitance": "F", "sensitivity": "V/N", "force_range": "N"}
WORDS = {"min_detectable_force": "minimum detectable force", "force_range": "saturation",
         "capacitance": "capacitance", "sensitivity": "open-circuit sensitivity"}
TOL_MM = 1e-6


@dataclass
class AnswerNumbers:
    """One answer design's values as page one shows them."""
    folder: str                     # the optimization folder (the ladder's anchors)
    role: str                       # "thesis", "recommended"
    array: dict                     # piezo, silicone_above, silicone_below, gap, taxel_width, piezo_thickness (SI)
    values: dict = field(default_factory=dict)      # QUANTITIES' keys -> SI

    def shown(self, key: str) -> str | None:
        v = self.values.get(key)
        return None if v is None else eng(v, UNITS[key], 3)

    def matches(self, scene_data: dict | None) -> bool:
        from taxel.units import magnitude
        arr = (scene_data or {}).get("array") or {}
        if arr.get("piezo") != self.array["piezo"]:
            return False
        for k in ("silicone_above", "silicone_below", "gap", "taxel_width", "piezo_thickness"):
            if k not in arr or abs(magnitude(arr[k]) - self.array[k]) > TOL_MM * 1e-3:
                return False
        return True


def of_answers(answers: list) -> list[AnswerNumbers]:
    """The answer designs of reports.answer.FrontAnswer objects, with page one's values."""
    out = []
    for a in answers:
        for d in (a.recommended, a.thesis):
            if d is None:
                continue
            out.append(AnswerNumbers(a.folder, d.role, {
                "piezo": d.material, **{k: getattr(d.array, k) for k in ("silicone_above", "silicone_below", "gap",
                                                                         "taxel_width", "piezo_thickness")}},
                {"sensitivity": d.sensitivity_V_per_N, **{k: d.values.get(k) for k in
                                                         ("min_detectable_force", "capacitance", "force_range")}}))
    return [n for n in out if None not in n.array.values()]


def model_row(scene_data: dict) -> int:
    """The ladder row of a page's model (module docstring)."""
    model = (scene_data or {}).get("model") or {}
    return ROW[ANSWER_MODEL] if model.get("type") == "3d" and (scene_data or {}).get("press") else \
        3 if model.get("type") == "3d" else 1


def annotate(numbers: list, scene_data: dict | None, answers: list[AnswerNumbers]) -> tuple[list, dict | None]:
    """`numbers` (reports.page.Headline) with each differing answer quantity's model and ladder
    row named and linked, and the page's note on the answer's values (None: not an answer design)."""
    a = next((n for n in answers if n.matches(scene_data)), None)
    if a is None:
        return numbers, None
    row = model_row(scene_data)
    href = f"index.html#{anchor(a.folder, a.role, row)}"
    answer_row = ROW[ANSWER_MODEL]
    out = []
    for n in numbers:
        key = QUANTITIES.get(n.label, (None,))[0]
        want = a.shown(key) if key else None
        if want is not None and n.value != want and row != answer_row:
            n = n._replace(model=f"{n.model} — ladder row {row}; the answer's: {want} (ladder row {answer_row})",
                           href=href)
        out.append(n)
    listed = "; ".join(f"{WORDS[k]} {a.shown(k)}" for k in WORDS if a.shown(k))
    note = {"type": "note", "href": href, "link": f"ladder row {row} of the {a.role} design ({a.folder})",
            "text": (f"This page's scene is the answer's {a.role} design of {a.folder}. Page one gives its numbers "
                     f"from the answer's model (ladder row {answer_row}: {listed}); the numbers here are this "
                     f"page's model's" + ("" if row == answer_row else f", ladder row {row}, whose row in the "
                                          "design's ladder says why they differ") + ".")}
    return out, note
