"""What the sensor must meet, and how the answer chooses a design against it.

An optimization file's `[requirements]` table states what a part must meet, one
metric per line, in the grammar a tolerance study's `[requirements]` uses
(studies.requirements: "<= value" or ">= value", a unit or a %):

    [requirements]
    pitch = "<= 7 mm"                 # coverage: a wider gap opens non-sensitive regions
    total_thickness = "<= 2.127 mm"
    crosstalk = "<= 2 %"

The same table is the yield's spec (optimize.robust: the fraction of parts meeting
every requirement) and the answer's: the report recommends, per optimization, the
design that meets every requirement and is the best by the search's objective.

Margin of one requirement, relative to its bound and signed so that a positive
margin meets it:

    m = (value - bound) / |bound|   for ">= bound",
    m = (bound - value) / |bound|   for "<= bound".

    coverage = ">= 100 %"             # a press anywhere at smallest_force is detected
    localization_error = "<= 0.5 mm"  # the predicted rms position error there (optimize.coverage)

A coverage of 100 % is judged on the 3D surface map's weakest point (optimize.coverage:
the smallest best-taxel response over the detection threshold, searched over the
surface, not a grid's fraction): met when it is at least 1, its margin that ratio
minus 1 (the thesis PZT design's 0.992 misses by 0.8 %); relaxing it lowers that ratio
("coverage ≥ 99.2 % of the detection threshold at the weakest point"). A bound below
100 % is judged on the fraction of the surface.

How the answer chooses (`choose`):
  1. every requirement is met or not (a requirement is a constraint, its margin shown, never
     maximized: a thinner sensor is not a better one, a crosstalk far under its bound is not
     asked for, and a surface that is live everywhere cannot be more so);
  2. among the designs meeting every requirement, the recommended one is the best by the
     search's own objective (the most sensitive, for `maximize = "sensitivity"`); where two
     are equal to within TIE, the larger smallest margin over the performance requirements
     (sensitivity, crosstalk, minimum detectable force, ...; leximin) decides; margins within
     a requirement's tolerance count as zero;
  3. where the file states no requirement on sensitivity, crosstalk or the readout's
     resolution (CORE), the reference design's own sensitivity and crosstalk are the bar
     (implied requirements: at least as sensitive, at most its crosstalk), so the
     recommendation is the best design, by the objective, that is better than the reference
     in both (when no design is, the bar is dropped and the stated requirements alone decide);
  4. where no design meets every requirement, there is no recommendation: the
     answer names the binding requirement, the one the closest design (largest
     smallest margin over all requirements) misses by most, and by how much.

The objective decides, not the margins, because the margins would choose against the
user: with crosstalk <= 3 % the only performance requirement, the largest margin is the
least crosstalk at any cost in sensitivity (a user's PVDF front: 0.27 % crosstalk at
5.41 V/N, over 2.99 % at 9.40 V/N, with `maximize = "sensitivity"` stated).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from taxel.optimize.metrics import METRIC_TABLE
from taxel.studies import requirements as grammar
from taxel.studies.requirements import RequirementError

# Two designs whose sensitivities or crosstalks differ by less than this (relative) are equal for
# the implied bar: the front's own dominance tolerance (optimize.probe_front.dominates), above
# the discretisation noise of a design's metrics (about 1e-4, optimize.front.noise)
TIE = 1e-3
# A miss smaller than this (relative) is met: the optimizer's constraint tolerance (a design at a
# limit, pitch 10 mm, comes back as 10.0000001 mm) and the metrics' rounding, far below any bound's meaning
SLACK = 1e-6
LIMITS = ("total_thickness", "pitch", "gap", "footprint")     # geometry: met or not, never maximized
MET_OR_NOT = (*LIMITS, "coverage", "localization_error", "max_strain", "yield")   # rule 1: met or not
# rule 3: the reference's sensitivity and crosstalk are the bar unless one of these is stated
CORE = ("sensitivity", "tangent_sensitivity", "readout_sensitivity", "min_detectable_force", "snr", "dynamic_range",
        "crosstalk", "readout_crosstalk", "robust_sensitivity", "robust_crosstalk")
RULE = ("Each requirement's margin is relative to its bound, positive when met. Every requirement must be met; "
        "among the designs meeting them all the recommended one is the best by the search's objective (on a tie, "
        "the one with the larger smallest margin on the performance requirements).")
IMPLIED = ("No performance requirement is stated, so among the designs meeting every requirement the "
           "recommendation prefers one at least as sensitive as the reference design with at most its crosstalk "
           "(a preference, not a requirement: it is not in the requirements table and has no price), the best of "
           "those by the objective, else the best by the objective.")
OBJECTIVE = ("maximize", "sensitivity")     # the fronts' objective (a front maximizes sensitivity)
# The optimizer's metrics as the requirement grammar's outputs: name -> SI unit ("" a ratio)
OUTPUTS = {k: m.si_unit for k, m in METRIC_TABLE.items()}

__all__ = ["Requirement", "RequirementError", "read", "implied", "judge", "choose", "Verdict", "Choice", "value_of",
           "relaxations"]


@dataclass(frozen=True)
class Requirement(grammar.Requirement):
    """One requirement of an optimization: the grammar's requirement on a metric
    (studies.requirements: output op bound, SI; a ratio for crosstalk), with whether the
    file stated it or the reference design implied it (rule 3) and the tolerance within
    which a miss counts as met."""
    stated: bool = True       # False: implied by the reference design (rule 3)
    tolerance: float = 0.0    # met while margin >= -tolerance
    weakest: bool = False     # coverage judged on the 3D map's weakest point (a 100 % bound, or relaxed from one)

    @property
    def metric(self) -> str:
        return self.output

    @property
    def limit(self) -> bool:
        """Met or not, never maximized (rule 1)."""
        return self.metric in MET_OR_NOT

    def text(self) -> str:
        """Plain language: "pitch ≤ 7 mm", "crosstalk ≤ 2 %"."""
        from taxel.units import engineering
        unit = METRIC_TABLE[self.metric].unit
        bound = f"{100 * self.bound:.3g} %" if unit == "ratio" else engineering(self.bound, unit, 3)
        if self.weakest and self.bound < 1:
            return f"coverage ≥ {bound} of the detection threshold at the weakest point"
        return f"{METRIC_TABLE[self.metric].label} {'≤' if self.op == '<=' else '≥'} {bound}"


def read(table: dict[str, str]) -> list[Requirement]:
    """The requirements of a [requirements] table, in the one grammar (studies.requirements:
    the metric must exist, the bound's unit must fit it); RequirementError (one line) otherwise."""
    out = []
    for metric, text in table.items():
        r = grammar.parse_requirement(metric, text, OUTPUTS)
        m = METRIC_TABLE[metric]
        if (r.op == "<=" and r.bound < m.lo) or (r.op == ">=" and r.bound > m.hi):
            edge = m.lo if r.op == "<=" else m.hi
            what = f"{100 * edge:g} %" if m.unit == "ratio" else f"{edge:g} {m.unit}"
            raise RequirementError(f"requirements.{metric} = {text!r}: cannot be met, {m.label} is never "
                                   f"{'below' if r.op == '<=' else 'above'} {what}; give a bound within reach")
        out.append(Requirement(r.output, r.op, r.bound, r.unit,
                               weakest=metric == "coverage" and r.op == ">=" and r.bound >= 1))
    return out


def value_of(values: dict, r: Requirement) -> float | None:
    """The value `r` is judged on: the metric's, except a 100 % coverage, judged on the 3D map's
    weakest point (coverage_minimum, its response over the detection threshold; module docstring)."""
    if r.weakest and values.get("coverage_minimum") is not None:
        return values["coverage_minimum"]
    return values.get(r.metric)


def implied(reqs: list[Requirement], reference: dict) -> list[Requirement]:
    """`reqs`, plus the reference design's sensitivity and crosstalk as the bar when no
    performance requirement is stated (rule 3)."""
    if any(r.metric in CORE for r in reqs) or reference.get("sensitivity") is None:
        return list(reqs)
    bar = [Requirement("sensitivity", ">=", reference["sensitivity"], "V/N", stated=False, tolerance=TIE),
           Requirement("crosstalk", "<=", reference["crosstalk"], "", stated=False, tolerance=TIE)]
    return list(reqs) + [r for r in bar if reference.get(r.metric) is not None]


@dataclass
class Verdict:
    """One design against the requirements."""
    margins: dict[str, float | None]            # metric -> relative margin (None: not evaluated)
    meets: bool                                  # every evaluated requirement met
    weighed: tuple[float, ...]                   # the performance margins, smallest first (rule 2)
    worst: tuple[str, float] | None              # the requirement missed or met by least, and its margin


def judge(values: dict, reqs: list[Requirement]) -> Verdict:
    """`values` (metric -> SI value) against `reqs`. A requirement whose metric the
    design lacks is not evaluated (its margin None) and does not exclude the design; one
    whose check failed (values["check_errors"], optimize.coverage) does."""
    margins = {r.metric: r.margin(value_of(values, r)) for r in reqs}
    known = {k: m for k, m in margins.items() if m is not None}
    tol = {r.metric: r.tolerance for r in reqs}
    if set(values.get("check_errors") or {}) & set(margins):    # a check that failed (optimize.coverage):
        known = {**known, **{k: -math.inf for k in values["check_errors"] if k in margins}}   # never recommended
    perf = sorted(0.0 if abs(m) <= r.tolerance else m
                  for r in reqs if not r.limit and (m := margins[r.metric]) is not None)
    worst = min(known.items(), key=lambda kv: kv[1]) if known else None
    return Verdict(margins, all(m >= -tol[k] - SLACK for k, m in known.items()), tuple(perf), worst)


@dataclass
class Choice:
    """The recommendation among candidate designs (indices into the candidates)."""
    recommended: int | None
    verdicts: list[Verdict]
    requirements: list[Requirement]
    binding: tuple[str, float] | None = None    # rule 4: (metric, margin < 0) when none meets every requirement
    notes: list[str] = field(default_factory=list)


def choose(candidates: list[dict], reqs: list[Requirement], objective: tuple[str, str] = OBJECTIVE) -> Choice:
    """The design among `candidates` (metric -> SI value each) that meets every
    requirement and is the best by `objective` ("maximize" | "minimize", metric), the
    largest smallest performance margin breaking a tie (the module's rules 1 to 4)."""
    verdicts = [judge(c, reqs) for c in candidates]
    ok = [i for i, v in enumerate(verdicts) if v.meets]
    notes = [RULE]
    if any(not r.stated for r in reqs):
        notes.append(IMPLIED)
    if not ok and any(not r.stated for r in reqs):      # no design beats the reference in both: drop the bar
        stated = [r for r in reqs if r.stated]
        got = choose(candidates, stated, objective)
        got.notes.append("No design is both at least as sensitive as the reference and at most its crosstalk: "
                         "the reference's bar is dropped, the stated requirements alone decide.")
        return got
    if ok:
        sense, metric = objective
        sign = 1.0 if sense == "maximize" else -1.0

        def goal(i):
            v = candidates[i].get(metric)
            return -math.inf if v is None or not math.isfinite(v) else sign * v
        top = max(goal(i) for i in ok)
        tied = [i for i in ok if goal(i) >= top - TIE * abs(top)]
        best = max(tied, key=lambda i: (tuple(round(m, 9) for m in verdicts[i].weighed), goal(i)))
        return Choice(best, verdicts, reqs, None, notes)
    closest = max(range(len(candidates)), key=lambda i: verdicts[i].worst[1] if verdicts[i].worst else -math.inf,
                  default=None)
    binding = verdicts[closest].worst if closest is not None else None
    return Choice(None, verdicts, reqs, binding, notes)


def relaxations(candidates: list[dict], reqs: list[Requirement], chosen: int | None,
                objective: tuple[str, str] = OBJECTIVE) -> list[tuple[int, float, int]]:
    """For each stated requirement (the reference design's implied bar is a preference among the
    designs meeting them, not a requirement: it has no price), the smallest relaxation that
    changes the choice (`choose`) among `candidates`: each candidate's own value that misses
    it, nearest first, tried as the bound. (index of the requirement, relaxed bound, index of
    the design then chosen); a requirement with one is one that binds (optimize.answer.prices)."""
    from dataclasses import replace
    out = []
    for i, r in enumerate(reqs):
        if not r.stated:
            continue
        missed = sorted({v for c in candidates if (v := value_of(c, r)) is not None
                         and (r.margin(v) or 0) < -r.tolerance - SLACK},
                        key=lambda v: abs(v - r.bound))
        for v in missed:
            relaxed = [replace(q, bound=v) if j == i else q for j, q in enumerate(reqs)]
            ch = choose(candidates, relaxed, objective)
            if ch.recommended is not None and ch.recommended != chosen:
                out.append((i, v, ch.recommended))
                break
    return out
