"""Every number of an answer with its band and all of its parts (optimize.band), and the largest
force a press of the answer reached (saturation past it is said so). Called by
reports.answer.headline_front; nothing is solved here."""

from __future__ import annotations

import json
from pathlib import Path

from taxel.reports.answer_design import FrontAnswer
from taxel.units import magnitude

DERIVED = ("readout_sensitivity", "charge_sensitivity", "min_detectable_force", "force_range")


def bands(a: FrontAnswer, folder: Path) -> None:
    """Every number's band with all of its parts (optimize.band): the model's own error (the 3D
    press mesh's, calibrated) and the probe's friction (friction-band.json), combined; the
    quantities derived from the sensitivity carry its band (the readout states no component
    tolerances, the scene no material spread: their parts are absent, the assumptions say so).
    a.error holds the combined totals, the larger of the two designs' per quantity."""
    from taxel.optimize.band import Band, friction_share
    mesh = "3D press mesh" if a.row == 7 else "model error"
    out: dict[str, Band] = {}
    for d in (a.recommended, a.thesis):
        if d is None:
            continue
        share = friction_share(folder, d.role, d.design.in_units()) or {}
        for q in ("sensitivity", "crosstalk"):
            b = Band({mesh: a.error.get(q), "friction": share.get(q)})
            if q not in out or b.total > out[q].total or out[q].total != out[q].total:
                out[q] = b
    for q in DERIVED:
        out[q] = out["sensitivity"]
    a.bands = out
    a.error = {q: b.total for q, b in out.items()}
    top = _largest_force(folder)
    for d in (a.recommended, a.thesis, *(d for _, d in a.priced)):
        if d is not None and top is not None:
            d.values["largest_force"] = top


def _largest_force(folder: Path) -> float | None:
    """The largest force a press of the answer reached (its probe's operating force), N."""
    path = folder / "probe-front.json"
    if not path.exists():
        return None
    force = json.loads(path.read_text()).get("press", {}).get("force")
    return magnitude(force) if force else None
