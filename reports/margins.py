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


def _prediction(metric: str, value: float | None) -> str:
    from taxel.optimize.metrics import METRIC_TABLE
    if value is None:
        return "not evaluated"
    unit = METRIC_TABLE[metric].unit
    return percent(value) if unit == "ratio" else eng(value, unit, 3)


def requirement_rows(a) -> list[list[str]]:
    """Requirement / prediction / margin of the recommended and the reference design of
    `a` (a reports.answer.FrontAnswer: the block's requirements table; a requirement
    implied by the reference design says so)."""
    rows = []
    for q in a.requirements:
        row = [q.text() + ("" if q.stated else f" ({a.reference_name}'s own)")]
        for d in (a.recommended, a.thesis):
            if d is None:
                row += ["—", "—"]
                continue
            row += [_prediction(q.metric, d.values.get(q.metric)), _margin(d.margins.get(q.metric))]
        rows.append(row)
    return rows


REQUIREMENT_COLS = ["requirement", "recommended: prediction", "margin", "reference: prediction", "margin"]

