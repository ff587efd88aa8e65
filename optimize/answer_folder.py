"""The owner of an optimization folder's answer: it reads the folder's headline record,
holds every candidate as a design (optimize.answer.Design: the optimization's own
variables, name -> SI value, with its metrics, SI), chooses among them with the folder's
requirements and prices each binding one, and writes and reads what the jobs add to the
folder (the answer's coverage, 3D presses, readout numbers and friction band). Jobs call it; reports
draw it (reports.answer.headline_front); nothing is solved here.

    a = FolderAnswer.read(folder)        # None when the folder holds no answer
    a.recommended, a.reference           # Designs (recommended None: the reference is kept)
    a.priced                             # [(Price, Design)]: what relaxing a binding requirement buys
    a.answer_designs()                   # recommended, reference, the priced ones: each once
    a.array(d)                           # the design's array (taxel.scene_tables.ArrayTable)
    a.add_coverage(d, values); a.write_presses(presses); a.write_readout(record); a.write_friction_band(record)

The headline record, first found: the front under the rig's probe (probe-front.json, its
3D presses in it, the linear 3D-verified front beside it as `linear`), else the
3D-verified front (front-3d.json), else a front (front.json with result.json), else a
2D optimum (optimum.json with optimum-history.csv, a built-in problem's). A design's
geometric metrics (gap, pitch, total thickness, footprint) are the scene's
(optimize.metrics.geometry) with the design's variables set at their paths, so a taxel
width or a piezo thickness can be a variable. The choice is optimize.requirements.choose's
(its rules 1 to 4), with the coverage the run computed for a design
(optimize.coverage.RECORD) in its metrics; the prices optimize.answer.prices'.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from types import SimpleNamespace

from taxel.optimize import answer_press, coverage
from taxel.optimize.answer import Design, Price, prices, reference_label
from taxel.optimize.metrics import geometry
from taxel.optimize.requirements import (OBJECTIVE, Choice, Requirement, choose, implied, judge,
                                         read as read_requirements)

READOUT_FILE = "answer-readout.json"     # the answer's designs through the bench's chain (taxel.jobs.answer_readout)
READOUT = {"charge_sensitivity": "charge_sensitivity_C_per_N", "readout_sensitivity": "readout_V_per_N",
           "min_detectable_force": "min_detectable_force_N", "force_range": "force_range_N",
           "capacitance": "capacitance_F"}    # metric -> the readout record's key
AT_READOUT = ("readout_sensitivity", "readout_crosstalk", "min_detectable_force")


@dataclass(frozen=True)
class Variable:
    """One variable of the optimization: its name, scene path and unit."""
    name: str
    path: str
    unit: str


@dataclass
class FolderAnswer:
    """The answer of one optimization folder (module docstring)."""
    folder: Path
    kind: str                                   # "probe-front", "front-3d", "front" or "optimum"
    record: dict                                # the headline record
    variables: list[Variable]
    scene: dict                                 # the folder's scene.json (its base scene), {} when absent
    reference: Design                           # label "thesis" (a built-in optimization's) or "reference"
    candidates: list[Design]                    # the other designs, in the record's order
    requirements: list[Requirement] = field(default_factory=list)
    choice: Choice | None = None
    priced: list[tuple[Price, Design]] = field(default_factory=list)
    linear: "FolderAnswer | None" = None        # probe-front: the 3D-verified linear front's answer beside it
    pressed: dict = field(default_factory=dict)  # label -> its AnswerPress (or None): the answer's 3D presses
    before: dict = field(default_factory=dict)  # label -> (sensitivity, crosstalk) before the presses took over
    readout: dict = field(default_factory=dict)  # label -> its row of READOUT_FILE
    reversed: set = field(default_factory=set)  # priced designs' labels whose 3D press is no better than the chosen's

    # -- reading -------------------------------------------------------------------------------
    @classmethod
    def read(cls, folder: str | Path, with_presses: bool = True) -> "FolderAnswer | None":
        """The answer `folder` holds (module docstring), None when it holds none."""
        folder = Path(folder)
        scene = _json(folder / "scene.json") or {}
        if (folder / answer_press.PROBE_FILE).exists():
            a = cls._records(folder, "probe-front", _json(folder / answer_press.PROBE_FILE), scene)
            if (folder / "front-3d.json").exists():
                a.linear = cls._records(folder, "front-3d", _json(folder / "front-3d.json"), scene)
                a.linear._choose()
            a._choose()
            if with_presses:
                a._take_presses()
        elif (folder / "front-3d.json").exists():
            a = cls._records(folder, "front-3d", _json(folder / "front-3d.json"), scene)
            a._choose()
        elif (folder / "front.json").exists() and (folder / "result.json").exists():
            a = cls._records(folder, "front", _json(folder / "result.json"), scene)
            if a is not None:
                a._choose()
        elif (folder / "optimum.json").exists():
            a = cls._records(folder, "optimum", _json(folder / "optimum.json"), scene)
            if a is not None:
                a._choose()
        else:
            return None
        if a is not None:
            a._take_readout()
        return a

    @classmethod
    def _records(cls, folder: Path, kind: str, rec: dict, scene: dict) -> "FolderAnswer | None":
        """The designs of a headline record, before the choice."""
        if kind == "probe-front":
            vs = _variables(rec.get("name") or folder.name, rec["reference"])
            s, c = "sensitivity (V/N)", "crosstalk"
            ref = rec["reference"]
            rows = [d for d in rec["front"] if d["x"] != ref["x"] and d.get(s) is not None]
            xs = [dict(zip((v.name for v in vs), r["x"])) for r in rows]
            mets = [{"sensitivity": r[s], "crosstalk": r[c]} for r in rows]
            ref_x = dict(zip((v.name for v in vs), ref["x"]))
            refm, role = {"sensitivity": ref[s], "crosstalk": ref[c]}, "thesis"
        elif kind == "front-3d":
            ref = rec["reference"]
            vs = _variables(folder.name, ref)
            s, c = "sensitivity 3D (V/N)", "crosstalk 3D"
            ref_x = _keyed(ref, vs)
            rows = [r for r in rec["front_3d"] if r.get(s) is not None and _keyed(r, vs) != ref_x]
            xs, mets = [_keyed(r, vs) for r in rows], [{"sensitivity": r[s], "crosstalk": r[c]} for r in rows]
            refm, role = {"sensitivity": ref[s], "crosstalk": ref[c]}, "thesis"
        elif kind == "front":
            ref = rec.get("reference") or {}
            if ref.get("sensitivity") is None or ref.get("crosstalk") is None:
                return None
            vs = _variables(rec.get("name"), None, rec["variables"], rec.get("paths"))
            role = "thesis" if reference_label(rec.get("name")) == "thesis design" else "reference"
            ref_x = {v.name: ref["x"][v.name] for v in vs}
            refm = {"sensitivity": ref["sensitivity"], "crosstalk": ref["crosstalk"],
                    **{k: ref.get(k) for k in AT_READOUT}}
            rows, xs, mets = [], [], []
            for r in rec["front"]:
                m, x = r["run"]["metrics"], r["run"]["x"]
                x = dict(zip((v.name for v in vs), x)) if isinstance(x, list) else x
                if r["run"].get("success", True) and m.get("sensitivity") is not None and x != ref_x:
                    rows.append(r), xs.append(x), mets.append({"sensitivity": m["sensitivity"],
                                                               "crosstalk": m["crosstalk"],
                                                               **{k: m.get(k) for k in AT_READOUT}})
        else:                                    # a built-in problem's short local search (taxel demo --small)
            m = rec.get("metrics") or {}
            if m.get("sensitivity") is None or m.get("crosstalk") is None:
                return None
            try:
                from taxel.optimize.spec import load_optimization
                spec = load_optimization(folder.name).spec
            except Exception:                   # not a built-in problem: no thesis design to compare with
                return None
            vs = _variables(folder.name, None)
            from taxel.units import magnitude
            unit = {v.name: v.unit for v in vs}
            ref_x = {n: magnitude(v) / _unit(unit[n]) for n, v in spec.reference.items() if n in unit}
            start = [h for x, h in _history(folder / "optimum-history.csv", len(rec["x"]))
                     if all(abs(v - ref_x.get(n, float("nan"))) < 1e-6 for n, v in zip(rec["x"], x))]
            if not start or start[0].get("sensitivity") is None:
                return None
            rec = {**rec, "requirements": spec.requirements}
            refm, role = {"sensitivity": start[0]["sensitivity"], "crosstalk": start[0]["crosstalk"]}, "thesis"
            rows, xs, mets = [rec], [rec["x"]], [{"sensitivity": m["sensitivity"], "crosstalk": m["crosstalk"]}]
        a = cls(folder, kind, rec, vs, scene, None, [])
        a.reference = a._design(role, ref_x, refm, rec.get("reference") or {})
        a.candidates = [a._design("candidate", x, mm, r) for x, mm, r in zip(xs, mets, rows)]
        return a

    def _design(self, label: str, x: dict, metrics: dict, row: dict) -> Design:
        """A design from its variables in their own units, its metrics joined by its geometry and
        the coverage the run computed for it."""
        from taxel.optimize.answer import si
        units = {v.name: v.unit for v in self.variables}
        d = Design(label, {n: si(x[n], units[n]) for n in units if n in x},
                   {k: v for k, v in metrics.items() if v is not None}, units, record=row)
        arr = self.array(d)
        d.metrics.update(geometry(SimpleNamespace(array=arr)), rows=arr.rows, cols=arr.cols)
        d.metrics.update(coverage.of(self.folder, d.in_units()))
        return d

    def array(self, d: Design):
        """The design's array: the scene's [array] with the design's variables set at their paths."""
        from taxel.scene_tables import ArrayTable
        data = json.loads(json.dumps(self.scene.get("array") or {}))
        for v in self.variables:          # a variable elsewhere in the scene does not move the array
            key = v.path.split(".", 1)[1] if v.path.startswith("array.") else None
            if key in ArrayTable.model_fields and v.name in d.x:
                data[key] = f"{d.x[v.name]!r} m" if v.unit else d.x[v.name]
        return ArrayTable.model_validate(data)

    # -- the choice ----------------------------------------------------------------------------
    @property
    def designs(self) -> list[Design]:
        """The designs the choice is among: the candidates (but the reference's own), then the reference."""
        return [d for d in self.candidates if not d.same(self.reference)] + [self.reference]

    def _requirements(self) -> list[Requirement]:
        """The record's requirements, with the bar the reference's metrics (as they stand) imply."""
        return implied(read_requirements(self.record.get("requirements") or {}), self.reference.metrics)

    def _choose(self) -> None:
        self.requirements = self._requirements()
        ds = self.designs
        self.choice = choose([d.metrics for d in ds], self.requirements, self.objective)
        for d, v in zip(ds, self.choice.verdicts):
            d.margins = v.margins
        if self.recommended is not None:
            self.recommended.label = "recommended"
        self.priced = [(p, replace(ds[p.design], label=f"relaxed-{p.requirement.metric}",
                                   metrics=dict(ds[p.design].metrics)))
                       for p in prices([d.metrics for d in ds], self.requirements, self.choice.recommended,
                                       self.objective)]

    @cached_property
    def objective(self) -> tuple[str, str]:
        """The run's (sense, metric) from its result.json (the choice's rule 2), read once; a
        front's maximize sensitivity without one."""
        rec = _json(self.folder / "result.json") or {}
        return next(iter((rec.get("objective") or {}).items()), OBJECTIVE)

    @property
    def recommended(self) -> Design | None:
        """The design the requirements choose; None when it is the reference (kept) or none meets them."""
        i = self.choice.recommended if self.choice else None
        best = None if i is None else self.designs[i]
        return None if best is self.reference else best

    @property
    def binding(self) -> tuple[str, float] | None:
        return self.choice.binding if self.choice else None

    @property
    def notes(self) -> list[str]:
        return list(self.choice.notes) if self.choice else []

    def answer_designs(self, labels: tuple[str, ...] | None = None) -> list[Design]:
        """The recommended, the reference and each priced design (only `labels` when given), in that
        order; a design named twice (a relaxation choosing the reference) is listed under each label."""
        return [d for d in (self.recommended, self.reference, *(d for _, d in self.priced))
                if d is not None and (not labels or d.label in labels)]

    # -- what the jobs add ---------------------------------------------------------------------
    def add_coverage(self, d: Design, values: dict) -> None:
        """A design's influence metrics into OUT/coverage.json (optimize.coverage.RECORD)."""
        coverage.add(self.folder, d.in_units(), values)

    def write_presses(self, presses: list, model: dict = answer_press.PRESS_3D) -> None:
        """The 3D presses of the answer's designs (optimize.answer_press.AnswerPress) into its record."""
        answer_press.write(self.folder, presses, model)

    def write_readout(self, record: dict) -> Path:
        """The answer's designs through the bench's chain (taxel.jobs.answer_readout) into READOUT_FILE."""
        return self._write(READOUT_FILE, record)

    def write_friction_band(self, record: dict) -> Path:
        """The answer's friction band (taxel.jobs.friction_band) into optimize.band.FRICTION_FILE."""
        from taxel.optimize.band import FRICTION_FILE
        return self._write(FRICTION_FILE, record)

    def _write(self, name: str, record: dict) -> Path:
        out = self.folder / name
        out.write_text(json.dumps(record, indent=1))
        return out

    def press_of(self, d: Design):
        """The 3D press of design `d` (optimize.answer_press.AnswerPress), None when it has none."""
        x = d.vector([v.name for v in self.variables])
        return next((p for p in answer_press.read(self.record) if p.role == d.label and len(p.x) == len(x)
                     and all(abs(u - v) < 1e-6 for u, v in zip(p.x, x))), None)

    def _take_presses(self) -> None:
        """The answer's numbers from the 3D presses of its designs, when every design of the answer
        has one with an error estimate (optimize.answer_press; the reports say why not otherwise):
        sensitivity and crosstalk replaced, the reference's bar re-implied, the margins re-judged."""
        ds = [d for d in (self.recommended, self.reference) if d is not None]
        if not answer_press.read(self.record):
            return
        self.pressed = {d.label: self.press_of(d) for d in ds}
        if any(p is None or p.failed or p.sensitivity is None or p.error is None for p in self.pressed.values()):
            return
        for _, d in self.priced:              # what relaxing a requirement buys: its own press, when it has one
            p = self.press_of(d)
            if p is not None and not p.failed and p.sensitivity is not None and p.error is not None:
                _take(d, p)
                d.metrics["pressed_3d"] = True
        self.before = {d.label: (d.metrics["sensitivity"], d.metrics["crosstalk"]) for d in ds}
        for d in ds:
            _take(d, self.pressed[d.label])
        self.requirements = self._requirements()
        for d in ds:
            d.margins = judge(d.metrics, self.requirements).margins
        # a price the presses reverse: the design a relaxation would take (chosen on the candidate
        # selection's numbers) presses no better, by the objective, than the chosen design's press
        chosen = self.recommended or self.reference
        sense, metric = self.objective
        sign = 1.0 if sense == "maximize" else -1.0
        self.reversed = {d.label for _, d in self.priced if d.metrics.get("pressed_3d")
                         and None not in (d.metrics.get(metric), chosen.metrics.get(metric))
                         and sign * d.metrics[metric] <= sign * chosen.metrics[metric]}

    def confirmed(self) -> dict | None:
        """A 3D-verified front's (front-3d.json) finer confirmation mesh's numbers, label ->
        (sensitivity, crosstalk), when it solved exactly the answer's designs; else None."""
        c = (self.record.get("answer") or {}).get("confirmed") if self.kind == "front-3d" else None
        best, cb = self.recommended, (c or {}).get("best")
        names = [v.name for v in self.variables]
        if not c or not (best is None or (cb is not None and [round(v, 6) for v in best.vector(names)]
                                          == [round(v, 6) for v in cb["x"]])):
            return None
        out = {self.reference.label: (c["thesis"]["sensitivity_V_per_N"], c["thesis"]["crosstalk"])}
        if best is not None:
            out[best.label] = (cb["sensitivity_V_per_N"], cb["crosstalk"])
        return out

    @property
    def pressed_3d(self) -> bool:
        """The answer's numbers are its 3D presses'."""
        return bool(self.before)

    def _take_readout(self) -> None:
        """The designs' numbers through the bench's chain (READOUT_FILE), when the run wrote them."""
        rec = _json(self.folder / READOUT_FILE)
        for r in (rec or {}).get("designs", []):
            d = self.recommended if r["role"] == "recommended" else self.reference
            if d is None or not coverage.same(r["x_mm"], d.in_units()):
                continue                                 # written for another answer: not this design's
            d.metrics.update({k: r.get(key) for k, key in READOUT.items()})
            self.readout[d.label] = r


def _take(d: Design, p) -> None:
    """A design's metrics from its 3D press (optimize.answer_press.AnswerPress): sensitivity,
    crosstalk and, when the press recorded it, the largest silicone strain."""
    d.metrics.update(sensitivity=p.sensitivity, crosstalk=p.crosstalk,
                     **({"max_strain": p.max_strain} if p.max_strain is not None else {}))


def _json(path: Path) -> dict | None:
    return json.loads(path.read_text()) if path.exists() else None


def _unit(unit: str) -> float:
    """SI value of one `unit` ("mm" -> 0.001)."""
    from taxel.optimize.answer import si
    return si(1.0, unit)


def _keyed(row: dict, vs: list[Variable]) -> dict:
    """A record row's variables in their own units: the row keys each "<name> (<unit>)"."""
    return {v.name: row[f"{v.name} ({v.unit})"] for v in vs}


def _variables(name: str | None, row: dict | None, units: dict | None = None,
               paths: dict | None = None) -> list[Variable]:
    """The optimization's variables: from its spec when `name` is one (built-in or a file), else from
    the record (`units`: name -> unit, `paths`: name -> scene path; a record without paths: the
    array's field of that name), else from `row`'s "<name> (<unit>)" keys of a length."""
    from taxel.optimize.spec import BUILTIN, OptimizationSpec, OptimizeError, magnitude
    from taxel.studies.spec import read_spec
    if units is None and name:
        try:
            spec, _, _ = read_spec(name, BUILTIN, OptimizationSpec, OptimizeError, "optimization")
            return [Variable(n, v.path, magnitude(v.min)[1]) for n, v in spec.variables.items()]
        except (OptimizeError, OSError):
            pass
    if units is None:
        units = {k.split(" (")[0]: k.split(" (")[1][:-1] for k in row or {} if k.endswith("(mm)")}
    return [Variable(n, (paths or {}).get(n) or f"array.{n}", u) for n, u in units.items()]


def _history(path: Path, n: int) -> list[tuple[list[float], dict]]:
    """(design variables, metrics) of each evaluation in an optimum-history.csv: the n
    variables follow the evaluation and phase columns, the metrics after them (a
    metric may share a variable's name: "gap" in mm, then in m)."""
    if not path.exists():
        return []
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    head, out = rows[0], []
    for r in rows[1:]:
        out.append(([float(v) for v in r[2:2 + n]], {k: float(v) for k, v in zip(head[2 + n:], r[2 + n:]) if v != ""}))
    return out
