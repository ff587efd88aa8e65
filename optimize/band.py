"""A number's uncertainty with all of its parts: the relative band of each source, combined
in quadrature (independent sources), and propagated to the quantities derived from it.

    b = Band({"3D press mesh": 0.014, "friction": 0.063})
    b.total                   # 0.0645: sqrt(0.014**2 + 0.063**2)
    b.flagged                 # True: above FLAG (2 %)
    b.with_parts({"feedback capacitor": 0.05})   # a derived quantity: its own parts added

Sources (optimize.answer_press, taxel.jobs.friction_band, the scene):
- the press mesh: the 3D press family's calibrated error (optimize.answer_press.ANSWER_PRESS_ERROR);
- friction: the move between the probe's limits, frictionless against the answer's own law
  (sticking), or to the rig's Coulomb coefficient when the rig file states one
  (`friction_share`); a 2D press's band, about one point wider than a 3D one where both exist;
- the material data's spread, where the scene gives one (none of the built-in scenes does);
- the readout's component tolerances, where the scene's readout states them (none does: the
  part is absent, and the assumptions table says so).

A quantity derived by products and quotients with exact factors (charge per newton =
sensitivity x capacitance, the readout's V/N = charge / C_f, the minimum detectable force =
noise / V/N, saturation = swing / V/N) carries the relative band of the number it comes from,
plus the parts of its other factors when they have one.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

FLAG = 0.02          # a band above it is flagged on the page
FRICTION_FILE = "friction-band.json"     # taxel.jobs.friction_band writes it into the optimization folder


@dataclass
class Band:
    """Relative parts of one number's uncertainty, source -> fraction (None: not known)."""
    parts: dict[str, float | None] = field(default_factory=dict)

    @property
    def total(self) -> float:
        known = [v for v in self.parts.values() if v is not None]
        return math.sqrt(sum(v * v for v in known)) if known else float("nan")

    @property
    def flagged(self) -> bool:
        return self.total > FLAG

    def with_parts(self, extra: dict[str, float | None]) -> "Band":
        return Band({**self.parts, **extra})

    def text(self) -> str:
        """"mesh 1.4 %, friction 6.3 %" (the parts, largest first)."""
        known = sorted(((k, v) for k, v in self.parts.items() if v is not None), key=lambda kv: -kv[1])
        return ", ".join(f"{k} {100 * v:.2g} %" for k, v in known) or "not estimated"


def friction_share(folder: Path, role: str, x_mm: dict | None = None) -> dict[str, float] | None:
    """{"sensitivity": rel, "crosstalk": rel} of one answer design: how far the probe's friction
    moves it from the answer's law (taxel.jobs.friction_band's FRICTION_FILE in `folder`); None when the
    folder has no band for this design. With the rig's coefficient stated, the move to it;
    else the largest move to either limit."""
    path = Path(folder) / FRICTION_FILE
    if not path.exists():
        return None
    rec = json.loads(path.read_text())
    for d in rec["designs"]:
        if d["role"] != role or (x_mm and any(abs(d["x_mm"].get(k, v) - v) > 1e-6 for k, v in x_mm.items())):
            continue
        ref = next((leg for leg in d["legs"] if leg["friction"] == rec["reference"]), None)
        if ref is None or ref["sensitivity_V_per_N"] is None:
            return None
        mu = rec.get("coefficient")
        legs = [leg for leg in d["legs"] if leg is not ref and leg["sensitivity_V_per_N"] is not None
                and leg.get("success", True) and (isinstance(mu, str) or leg["friction"] == mu)]
        if not legs:
            return None
        out = {"sensitivity": max(abs(leg["sensitivity_V_per_N"] / ref["sensitivity_V_per_N"] - 1) for leg in legs)}
        if ref.get("crosstalk"):
            out["crosstalk"] = max(abs(leg["crosstalk"] / ref["crosstalk"] - 1) for leg in legs
                                   if leg.get("crosstalk") is not None)
        return out
    return None
