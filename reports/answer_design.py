"""The answer's view types: one design as the page draws it (`AnswerDesign`: the owner's
design, optimize.answer_folder.FolderAnswer's, with its table row and its answer.csv rows),
the answer of one optimization folder as drawn (`FrontAnswer`: the recommended and the
reference design, the model and error band of their numbers, the requirements, what the
recommendation trades, the model ladder), and a noise budget's minimum detectable force
(`NoiseFloor`). reports.answer builds them from the owner and draws the index's answer
block from them; nothing here chooses."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

from taxel.optimize.answer import Design
from taxel.reports.first_screen import MATERIALS
from taxel.scene_tables import ArrayTable
from taxel.reports.ladder import anchor
from taxel.reports.tables import eng, percent


def _band(value: float, rel: float | None, unit: str) -> str:
    """A value with its error band in the same unit: "838 ± 4 mV/N", "0.971 ± 0.049 %";
    a band above 2 % (optimize.band.FLAG) flagged: "838 ± 55 mV/N (band 6.6 % > 2 %)"."""
    from math import isfinite
    from taxel.optimize.band import FLAG
    if rel is None or not isfinite(rel):
        return (f"{value:.3g} %" if unit == "%" else eng(value, unit, 3)) + " (band not estimated)"
    flag = f" (band {100 * rel:.2g} % > {100 * FLAG:g} %)" if rel > FLAG else ""
    if unit == "%":
        return f"{value:.3g} ± {rel * value:.2g} %" + flag
    v = eng(value, unit)
    number, u = v.split(" ", 1)
    return f"{number} ± {float(number) * rel:.2g} {u}" + flag


@dataclass
class AnswerDesign:
    """One design of the answer as the page draws it: the owner's design
    (optimize.answer_folder.FolderAnswer: its variables, SI, and metrics) with its array, and
    the numbers the page shows; lengths in mm for display only."""
    role: str                                   # "recommended", "thesis", (a user's) "reference", "relaxed-<metric>"
    design: Design                              # the owner's (variables and metrics, SI)
    array: ArrayTable                           # the design's array: the scene's with its variables set
    material: str
    sensitivity_V_per_N: float                  # the page's numbers (a finer mesh's, when it solved this design)
    crosstalk: float
    min_detectable_force_N: float | None = None
    bandwidth_Hz: tuple[float, float] | None = None   # the readout's corners with this design (READOUT_FILE)

    @property
    def values(self) -> dict:
        """metric -> SI value (the owner's design's metrics), for the requirements."""
        return self.design.metrics

    @property
    def margins(self) -> dict:
        """metric -> relative margin (optimize.requirements), the owner's."""
        return self.design.margins

    def mm(self, name: str) -> float:
        """A length of the design in mm, for display: a variable's own value (as the run wrote it)
        when it is a variable in mm, else the design's array's."""
        if self.design.units.get(name) == "mm":
            return self.design.in_units()[name]
        return 1e3 * getattr(self.array, name)

    @property
    def silicone_above_mm(self) -> float:
        return self.mm("silicone_above")

    @property
    def silicone_below_mm(self) -> float:
        return self.mm("silicone_below")

    @property
    def gap_mm(self) -> float:
        return self.mm("gap")

    @property
    def pitch_mm(self) -> float:
        """The array's pitch (ArrayTable.pitch), mm."""
        return 1e3 * self.array.pitch

    def records(self, error: dict, model: str, bands: dict | None = None) -> list[dict]:
        """answer.csv's rows of this design: one quantity each, numeric value, relative error
        (all of its parts combined, optimize.band; empty: not estimated), its parts, and SI unit."""
        from math import isfinite
        out = []
        for q, v, unit, key in (("silicone above", self.array.silicone_above, "m", None),
                                ("silicone below", self.array.silicone_below, "m", None),
                                ("gap", self.array.gap, "m", None), ("pitch", self.array.pitch, "m", None),
                                ("open-circuit sensitivity", self.sensitivity_V_per_N, "V/N", "sensitivity"),
                                ("open-circuit crosstalk", self.crosstalk, "1", "crosstalk"),
                                ("sensitivity at the readout", self.values.get("readout_sensitivity"), "V/N",
                                 "readout_sensitivity"),
                                ("charge per newton", self.values.get("charge_sensitivity"), "C/N", "charge_sensitivity"),
                                ("minimum detectable force", self.min_detectable_force_N, "N", "min_detectable_force"),
                                ("force range to saturation", self.values.get("force_range"), "N", "force_range")):
            if v is not None:
                err = error.get(key) if key else None
                band = (bands or {}).get(key)
                out.append({"design": self.role, "material": MATERIALS.get(self.material, self.material),
                            "quantity": q, "value": v, "relative error": err if err is not None and isfinite(err)
                            else "", "error parts": band.text() if band is not None else
                            ("exact (a design variable)" if key is None else ""),
                            "unit": unit, "model": model + ("; beyond the largest force solved, "
                                                            f"{self.values['largest_force']:g} N: a straight line"
                                                            if key == "force_range" and self.values.get("largest_force")
                                                            and v > self.values["largest_force"] else "")})
        return out

    def row(self, error: dict) -> dict:
        """The answer table's row."""
        return {"design": self.role, "material": MATERIALS.get(self.material, self.material),
                "silicone above (mm)": f"{self.silicone_above_mm:.2f}",
                "silicone below (mm)": f"{self.silicone_below_mm:.2f}", "gap (mm)": f"{self.gap_mm:.2f}",
                "pitch (mm)": f"{self.pitch_mm:.2f}",
                "open-circuit sensitivity": _band(self.sensitivity_V_per_N, error["sensitivity"], "V/N"),
                "open-circuit crosstalk": _band(100 * self.crosstalk, error["crosstalk"], "%"),
                "min. detectable force": (_band(self.min_detectable_force_N, error.get("min_detectable_force"), "N")
                                          if self.min_detectable_force_N else "not computed"),
                **({"sensitivity at the readout": _band(self.values["readout_sensitivity"],
                                                        error.get("readout_sensitivity"), "V/N")}
                   if self.values.get("readout_sensitivity") is not None else {}),
                **({"crosstalk at the readout": percent(self.values["readout_crosstalk"])}
                   if self.values.get("readout_crosstalk") is not None else {}),
                **({"charge per newton": _band(self.values["charge_sensitivity"], error.get("charge_sensitivity"),
                                               "C/N")}
                   if self.values.get("charge_sensitivity") is not None else {}),
                **({"force range to saturation": self.saturation(error)}
                   if self.values.get("force_range") is not None else {})}

    def saturation(self, error: dict) -> str:
        """The force at which the readout clips: the number when a press reached it, else "beyond the
        largest force solved" with that force (the straight line past it is not a press)."""
        f, top = self.values["force_range"], self.values.get("largest_force")
        if top is not None and f > top * (1 + 1e-9):
            return (f"beyond {eng(top, 'N', 3)}, the largest force solved (a straight line from it: "
                    f"{eng(f, 'N', 3)}, not a press)")
        return _band(f, error.get("force_range"), "N")


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
                         "(taxel.analyses.accuracy.error_estimate: CHEAP_3D_ERROR); the linear silicone holds for small "
                         "presses (the V/N of a light touch)")
    requirements: list = field(default_factory=list)   # optimize.requirements.Requirement, implied ones too
    binding: tuple | None = None                        # (metric, margin) when no design meets every requirement
    path: Path | None = None                            # the optimization folder (the ladder's records)
    chain: str | None = None                            # how the readout numbers were made (READOUT_FILE)
    row: int = 6                                        # the ladder row (reports.ladder.ROW) of its numbers
    bands: dict = field(default_factory=dict)           # quantity -> optimize.band.Band (all of its parts)
    priced: list = field(default_factory=list)          # (optimize.answer.Price, AnswerDesign): a relaxation's design
    reversed: set = field(default_factory=set)          # priced designs' roles the 3D presses reverse (FolderAnswer)

    def ladders(self) -> list[dict]:
        """The model ladder (reports.ladder) of the recommended and the reference design."""
        from taxel.reports.ladder import capacitance_note, ladder
        if self.path is None:
            return []
        out = []
        for d in (self.recommended, self.thesis):
            if d is None:
                continue
            x = d.design.in_units()
            rungs = ladder(self.path, x, d is self.thesis)
            if rungs:
                out.append({"design": "recommended design" if d is self.recommended else self.reference_name,
                            "role": d.role, "rows": [r.row() for r in rungs],
                            "note": capacitance_note(self.path, x, d.role),
                            "ids": [anchor(self.folder, d.role, r.number) for r in rungs],
                            "answer": next(anchor(self.folder, d.role, r.number) for r in rungs if r.answer)})
        return out

    @property
    def reference_name(self) -> str:
        """"the thesis design" (a built-in optimization), else "your reference design"."""
        return "the thesis design" if self.thesis.role == "thesis" else "your reference design"

    @property
    def trade(self) -> str:
        """What the recommendation gives up or changes against the thesis design."""
        r, t = self.recommended, self.thesis
        if r is None and self.binding is not None:
            req = next(q for q in self.requirements if q.metric == self.binding[0])
            return (f"No design found meets every requirement: {req.text()} binds, missed by "
                    f"{100 * abs(self.binding[1]):.3g} % by the closest design.")
        if r is None:
            return (f"Keep {self.reference_name}: of the designs found, it meets every requirement and is the "
                    "best by the run's objective." + self.prices)
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
                f"{100 * xt:+.0f} % crosstalk (relative)." + self.prices)

    @property
    def prices(self) -> str:
        """" What the requirements cost: ..." (each binding requirement, relaxed to the next
        candidate's value: the design then chosen, its numbers the model's the page names)."""
        from dataclasses import replace
        chosen = (self.recommended or self.thesis).values
        margins = (self.recommended or self.thesis).margins
        at = [q.text() for q in self.requirements if q.stated and margins.get(q.metric) is not None
              and abs(margins[q.metric]) < 1e-3 and q.metric in ("pitch", "gap", "total_thickness", "footprint")]
        active = (f" {', '.join(at)} holds the chosen design at its bound in the search itself: relaxing it "
                  "needs a new search with the bound moved." if at else "")
        if not self.priced:
            return active + " No other requirement binds among the designs found."
        def where(d):
            return (d.design.text()                   # its variables, every one (optimize.answer.Design)
                    + (", its 3D press" if d.values.get("pressed_3d") else ", the candidate selection's estimate")
                    + "".join(f"; {q.text()} not evaluated for it" for q in self.requirements
                              if q.stated and d.values.get(q.metric) is None))

        def cost(p, d):
            if d.role in self.reversed:     # the candidate selection's order, reversed by the 3D presses
                return (f"{p.requirement.text()} binds on the candidate selection's numbers, but relaxing it "
                        f"buys nothing on the 3D presses: the design it would take ({where(d)}) presses at "
                        f"{eng(d.sensitivity_V_per_N, 'V/N', 3)} and {100 * d.crosstalk:.3g} % crosstalk, no better "
                        f"than the chosen design's {eng(chosen['sensitivity'], 'V/N', 3)}")
            return replace(p, design=0).text([d.values], chosen) + f" ({where(d)})"
        return " What the requirements cost: " + "; ".join(cost(p, d) for p, d in self.priced) + "." + active


def preference(answers: list[FrontAnswer]) -> str | None:
    """Why one material is preferred: the design each material recommends (or keeps),
    compared through the readout (charge per newton, volts at the output, minimum
    detectable force, saturation); None without the readout numbers of two materials."""
    ds = [(MATERIALS.get(a.thesis.material, a.thesis.material), a.recommended or a.thesis) for a in answers]
    if len(ds) < 2 or any(d.values.get("min_detectable_force") is None for _, d in ds):
        return None
    (bn, b), *rest = sorted(ds, key=lambda nd: nd[1].values["min_detectable_force"])
    on, o = rest[0]
    v = b.values
    text = (f"{bn} is preferred for these requirements: through the bench's charge amplifier it gives "
            f"{eng(v['charge_sensitivity'], 'C/N', 3)} ({eng(v['readout_sensitivity'], 'V/N', 3)} at the output) "
            f"against {eng(o.values['charge_sensitivity'], 'C/N', 3)} "
            f"({eng(o.values['readout_sensitivity'], 'V/N', 3)}) for {on}, so it detects "
            f"{eng(v['min_detectable_force'], 'N', 3)} against {eng(o.values['min_detectable_force'], 'N', 3)}, "
            f"and saturates at {eng(v['force_range'], 'N', 3)}.")
    if o.sensitivity_V_per_N > b.sensitivity_V_per_N:
        text += (f" {on}'s open-circuit voltage is higher ({eng(o.sensitivity_V_per_N, 'V/N', 3)} against "
                 f"{eng(b.sensitivity_V_per_N, 'V/N', 3)}), but a charge amplifier reads charge, not voltage.")
    return text
