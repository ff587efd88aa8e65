"""A run's 3D check, from `taxel optimize FILE --check-3d` itself: the design its requirements
choose (optimize.answer; the closest one when none meets them all) and its reference design,
solved again on the 3D model of the same scene (optimize.multifidelity.solve_3d: the
verification mesh VERIFY_3D, whose error against the converged 3D reference is measured,
VERIFY_3D_ERROR), each beside its 2D number. Written to OUT/check-3d.json (FILE), which the
optimization's page shows; the store keeps the solves, so a second check costs nothing.
"""

from __future__ import annotations

import json
from pathlib import Path

FILE = "check-3d.json"
VERIFY_3D_ERROR = {"sensitivity": 0.038, "crosstalk": 0.06}   # the verification mesh's worst measured (multifidelity, 6.)


def check_3d(problem, result, workers: int = 2) -> dict:
    """3D sensitivity and crosstalk of the chosen (or closest) and the reference design of
    `result` (an OptimizationResult of `problem`), written to problem.out / FILE."""
    import numpy as np
    from taxel.optimize.answer import Answer, reference_label
    from taxel.optimize.multifidelity import VERIFY_3D, solve_3d
    ans = Answer.of(result)
    picked = [d for d in (ans.closest, next((d for d in ans.designs if d.label == "reference"), None))
              if d is not None]
    picked = list({id(d): d for d in picked}.values())
    xs = [np.array(d.vector(problem.names)) for d in picked]
    got = solve_3d(problem, xs, workers) if xs else []
    rows = []
    for d, g in zip(picked, got):
        label = reference_label(result.name) if d.label == "reference" else f"the {d.label} design"
        rows.append({"design": label, "x": d.shown, "sensitivity_2d_V_per_N": d.metrics.get("sensitivity"),
                     "crosstalk_2d": d.metrics.get("crosstalk"),
                     "sensitivity_3d_V_per_N": None if g is None else g[0],
                     "crosstalk_3d": None if g is None else g[1]})
    rec = {"model": {**VERIFY_3D}, "error": VERIFY_3D_ERROR, "designs": rows}
    if problem.out is not None:
        Path(problem.out, FILE).write_text(json.dumps(rec, indent=1))
    return rec


def lines(rec: dict) -> list[str]:
    """The check for a person: 2D -> 3D per design."""
    from taxel.units import engineering
    out = [f"3D check ({rec['model']['model.type']} model, {rec['model']['mesh.size']} mesh; its error "
           f"{100 * rec['error']['sensitivity']:.2g} % in sensitivity, {100 * rec['error']['crosstalk']:.2g} % "
           "in crosstalk):"]
    for r in rec["designs"]:
        if r["sensitivity_3d_V_per_N"] is None:
            out.append(f"  {r['design']}: the 3D solve failed")
            continue
        out.append(f"  {r['design']}: sensitivity {engineering(r['sensitivity_2d_V_per_N'], 'V/N', 3)} (2D) -> "
                   f"{engineering(r['sensitivity_3d_V_per_N'], 'V/N', 3)} (3D), crosstalk "
                   f"{100 * r['crosstalk_2d']:.3g} % -> {100 * r['crosstalk_3d']:.3g} %")
    return out
