"""The answer of one optimization run: which design its requirements choose, which
requirement binds, and, when none meets them all, which is missed, by how much, and
which design comes closest.

    ans = Answer.of(result)          # an OptimizationResult (optimize.result)
    ans.chosen                       # the Design the requirements choose, or None
    ans.binding                      # (Requirement, margin): missed by most, or met by least
    ans.lines()                      # what `taxel optimize` prints and the report shows

A design is a mapping of the optimization's own variables to SI values (`Design.x`),
with its metrics (SI); the candidates are the reference design (when the spec names
one) and every design the run ended on (the optimum, or each front run's). The choice
is optimize.requirements.choose's (its rules 1 to 4).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import lru_cache

from taxel.optimize.metrics import METRIC_TABLE
from taxel.optimize.requirements import (OBJECTIVE, SLACK, Choice, Requirement, choose, implied, read, relaxations,
                                         value_of)
from taxel.units import engineering, quantity


@dataclass
class Design:
    """One candidate: its variables (name -> SI value), its metrics (SI) and what it is. The
    same type holds a run's candidates (`Answer`) and an optimization folder's answer designs
    (optimize.answer_folder.FolderAnswer)."""
    label: str                                  # "reference", "optimum", "front: crosstalk <= 1.2 %", "recommended"
    x: dict[str, float]
    metrics: dict = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)    # name -> the variable's own unit ("" a number)
    margins: dict = field(default_factory=dict)            # metric -> relative margin (optimize.requirements)
    record: dict = field(default_factory=dict)             # the design's own row of the record it was read from

    def in_units(self) -> dict[str, float]:
        """The variables in their own units ({"gap": 3.0} for a gap in mm): how a folder's records key a design."""
        return {n: float(f"{v / _factor(self.units.get(n, '')):.15g}") for n, v in self.x.items()}

    def vector(self, names: list[str]) -> list[float]:
        """The variables `names` in their own units, in that order (an Optimization's x)."""
        got = self.in_units()
        return [got[n] for n in names]

    def same(self, other: "Design", tol: float = 1e-6) -> bool:
        """The same design: every variable within `tol` of the other's, in its own unit."""
        a, b = self.in_units(), other.in_units()
        return a.keys() == b.keys() and all(abs(a[n] - b[n]) <= tol for n in a)

    @property
    def shown(self) -> dict[str, str]:
        """name -> the value in the variable's own unit: "1 mm"."""
        return {n: f"{v:.4g} {self.units.get(n, '')}".strip() for n, v in self.in_units().items()}

    def text(self) -> str:
        """"silicone above 1 mm, gap 3 mm" (the variables' names in words, as the pages write them)."""
        return ", ".join(f"{n.replace('_', ' ')} {s}" for n, s in self.shown.items())


@dataclass
class Price:
    """What relaxing one requirement buys: the smallest relaxation of its bound, to a
    candidate's own value, at which the choice moves to another design (`design`, an index
    into the candidates)."""
    requirement: Requirement
    relaxed: float                 # the relaxed bound (SI)
    design: int

    def text(self, designs: list[dict], chosen: dict | None) -> str:
        """"localization error ≤ 1 mm binds: at ≤ 1.41 mm, 938 mV/N (+16 %) at 5.11 % crosstalk (-32 %)"."""
        r = replace(self.requirement, bound=self.relaxed)
        m = designs[self.design]
        gain = []
        for k, unit in (("sensitivity", "V/N"), ("crosstalk", "ratio")):
            if m.get(k) is None:
                continue
            rel = f" ({100 * (m[k] / chosen[k] - 1):+.2g} %)" if chosen and chosen.get(k) else ""
            gain.append((f"{100 * m[k]:.3g} % crosstalk" if unit == "ratio" else engineering(m[k], unit, 3)) + rel)
        return f"{self.requirement.text()} binds: at {_bound(r)} the choice is {' at '.join(gain)}"


def _bound(r: Requirement) -> str:
    return r.text()[len(METRIC_TABLE[r.metric].label) + 1:]


def prices(candidates: list[dict], reqs: list[Requirement], chosen: int | None,
           objective: tuple[str, str] = OBJECTIVE) -> list[Price]:
    """What relaxing each stated requirement buys (optimize.requirements.relaxations), as Prices."""
    return [Price(reqs[i], v, d) for i, v, d in relaxations(candidates, reqs, chosen, objective)]


def reference_label(name: str) -> str:
    """What a run calls its reference design: "thesis design" for a built-in optimization (its
    reference is the seed's design), else "reference design" (the user's own)."""
    from taxel.optimize.spec import BUILTIN
    return "thesis design" if name and (BUILTIN / f"{name}.toml").exists() else "reference design"


def si(value: float, unit: str) -> float:
    """A variable's value in its own unit, in SI."""
    return float(value) * _factor(unit)


@lru_cache(maxsize=None)
def _factor(unit: str) -> float:
    """SI value of one `unit` ("mm" -> 0.001; "" a plain number: 1)."""
    return float(quantity(f"1 {unit}").to_base_units().magnitude) if unit else 1.0


@dataclass
class Answer:
    """The requirements of a run, its candidates, and the choice among them."""
    requirements: list[Requirement]
    designs: list[Design]
    choice: Choice
    objective: tuple[str, str] = OBJECTIVE      # the run's (sense, metric): the choice's rule 2

    @classmethod
    def of(cls, result) -> "Answer":
        """The answer of an OptimizationResult (optimize.result)."""
        designs = []
        units = dict(zip(result.names, result.units))
        ref = result.reference
        if ref and ref.get("sensitivity") is not None:
            designs.append(Design("reference", {n: si(ref["x"][n], u) for n, u in zip(result.names, result.units)},
                                  {k: v for k, v in ref.items() if k != "x"}, units))
        runs = [("optimum", result.optimum)] if result.optimum is not None else \
            [(f"front: crosstalk <= {100 * r.bound:.3g} %", r.result) for r in result.runs if r.bound is not None]
        for label, r in runs:
            if r is not None and r.metrics.get("sensitivity") is not None:
                designs.append(Design(label, {n: si(v, u) for n, u, v in zip(result.names, result.units, r.x)},
                                      dict(r.metrics), units))
        reqs = implied(read(result.requirements), ref or {})
        objective = (result.sense, result.metric)
        return cls(reqs, designs, choose([d.metrics for d in designs], reqs, objective), objective)

    @property
    def chosen(self) -> Design | None:
        return None if self.choice.recommended is None else self.designs[self.choice.recommended]

    @property
    def closest(self) -> Design | None:
        """The chosen design, or the one missing its worst requirement by least."""
        if self.chosen is not None:
            return self.chosen
        if not self.designs:
            return None
        worst = [v.worst[1] if v.worst else -1e300 for v in self.choice.verdicts]
        return self.designs[max(range(len(worst)), key=worst.__getitem__)]

    @property
    def binding(self) -> tuple[Requirement, float] | None:
        """The stated requirement the closest design misses by most, or meets by least."""
        d = self.closest
        if d is None:
            return None
        margins = self.choice.verdicts[self.designs.index(d)].margins
        known = [(r, margins[r.metric]) for r in self.requirements if r.stated and margins.get(r.metric) is not None
                 and (margins[r.metric] < 0 or r.bound not in (METRIC_TABLE[r.metric].lo, METRIC_TABLE[r.metric].hi))]
        return min(known, key=lambda rm: rm[1]) if known else None

    def rows(self) -> list[dict]:
        """The requirements table: one row per requirement, the chosen (or closest) design's value,
        its margin and whether it is met."""
        d = self.closest
        if d is None or not any(r.stated for r in self.requirements):
            return []
        v = self.choice.verdicts[self.designs.index(d)]
        out = []
        for r in self.requirements:
            m = v.margins.get(r.metric)
            value = value_of(d.metrics, r)
            out.append({"requirement": r.text(), "from": "stated" if r.stated else "implied by the reference design",
                        f"{d.label} design": "not evaluated" if value is None else _value(r, value),
                        "margin": "" if m is None else f"{100 * m:+.3g} %",
                        "met": "not evaluated" if m is None else ("yes" if m >= -r.tolerance - SLACK else "NO")})
        return out

    def lines(self) -> list[str]:
        """The verdict for a person, one requirement a line."""
        if not [r for r in self.requirements if r.stated]:
            return []
        if not self.designs:
            return ["requirements: no design was evaluated"]
        d = self.closest
        v = self.choice.verdicts[self.designs.index(d)]
        head = (f"requirements: every one met by the {d.label} design ({d.text()})" if self.chosen is not None else
                f"requirements NOT met by any design; the closest is the {d.label} design ({d.text()})")
        out = [head]
        for r in self.requirements:
            m = v.margins.get(r.metric)
            value = value_of(d.metrics, r)
            shown = "not evaluated" if value is None else _value(r, value)
            state = "not evaluated" if m is None else ("met" if m >= -r.tolerance - SLACK else "MISSED")
            by = "" if m is None else f" ({'margin' if m >= 0 else 'short by'} {abs(100 * m):.3g} %)"
            out.append(f"  {r.text()}{'' if r.stated else ' (implied by the reference)'}: {shown}, {state}{by}")
        b = self.binding
        if b is not None:
            out.append(f"  closest to its bound: {b[0].text()} ({'met with' if b[1] >= 0 else 'missed by'} "
                       f"{abs(100 * b[1]):.3g} %)")
        metrics = [x.metrics for x in self.designs]
        for p in prices(metrics, self.requirements, self.choice.recommended, self.objective):
            out.append(f"  {p.text(metrics, self.chosen.metrics if self.chosen else None)} "
                       f"(the {self.designs[p.design].label} design: {self.designs[p.design].text()})")
        return out


def _value(r: Requirement, value: float) -> str:
    if r.weakest:
        return f"the weakest point at {value:.3g}x the detection threshold"
    unit = METRIC_TABLE[r.metric].unit
    return f"{100 * value:.3g} %" if unit == "ratio" else (f"{value:.3g} dB" if unit == "dB" else
                                                          engineering(value, unit, 3))
