"""The answer's friction band on the report's first page: the recommended and the thesis
design's sensitivity and crosstalk when the rig's probe is frictionless, at the rig's
Coulomb coefficient (when the rig file gives one, `[probe] friction`) and sticking, read
from FILE in an optimization folder (written by taxel.jobs.friction_band; no solves here).
"""

from __future__ import annotations

import json
from pathlib import Path

from taxel.reports.ladder import SHORT
from taxel.reports.tables import eng, percent

from taxel.optimize.band import FRICTION_FILE as FILE     # in the optimization folder, beside probe-front.json


def _law(friction) -> str:
    return friction if isinstance(friction, str) else f"Coulomb, mu = {friction:g}"


def block(folder: Path | None) -> dict | None:
    """Template data of the band's table ({caption, cols, rows, note}); None when the
    folder holds no band."""
    path = None if folder is None else Path(folder) / FILE
    if path is None or not path.exists():
        return None
    rec = json.loads(path.read_text())
    rows = []
    for d in rec["designs"]:
        ref = next((leg for leg in d["legs"] if leg["friction"] == rec["reference"]), None)
        for leg in d["legs"]:
            s = leg["sensitivity_V_per_N"]
            if s is None:                  # the press did not converge even at its first load step
                rows.append([d["role"], _law(leg["friction"]), "—", "—", f"no state: {leg['stop']}"])
                continue
            rel = ("" if ref is None or leg is ref or ref["sensitivity_V_per_N"] is None else
                   f" ({100 * (s / ref['sensitivity_V_per_N'] - 1):+.1f} %)")
            rows.append([d["role"], _law(leg["friction"]), eng(s, "V/N", 3) + rel,
                         "—" if leg["crosstalk"] is None else percent(leg["crosstalk"]),
                         eng(leg["force_N"], "N", 3) + ("" if leg["success"] else f" (stopped short: {leg['stop']})")])
    coefficient = rec["coefficient"]
    said = (f"the rig file ({rec['rig']}) gives mu = {coefficient:g}" if not isinstance(coefficient, str) else
            f"the rig file ({rec['rig']}) gives no coefficient ([probe] friction = \"{coefficient}\"): the two "
            "limits are the band")
    return {"caption": "friction band: the probe's unknown friction on the silicone",
            # the probe front's own law is the ladder's row 5 (reports.ladder): the columns name it
            "cols": ["design", "friction", f"sensitivity {SHORT[5]} (vs {rec['reference']}: ladder row 5)",
                     f"crosstalk {SHORT[5]}", "force"],
            "rows": rows,
            "note": (f"How much the probe's friction moves the answer: {said}. Model: {rec['model']}. "
                     f"{rec['three_d']} Computed in {rec['seconds']:.0f} s.")}
