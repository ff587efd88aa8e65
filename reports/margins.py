"""The answer's requirements table: each requirement against the prediction of the
recommended and the reference design, with its margin (optimize.requirements), in
plain words and 3 significant figures."""

from __future__ import annotations

from taxel.reports.tables import eng, percent


def _margin(m: float | None) -> str:
    """A relative margin in plain words: "+12.3 %", "< 0.01 %", "not evaluated"."""
    if m is None:
        return "not evaluated"
    if m == 0:
        return "at the bound"
    if abs(m) < 1e-4:
        return "< 0.01 %"
    return f"{100 * m:+.3g} %"


def _prediction(q, values: dict) -> str:
    """The value requirement `q` is judged on, in words; a 100 % coverage's weakest point on the 3D
    map with where it is: "the weakest point 0.992x the detection threshold, at (-7.00, -3.50) mm"."""
    from taxel.optimize.metrics import METRIC_TABLE
    from taxel.optimize.requirements import value_of
    metric, value = q.metric, value_of(values, q)
    if value is None:
        return "not evaluated"
    if q.weakest and values.get("coverage_minimum") is not None:
        at = values.get("coverage_minimum_at_mm")
        return (f"the weakest point {value:.3g}x the detection threshold"
                + (f", at ({at[0]:.2f}, {at[1]:.2f}) mm" if at else "")
                + (f" ({percent(values['coverage'])} of the surface on the map's grid)"
                   if values.get("coverage") is not None else ""))
    unit = METRIC_TABLE[metric].unit
    return percent(value) if unit == "ratio" else eng(value, unit, 3)


def requirement_rows(a) -> list[list[str]]:
    """Requirement / prediction / margin of the recommended and the reference design of
    `a` (a reports.answer.FrontAnswer: the block's requirements table, columns
    `requirement_cols(a)`; the recommended design's columns only when there is one). Only the
    stated requirements: the reference design's own sensitivity and crosstalk, the bar a run
    without a performance requirement prefers (optimize.requirements, rule 3), are not a
    requirement of the application; the answer's notes say when they decide."""
    rows = []
    for q in stated(a):
        row = [q.text()]
        for d in (a.recommended, a.thesis):
            if d is not None:
                row += [_prediction(q, d.values), _margin(d.margins.get(q.metric))]
        rows.append(row)
    return rows


def anchor(folder: str, metric: str) -> str:
    """The page anchor of a requirement's row (the answer's first screen links to it)."""
    return f"requirement-{folder}-{metric}"


def requirement_ids(a) -> list[str]:
    """The anchors of `requirement_rows(a)`, row by row."""
    return [anchor(a.folder, q.metric) for q in stated(a)]


def stated(a) -> list:
    """The requirements of `a` the file states (not the reference's implied bar)."""
    return [q for q in a.requirements if q.stated]


def requirement_cols(a) -> list[str]:
    """The requirements table's columns for `a`."""
    ref = [f"{a.reference_name.removeprefix('the ')}{'' if a.recommended else ' (kept)'}: prediction", "margin"]
    return ["requirement"] + (["recommended: prediction", "margin"] if a.recommended else []) + ref





def _full(q, d) -> bool:
    """A coverage requirement met by a surface live everywhere: at its bound, but nothing limits it."""
    return q.metric == "coverage" and not q.weakest and d.values.get("coverage") == 1.0


def limits(a) -> str:
    """What limits the design the answer gives (a reports.answer.FrontAnswer): the
    requirement that binds, else those it meets with less than 1 % to spare."""
    if a.binding is not None:
        q = next(r for r in a.requirements if r.metric == a.binding[0])
        return (f"No design found meets every requirement; the closest misses {q.text()} by "
                f"{100 * abs(a.binding[1]):.3g} %.")
    d = a.recommended or a.thesis
    tight = [q for q in a.requirements if q.stated and d.margins.get(q.metric) is not None
             and d.margins[q.metric] < 0.01 and not _full(q, d)]
    if not tight:
        return "No stated requirement is within 1 % of its bound."
    return "What limits it: " + ", ".join(f"{q.text()} ({_margin(d.margins[q.metric])})" for q in tight) + "."


def risks(a) -> list[str]:
    """The top risks of the answer's numbers, in words."""
    out = []
    err = a.error.get("sensitivity")
    if err == err and err is not None and err > 0.02:
        out.append(f"the numbers are an estimate with {100 * err:.2g} % error, above the 2 % a 3D press by the "
                   "rig's probe would give")
    if err != err:
        out.append("the numbers' error against 3D is not estimated")
    if a.chain and "hum" in a.chain:
        out.append("mains hum sets the minimum detectable force: the notch and the wiring matter more than the "
                   "design")
    return out
