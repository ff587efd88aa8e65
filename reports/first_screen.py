"""The answer's first screen, what links and what is added to the table: the title
and the answer table's numbers linked to the table rows they come from (a design's
ladder row of the answer's model, a stated requirement's row), and the line of
bandwidth and first resonance. `a` is a reports.answer.FrontAnswer, `d` one of its
AnswerDesign (reports.answer imports this module, not the other way). Nothing is
solved here."""

from __future__ import annotations

from typing import NamedTuple

from taxel.reports.margins import anchor as requirement_anchor
from taxel.reports.tables import eng, percent

MATERIALS = {"PSI-5H4E": "PZT (PSI-5H4E)"}          # the answer's name of a built-in piezo


class Sweep(NamedTuple):
    """A frequency sweep of the run: its resonance (None: none in the sweep), its span
    and the page it is on."""
    resonance_Hz: float | None
    span_Hz: tuple[float, float]
    page: str
    model: str


def dynamics(answers: list, sweep: Sweep | None) -> str:
    """Page one's bandwidth and first resonance, in a line: each answer design's readout
    bandwidth (its charge amplifier's corners), and the run's frequency sweep's first
    resonance; "not computed" where the run did not."""
    bands = [f"{MATERIALS.get(a.thesis.material, a.thesis.material)} {'recommended' if d is a.recommended else 'thesis'}"
             f" design {eng(d.bandwidth_Hz[0], 'Hz', 3)} to {eng(d.bandwidth_Hz[1], 'Hz', 3)}"
             for a in answers for d in (a.recommended, a.thesis) if d is not None and d.bandwidth_Hz]
    band = ("Bandwidth (the charge amplifier's corners with each design's capacitance): " + ", ".join(bands)
            if bands else "Bandwidth: not computed")
    if sweep is None:
        res = "first resonance: not computed (no frequency sweep in this run)"
    elif sweep.resonance_Hz is None:
        res = (f"first resonance: none in the frequency sweep ({eng(sweep.span_Hz[0], 'Hz', 3)} to "
               f"{eng(sweep.span_Hz[1], 'Hz', 3)}, page {sweep.page})")
    else:
        res = (f"first resonance: {eng(sweep.resonance_Hz, 'Hz', 3)} ({sweep.model}; the frequency sweep's peak, "
               f"{eng(sweep.span_Hz[0], 'Hz', 3)} to {eng(sweep.span_Hz[1], 'Hz', 3)}, page {sweep.page})")
    return f"{band}; {res}."


def title(a, ladders: list[dict]) -> list[tuple[str, str | None]]:
    """One material's recommendation in a line, as (text, link) pieces: each number
    links to the table row it comes from (`links`)."""
    r = a.recommended
    name = MATERIALS.get(a.thesis.material, a.thesis.material)
    if r is None:
        return [(f"{name}, keep {a.reference_name}" + (
            " (no design meets every requirement)" if a.binding else ""), None)]
    hrefs = links(a, r, ladders)
    return [(f"{name}, silicone {r.silicone_above_mm:.2f} mm above and {r.silicone_below_mm:.2f} mm below, gap ",
             None), (f"{r.gap_mm:.2f} mm", hrefs.get("gap (mm)")), (": ", None),
            (eng(r.sensitivity_V_per_N, "V/N", 3), hrefs.get("open-circuit sensitivity")), (" at ", None),
            (percent(r.crosstalk), hrefs.get("open-circuit crosstalk")), (" crosstalk", None)]


# the answer table's columns held by a requirement's row, by the requirement's metric
REQUIREMENT_COLUMNS = {"pitch (mm)": "pitch", "gap (mm)": "gap", "min. detectable force": "min_detectable_force",
                       "sensitivity at the readout": "readout_sensitivity",
                       "crosstalk at the readout": "readout_crosstalk", "force range to saturation": "force_range"}


def links(a, d, ladders: list[dict]) -> dict:
    """{answer table column: "#anchor"} of design `d`: its open-circuit sensitivity and
    crosstalk to its ladder's answer row, a quantity a requirement states to that
    requirement's row (the same prediction)."""
    out = {}
    ladder_row = next((g["answer"] for g in ladders if g["role"] == d.role), None)
    if ladder_row:
        out["open-circuit sensitivity"] = out["open-circuit crosstalk"] = f"#{ladder_row}"
    stated = {q.metric for q in a.requirements if q.stated}
    for col, metric in REQUIREMENT_COLUMNS.items():
        if metric in stated and d.values.get(metric) is not None:
            out[col] = f"#{requirement_anchor(a.folder, metric)}"
    return out
