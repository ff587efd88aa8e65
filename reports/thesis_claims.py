"""The thesis's Fig. 2.5 and 2.6 beside a study of the same grid: what the thesis
states about them, checked on the study's rows.

The thesis (the seed text, section 2, Figures 2.5 and 2.6) gives these figures as
images: its text has no digitised values, only the set-up and two statements. So
the overlay is the statements, each checked on the tool's curves (one per material
and force), not a curve against curve. The copy below is the thesis's own wording
with its place in the seed; nothing is read from the seed at run time.
"""

from __future__ import annotations

import numpy as np

SOURCE = "thesis (seed 000_f6db7244331206d6), section 2, Figures 2.5 and 2.6 and the paragraph after them"
SETUP = ("2D plane stress FEM (COMSOL), Yeoh silicone, 4x4 mm taxel; silicone thickness k above and below 0 to 3 mm "
         "in 0.5 mm steps, total force f 0.2 to 1 N in 0.2 N steps as a uniform pressure; PZT 0.127 mm, PVDF 52 µm; "
         "output: the magnitude of the largest voltage of the taxel. No values are printed: the figures are images.")
CLAIMS = (
    ("rises", "by increasing the silicone layer of the sensors, the voltage produced by the taxels are increased"),
    ("slows", "the rate of this change, decreases"),
)
CHOICE = "silicone layer thickness of 1 mm have been chosen (a 2 mm thick sensor)"


def _curves(rows: list[dict]) -> dict[tuple[str, str], list[tuple[float, float]]]:
    """(material, force) -> [(thickness mm, |V|)] sorted by thickness, from a study's rows."""
    out: dict = {}
    for r in rows:
        if r.get("status") != "done":
            continue
        try:
            k = float(str(r["silicone_thickness"]).split()[0])
            v = abs(float(r["pressed_voltage"]))
        except (KeyError, TypeError, ValueError):
            continue
        out.setdefault((r.get("piezo", ""), str(r.get("force", ""))), []).append((k, v))
    return {key: sorted(pts) for key, pts in out.items() if len(pts) >= 3}


def checks(rows: list[dict]) -> list[dict]:
    """One row per material and force: does |V| rise with the silicone thickness, and
    does its rate fall (the thesis's two statements)? Empty when the study is not on
    the thesis's grid (no silicone_thickness column)."""
    out = []
    for (material, force), pts in sorted(_curves(rows).items()):
        k, v = np.array(pts).T
        slope = np.diff(v) / np.diff(k)
        rises = bool(np.all(slope > 0))
        slows = bool(np.all(np.diff(slope) < 0))
        out.append({"material": material, "force": force,
                    "thickness range (mm)": f"{k[0]:.2f}-{k[-1]:.2f}",
                    "|V| rises with thickness (thesis: yes)": "yes" if rises else
                    f"no: falls at {', '.join(f'{a:.2f}' for a, s in zip(k[1:], slope) if s <= 0)} mm",
                    "rate falls (thesis: yes)": "yes" if slows else "no",
                    "|V| at 1 mm / at 3 mm (%)": _ratio(k, v)})
    return out


def _ratio(k, v) -> str:
    if 1.0 in k and 3.0 in k:
        return f"{100 * v[list(k).index(1.0)] / v[list(k).index(3.0)]:.3g}"
    return ""
