"""The answer's numbers from its 3D presses (optimize.answer_press, probe-front.json's
answer_3d): the recommended and the thesis design of a probe-front answer
(reports.answer.FrontAnswer) take the presses' sensitivity and crosstalk, each quantity
its own error band (a band above 2 % is flagged where it is shown, not set aside: PVDF's
press, 2.7 %, is still the better model than the selection's estimate), their margins
against the requirements re-judged, and the ladder row of the answer's model (7) -- when
every design of the answer has a press with an error estimate; else the candidate-selection
model's numbers stay (ladder row 6) and a note says why.
Nothing is solved here."""

from __future__ import annotations

from taxel.reports.ladder import ANSWER_MODEL, ROW, SELECTION_MODEL
from taxel.reports.tables import eng, percent


def pressed_3d(a, rec: dict) -> None:
    """The answer's numbers from the 3D presses of its designs (optimize.answer_press, the
    record's answer_3d), when every design of the answer has one with an estimate; else the
    selection model's stay, and a note says why."""
    from taxel.optimize.answer_press import read
    from taxel.optimize.requirements import implied, judge, read as read_requirements
    presses = read(rec)
    if not presses:
        return
    designs = [d for d in (a.recommended, a.thesis) if d is not None]

    def press_of(d):
        x = [getattr(d, f"{n}_mm") for n in ("silicone_above", "silicone_below", "gap")]
        return next((p for p in presses if p.role == d.role and len(p.x) == 3
                     and all(abs(u - v) < 1e-6 for u, v in zip(p.x, x))), None)
    got = {d.role: press_of(d) for d in designs}
    missing = [r for r, p in got.items() if p is None or p.failed or p.sensitivity is None]
    above = [r for r, p in got.items() if r not in missing and p.error is None]   # no estimate: not the answer
    if missing or above:
        a.notes.append("Not the 3D press's numbers: " + "; ".join(
            [f"the {r} design has no 3D press ({(got[r].failed if got[r] else 'not pressed')})" for r in missing]
            + [f"the {r} design's 3D press has no error estimate (its piezo or mesh is not calibrated)"
               for r in above]) + ".")
        return
    for _, d in a.priced:                   # what relaxing a requirement buys: its own press, when it has one
        p = press_of(d)
        if p is not None and not p.failed and p.sensitivity is not None and p.error is not None:
            d.sensitivity_V_per_N, d.crosstalk = p.sensitivity, p.crosstalk
            d.values.update(sensitivity=p.sensitivity, crosstalk=p.crosstalk, pressed_3d=True)
    before = {d.role: (d.sensitivity_V_per_N, d.crosstalk) for d in designs}
    for d in designs:
        p = got[d.role]
        d.sensitivity_V_per_N, d.crosstalk = p.sensitivity, p.crosstalk
        d.values.update(sensitivity=p.sensitivity, crosstalk=p.crosstalk)
    a.requirements = implied(read_requirements(rec.get("requirements", {})), a.thesis.values)
    for d in designs:
        d.margins = judge(d.values, a.requirements).margins
    a.error = {"sensitivity": max(got[d.role].error for d in designs),
               "crosstalk": max(got[d.role].crosstalk_error for d in designs)}
    a.row = ROW[ANSWER_MODEL]
    n = max(got[d.role].unknowns or 0 for d in designs)
    a.model = ("3D presses by the rig's probe on Yeoh silicone, one per design (3x3 array, quarter model, the default "
               f"press mesh, up to {n} unknowns; ladder row {ROW[ANSWER_MODEL]}), 1 N on the middle taxel")
    a.error_source = ("each 3D press's error, calibrated on the press family: the single taxel's error against its "
                      "nested reference plus the move of the 3x3 / single-taxel ratio under refinement, "
                      "extrapolated, times a safety factor (sensitivity and crosstalk each their own band)")
    moved = "; ".join(f"{d.role} {eng(before[d.role][0], 'V/N', 3)} at {percent(before[d.role][1])} → "
                      f"{eng(d.sensitivity_V_per_N, 'V/N', 3)} at {percent(d.crosstalk)}" for d in designs)
    a.notes.append(f"The candidates were chosen on the 2D press scaled by the linear 3D/2D ratio (ladder row "
                   f"{ROW[SELECTION_MODEL]}); the 3D presses give the answer's numbers: {moved}.")
