"""The caption of each figure a result folder holds, from its file name: one
sentence saying what is drawn, against what, and from which model. Every figure on
a report page has one (the page test checks it)."""

from __future__ import annotations

import re
from pathlib import Path

_OUTPUTS = {"pressed_voltage": "the pressed taxel's open-circuit voltage (|V|)",
            "max_strain": "the largest silicone strain", "sensitivity": "the sensitivity (V/N)",
            "crosstalk": "the crosstalk"}

_FIXED = {
    "pareto.png": "The 2D front: the most sensitive design at each crosstalk bound (blue), every feasible design "
                  "the search evaluated (grey) and the thesis design (red star), on the cheap 2D model.",
    "pareto-3d.png": "The 2D front (blue), every design re-solved in 3D (grey), the 3D-verified front (red) and "
                     "the thesis design in 2D (hollow star) and 3D (filled star); crosstalk on a log axis.",
    "pareto-probe.png": "The front under the rig's probe on Yeoh silicone (red) beside the linear pressure-patch "
                        "front verified in 3D (blue); grey lines join each linear front design to the same design "
                        "under the probe; the thesis design under each (hollow and filled star); crosstalk on a log "
                        "axis.",
    "optimum-convergence.png": "The objective at every evaluation of the search (grey) and the best so far.",
    "noise-budget.png": "Left: the noise density at the readout output per source, stacked, with the mains lines "
                        "dotted. Right: each source's share of the band's variance.",
    "render.png": "The deformed mesh under the press: the piezo coloured by its electric potential, the silicone "
                  "grey (a 3D mesh is cut through the pressed row).",
    "section.png": "Cross-section: the potential in the piezo on the deformed mesh (top) and the vertical "
                   "displacement (bottom).",
    "taxels.png": "The open-circuit voltage of every taxel for the press (mV); the pressed taxel in bold.",
    "mesh.png": "The mesh the solve used: piezo orange, silicone grey, edges drawn; its element, node and "
                "unknown counts and element sizes in the title.",
}


def caption(path: Path) -> str:
    """The caption of a figure file written by the tool."""
    name = Path(path).name
    if name in _FIXED:
        return _FIXED[name]
    m = re.fullmatch(r"(.+)-vs-(.+)\.png", name)
    if m:
        out, par = m.groups()
        return (f"Parameter study: {_OUTPUTS.get(out, out.replace('_', ' '))} against "
                f"{par.replace('_', ' ')}, one line per value of the other parameters, one panel per material.")
    if name.startswith("coverage-map-"):
        from taxel.reports.coverage_map import CAPTION
        return CAPTION
    if name.endswith("-bode.png"):
        return ("Frequency response: the readout output per newton (magnitude, top) and its phase (unwrapped, "
                "bottom); the notch and the resonance are marked.")
    if name.endswith("-transient.png"):
        return "Time response: the applied force (top) and the readout's output voltage (bottom)."
    if name.endswith("-lumped.png"):
        return "Frequency response of the lumped 3-DoF model through the readout."
    if name.endswith("-contact.png"):
        return "Indenter press: force against travel (left) and each electrode's voltage against force (right)."
    if re.fullmatch(r".+-[\d.]+N\.png", name):
        return "Work against precision: wall time against error (log-log), one point per model and mesh."
    return f"{name.removesuffix('.png').replace('-', ' ').replace('_', ' ')}."
