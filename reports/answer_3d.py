"""The answer's numbers from its 3D presses (optimize.answer_press, probe-front.json's
answer_3d), as the page draws them: the owner (optimize.answer_folder.FolderAnswer) gives
the recommended and the thesis design of a probe-front answer the presses' sensitivity and
crosstalk and re-judges their margins when every design of the answer has a press with an
error estimate; here each quantity gets its own error band (a band above 2 % is flagged where
it is shown, not set aside: PVDF's press is still the better model than the selection's
estimate) and the ladder row of the answer's model (7); else the candidate-selection model's
numbers stay (ladder row 6) and a note says why. Nothing is solved or chosen here."""

from __future__ import annotations

from taxel.reports.ladder import ANSWER_MODEL, ROW, SELECTION_MODEL
from taxel.reports.tables import eng, percent


def pressed_3d(a, o) -> None:
    """Draw the 3D presses of the answer `a` (reports.answer.FrontAnswer) of the owner `o`
    (its `pressed` and `before`): the model, the bands and a note; or a note why not."""
    if not o.pressed:
        return
    got = o.pressed
    missing = [r for r, p in got.items() if p is None or p.failed or p.sensitivity is None]
    above = [r for r, p in got.items() if r not in missing and p.error is None]   # no estimate: not the answer
    if missing or above:
        a.notes.append("Not the 3D press's numbers: " + "; ".join(
            [f"the {r} design has no 3D press ({(got[r].failed if got[r] else 'not pressed')})" for r in missing]
            + [f"the {r} design's 3D press has no error estimate (its piezo or mesh is not calibrated)"
               for r in above]) + ".")
        return
    designs = [d for d in (a.recommended, a.thesis) if d is not None]
    a.error = {"sensitivity": max(got[d.role].error for d in designs),
               "crosstalk": max(got[d.role].crosstalk_error for d in designs)}
    a.row = ROW[ANSWER_MODEL]
    n = max(got[d.role].unknowns or 0 for d in designs)
    a.model = ("3D presses by the rig's probe on Yeoh silicone, one per design (3x3 array, quarter model, the default "
               f"press mesh, up to {n} unknowns; ladder row {ROW[ANSWER_MODEL]}), 1 N on the middle taxel")
    a.error_source = ("each 3D press's error, calibrated on the press family: the single taxel's error against its "
                      "nested reference plus the move of the 3x3 / single-taxel ratio under refinement, "
                      "extrapolated, times a safety factor (sensitivity and crosstalk each their own band)")
    moved = "; ".join(f"{d.role} {eng(o.before[d.role][0], 'V/N', 3)} at {percent(o.before[d.role][1])} → "
                      f"{eng(d.sensitivity_V_per_N, 'V/N', 3)} at {percent(d.crosstalk)}" for d in designs)
    a.notes.append(f"The candidates were chosen on the 2D press scaled by the linear 3D/2D ratio (ladder row "
                   f"{ROW[SELECTION_MODEL]}); the 3D presses give the answer's numbers: {moved}.")
