"""The model ladder of an answer design: the same design's sensitivity, crosstalk,
capacitance and coverage in every model the run solved it with, each with its error
estimate and one line on why it differs from the answer, so that every other number of
the design on a page can say which row it is.

Capacitance (the pressed taxel's, F) where the run has it, from the answer's readout
record (answer-readout.json, taxel.jobs.answer_readout): the 2D section's |Q_sc / V_oc|
in row 1, and in the answer's row the one its charge per newton uses, the 3D model's
(the free parallel plate eps33^T A / t); the 3D verification mesh's own from the
design's 3D view (the main job's NAME-ROLE-3d solve folder beside the optimization
folder) in row 3; why they differ is the ladder's note (`capacitance_note`).
Coverage (optimize.coverage, OUT/coverage.json) is the design's 3D surface map's weakest
point (its best taxel's response over the detection threshold, and where; linear
silicone, the probe's footprint), the value a 100 % coverage requirement is judged on: it
sits in the answer's row, named as the map's.

The rows come from an optimization folder's records, matched to the design by its
variables (within 1 µm):

  2D section, pressure patch, linear silicone   the cheap front (front-3d.json "2D" columns)
  the 2D model corrected toward 3D              front-3d.json "predicted" columns (a prediction)
  3D, pressure patch, linear silicone           the verification mesh (front-3d.json "3D")
  3D, pressure patch, finer mesh                the confirmation (front-3d.json answer.confirmed)
  2D section, the rig's probe, Yeoh silicone    probe-front.json "2D press" columns
  2D press x linear 3D/2D (candidate selection) probe-front.json front rows: the 2D press
                                                scaled by the linear 3D/2D ratio, the model
                                                that chooses the candidates
  3D under the rig's probe (the answer's model) probe-front.json answer_3d: one 3D press per
                                                answer design (optimize.answer_press), with
                                                its error estimate

Each model has a fixed row number (ROW), the same for every design, so that a page's
column of one model names its row once (`label`: "sensitivity 2D, pressure patch —
ladder row 1"); a design the run did not solve in a model has no such row.

Nothing is solved here.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from taxel.optimize.answer_folder import READOUT_FILE  # noqa: F401  the answer's designs through the bench's chain
from taxel.reports.tables import eng, percent

# the probe front's own rows: the model the candidates are chosen on (optimize.probe_front)
SELECTION_MODEL = "the rig's probe, Yeoh silicone: 2D press x linear 3D/2D ratio (the candidate selection)"
# The error of the coarse verification mesh (optimize.multifidelity.VERIFY_3D) against the
# 3D reference: 0.2-3.8 % in voltage (taxel.analyses.accuracy.error_estimate, measured on the thesis
# PZT taxel) and 3-6 % on the 3x3 array (optimize.multifidelity, step 6): the worst of each.
VERIFY_3D_ERROR = {"sensitivity": 0.038, "crosstalk": 0.06}

WHY = {
    "2D section, pressure patch, linear silicone":
        "a plane section of the array (the row is infinitely deep: crosstalk about 3 times too high), a uniform "
        "pressure instead of the probe, linear silicone",
    "2D section corrected toward 3D (the front's prediction)":
        "a prediction, not a solve: the 2D model corrected by the 3D solves before it (the verification's "
        "check of it is the next row)",
    "3D, pressure patch, linear silicone (verification mesh)":
        "the coarse 3D mesh that checks the front; a uniform pressure instead of the probe, linear silicone",
    "3D, pressure patch, linear silicone (finer mesh)":
        "a uniform pressure instead of the probe and linear silicone: the silicone under the probe's rim "
        "strains far past the linear range",
    "2D section, the rig's probe, Yeoh silicone":
        "the probe and the Yeoh silicone, on a plane section (crosstalk too high, as above)",
    SELECTION_MODEL:
        "an estimate, not a solve: the 2D press times the linear model's 3D/2D ratio at the same design; it "
        "chooses the candidates, the 3D press checks them",
}


ANSWER_MODEL = "3D under the rig's probe, Yeoh silicone (one press per answer design)"
# the row number of each model, fixed: a page names a model's numbers by it
ROW = {m: i + 1 for i, m in enumerate([*WHY, ANSWER_MODEL])}
SHORT = {1: "2D, pressure patch", 2: "2D corrected, a prediction", 3: "3D, pressure patch",
         4: "3D finer mesh, pressure patch", 5: "2D press, the rig's probe",
         6: "2D press x 3D/2D ratio, the candidate selection", 7: "3D under the probe, the answer's model"}


def label(quantity: str, model: int) -> str:
    """A page's column name for one model's numbers: "sensitivity 2D, pressure patch — ladder row 1"."""
    return f"{quantity}, {SHORT[model]} — ladder row {model}"


# the record columns of each model's numbers, and their ladder row
FRONT_3D_COLUMNS = {"sensitivity 2D (V/N)": 1, "crosstalk 2D": 1, "predicted sensitivity": 2, "predicted crosstalk": 2,
                    "sensitivity 3D (V/N)": 3, "crosstalk 3D": 3}
PROBE_COLUMNS = {"sensitivity (V/N)": 6, "crosstalk": 6, "sensitivity 2D press (V/N)": 5, "crosstalk 2D press": 5,
                 "linear sensitivity (V/N)": 3, "linear crosstalk": 3, "probe sensitivity (V/N)": 6,
                 "probe crosstalk": 6}


def named(row: dict, columns: dict) -> dict:
    """`row` (changed in place, its order kept) with each column of `columns` ({record
    column: ladder row}) renamed by `label`, a sensitivity's unit V/N: "sensitivity 2D (V/N)" ->
    "sensitivity 2D, pressure patch — ladder row 1 (V/N)"."""
    items = list(row.items())
    row.clear()
    for k, v in items:
        if k in columns:
            quantity = "sensitivity" if "sensitivity" in k else "crosstalk"
            k = label(quantity, columns[k]) + (" (V/N)" if quantity == "sensitivity" else "")
        row[k] = v
    return row


def anchor(folder: str, role: str, number: int) -> str:
    """The page anchor of a design's ladder row (the answer's first screen links to it)."""
    return f"ladder-{folder}-{role}-{number}"


@dataclass
class Rung:
    """One row of the ladder."""
    model: str
    sensitivity: float | None          # V/N, open circuit
    crosstalk: float | None            # ratio
    error: float | None                # relative, None: not estimated
    why: str
    answer: bool = False
    number: int = 0                    # ROW's number of the model
    capacitance: float | None = None   # F, the pressed taxel's (module docstring)
    coverage: str | None = None        # the 3D map's weakest point, in words (optimize.coverage)
    crosstalk_error: float | None = None   # relative, when crosstalk carries its own band

    def row(self) -> list[str]:
        err = f"{100 * self.error:.2g} %" if self.error is not None else "not estimated"
        if self.crosstalk_error is not None:
            err = f"sensitivity {err}, crosstalk {100 * self.crosstalk_error:.2g} %"
        return [f"{self.number}. " + self.model + (" (the answer)" if self.answer else ""),
                eng(self.sensitivity, "V/N", 3) if self.sensitivity is not None else "—",
                percent(self.crosstalk) if self.crosstalk is not None else "—",
                eng(self.capacitance, "F", 3) if self.capacitance is not None else "—",
                self.coverage or "—", err, self.why]


COLS = ["model", "sensitivity", "crosstalk", "capacitance", "coverage", "error estimate",
        "why it differs from the answer"]


def _same(row: dict, x_mm: dict) -> bool:
    return all(abs(row.get(f"{n} (mm)", float("nan")) - v) < 1e-3 for n, v in x_mm.items())


def _same_x(x: list, x_mm: dict) -> bool:
    return len(x) == len(x_mm) and all(abs(a - b) < 1e-3 for a, b in zip(x, x_mm.values()))


def ladder(folder: Path, x_mm: dict, reference: bool) -> list[Rung]:
    """The ladder of the design `x_mm` ({variable: mm}) in an optimization folder;
    `reference`: the design is the folder's reference (thesis) design."""
    from taxel.analyses.accuracy.error_estimate import CHEAP_3D_ERROR
    folder = Path(folder)
    out: list[Rung] = []
    names = list(WHY)
    if (folder / "front-3d.json").exists():
        rec = json.loads((folder / "front-3d.json").read_text())
        rows = [rec["reference"]] if reference else [r for r in rec["verified"] if _same(r, x_mm)]
        if rows:
            r = rows[0]
            out.append(Rung(names[0], r.get("sensitivity 2D (V/N)"), r.get("crosstalk 2D"), None, WHY[names[0]]))
            if r.get("predicted sensitivity") is not None or r.get("predicted crosstalk") is not None:
                out.append(Rung(names[1], r.get("predicted sensitivity"), r.get("predicted crosstalk"), None,
                                WHY[names[1]]))
            if r.get("sensitivity 3D (V/N)") is not None:
                out.append(Rung(names[2], r["sensitivity 3D (V/N)"], r.get("crosstalk 3D"),
                                VERIFY_3D_ERROR["sensitivity"], WHY[names[2]]))
        c = (rec.get("answer") or {}).get("confirmed") or {}
        conf = c.get("thesis") if reference else (c.get("best") if c.get("best") and all(
            abs(a - b) < 1e-3 for a, b in zip(c["best"]["x"], x_mm.values())) else None)
        if conf:
            out.append(Rung(names[3], conf["sensitivity_V_per_N"], conf["crosstalk"],
                            CHEAP_3D_ERROR["sensitivity"], WHY[names[3]]))
    if (folder / "probe-front.json").exists():
        rec = json.loads((folder / "probe-front.json").read_text())
        rows = [rec["reference"]] if reference else [r for r in rec["front"] if _same(r, x_mm)]
        if rows:
            r = rows[0]
            if r.get("sensitivity 2D press (V/N)") is not None:
                out.append(Rung(names[4], r["sensitivity 2D press (V/N)"], r.get("crosstalk 2D press"), None,
                                WHY[names[4]]))
            if r.get("how") == "3D press":   # a front design pressed in 3D (taxel demo --presses-3d N, --full)
                out.append(Rung(ANSWER_MODEL, r["sensitivity (V/N)"], r["crosstalk"], r.get("estimated error"),
                                "the answer's model", answer=True))
            else:
                out.append(Rung(SELECTION_MODEL, r["sensitivity (V/N)"], r["crosstalk"], r.get("estimated error"),
                                WHY[SELECTION_MODEL]))
        press = next((p for p in rec.get("answer_3d", {}).get("designs", [])
                      if p.get("sensitivity") is not None and (p["role"] in ("thesis", "reference") if reference
                                                               else _same_x(p["x"], x_mm))), None)
        if press is not None and not any(r.answer for r in out):
            ok = press.get("error") is not None        # a band above 2 % is flagged, not set aside (reports.answer_3d)
            out.append(Rung(ANSWER_MODEL, press["sensitivity"], press["crosstalk"], press.get("error"),
                            "the answer's model" if ok else "no error estimate: not presented as the answer",
                            answer=ok, crosstalk_error=press.get("crosstalk_error")))
            if not ok and len(out) > 1:
                out[-2].answer = True
    if out and not any(r.answer for r in out):
        out[-1].answer = True
        out[-1].why = "the answer's model"
    for r in out:
        r.number = ROW.get(r.model, ROW[ANSWER_MODEL])
    caps = capacitances(folder, x_mm, "thesis" if reference else "recommended")
    from taxel.optimize.coverage import of as influence_metrics_of
    got = influence_metrics_of(folder, x_mm)
    at = got.get("coverage_minimum_at_mm")
    cov = (f"weakest point {got['coverage_minimum']:.3g}x the threshold"
           + (f" at ({at[0]:.2f}, {at[1]:.2f}) mm" if at else "") + " (its 3D surface map)"
           if got.get("coverage_minimum") is not None else None)
    for r in out:
        r.capacitance = caps.get("answer") if r.answer else caps.get(r.number)
        r.coverage = cov if r.answer else None
    return out


def _readout_row(folder: Path, x_mm: dict, role: str) -> dict | None:
    """The design's row of the answer's readout record (READOUT_FILE)."""
    path = Path(folder) / READOUT_FILE
    if not path.exists():
        return None
    return next((r for r in json.loads(path.read_text())["designs"] if r["role"] == role and
                 all(abs(r["x_mm"].get(k, v) - v) < 1e-6 for k, v in x_mm.items())), None)


THREE_D = "3D, pressure patch, linear silicone (verification mesh)"


def capacitances(folder: Path, x_mm: dict, role: str) -> dict[int | str, float]:
    """{ladder row: the pressed taxel's capacitance (F)} of a design (module docstring), and
    under "answer" the capacitance the answer's charge per newton uses (its row's)."""
    out = {}
    r = _readout_row(folder, x_mm, role)
    if r is not None:
        if r.get("capacitance_2d_F"):
            out[1] = r["capacitance_2d_F"]
        if r.get("capacitance_F"):
            out["answer"] = r["capacitance_F"]
    view = Path(folder).parent / f"{Path(folder).name.removesuffix('-front')}-{role}-3d"
    if (view / "result.json").exists() and (view / "scene.json").exists():
        from taxel.schema import electrode_name
        from taxel.units import magnitude
        scene = json.loads((view / "scene.json").read_text())
        array = scene.get("array", {})
        if all(abs(1e3 * magnitude(array[k]) - v) < 1e-3 for k, v in x_mm.items() if k in array):
            rec = json.loads((view / "result.json").read_text())
            e = rec.get("electrodes", {}).get(electrode_name(*scene.get("load", {}).get("taxel", (0, 0))), {})
            if e.get("capacitance_F"):
                out[ROW[THREE_D]] = abs(e["capacitance_F"])
    return out


def capacitance_note(folder: Path, x_mm: dict, role: str) -> str | None:
    """Why the design's capacitances differ (answer-readout.json): one line, None without the numbers."""
    r = _readout_row(folder, x_mm, role)
    if r is None or not r.get("capacitance_F") or not r.get("capacitance_2d_F"):
        return None
    plate, two = r["capacitance_F"], r["capacitance_2d_F"]
    three = capacitances(folder, x_mm, role).get(ROW[THREE_D])
    return (f"Capacitance: the free parallel plate (the piezo's permittivity at zero stress times the taxel's area "
            f"over its thickness) gives {eng(plate, 'F', 3)}, the answer's (ladder row {ROW[ANSWER_MODEL]}) and "
            "the 3D model's: the piezo is free in its plane under silicone seven orders softer"
            + (f" (this design's 3D solve, ladder row {ROW[THREE_D]}: {eng(three, 'F', 3)})" if three else "")
            + f"; the 2D section (ladder row 1) gives {eng(two, 'F', 3)} ({100 * (two / plate - 1):+.3g} %), "
            "because a plane section holds the piezo's strain along the depth at zero, which moves its permittivity "
            "toward the clamped one. The answer's charge per newton is its open-circuit sensitivity times "
            f"{eng(plate, 'F', 3)}.")
