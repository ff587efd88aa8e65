"""The 3D-verified front's files: front-3d.json (the cheap front, every 3D-verified
design, the 3D front, the thesis design in 2D and 3D, the rounds, the plan and
what was spent, and the answer to the thesis's question) and pareto-3d.png."""

from __future__ import annotations

import json
from pathlib import Path

from taxel.optimize.multifidelity import CONFIRM_3D, VERIFY_3D, MultiFidelity, best_below
from taxel.reports.figures import pyplot


def answer(mf: MultiFidelity) -> dict:
    """Is the reference design on the 3D front, and what does the 3D front offer?"""
    s0, c0 = mf.reference.fine
    better = [d for d in mf.front_3d if d is not mf.reference and d.fine[0] >= s0 and d.fine[1] <= c0]
    out = {"thesis_3d": {"sensitivity_V_per_N": s0, "crosstalk": c0},
           "thesis_on_3d_front": not better and any(d is mf.reference for d in mf.front_3d)}
    b = best_below(mf)
    if b is not None:
        out["best_at_or_below_thesis_crosstalk"] = {"x": b.x, "sensitivity_V_per_N": b.fine[0], "crosstalk": b.fine[1],
                                                   "sensitivity_gain": b.fine[0] / s0 - 1}
    conf = mf.confirmed
    if "reference" in conf:
        out["confirmed"] = {"model": {k: str(v) for k, v in CONFIRM_3D.items()},
                            "thesis": {"sensitivity_V_per_N": conf["reference"][0], "crosstalk": conf["reference"][1]}}
        if "best" in conf:
            b = best_below(mf)
            out["confirmed"]["best"] = {"x": b.x, "sensitivity_V_per_N": conf["best"][0], "crosstalk": conf["best"][1],
                                        "sensitivity_gain": conf["best"][0] / conf["reference"][0] - 1}
    same = [d for d in mf.front_3d if d.fine[0] >= s0]
    if same:
        b = min(same, key=lambda d: d.fine[1])
        out["least_crosstalk_at_thesis_sensitivity"] = {"x": b.x, "sensitivity_V_per_N": b.fine[0],
                                                        "crosstalk": b.fine[1]}
    return out


def sentence(problem, a: dict) -> str:
    t = a["thesis_3d"]
    head = (f"In 3D the thesis design gives {t['sensitivity_V_per_N']:.3f} V/N at {100 * t['crosstalk']:.2f} % "
            f"crosstalk; it is {'on' if a['thesis_on_3d_front'] else 'not on'} the 3D-verified front.")
    b = a.get("best_at_or_below_thesis_crosstalk")
    if b and not a["thesis_on_3d_front"]:
        x = ", ".join(f"{n.replace('_', ' ')} {v:.2f} {u}" for n, v, u in zip(problem.names, b["x"], problem.units))
        head += (f" The 3D front offers {b['sensitivity_V_per_N']:.3f} V/N ({100 * b['sensitivity_gain']:+.1f} %) "
                 f"at {100 * b['crosstalk']:.2f} % crosstalk ({x}).")
    c = a.get("confirmed")
    if c:
        t = c["thesis"]
        head += (f" On the finer 3D mesh (1.5 mm, 0.6 mm at the taxels): the thesis design "
                 f"{t['sensitivity_V_per_N']:.3f} V/N at {100 * t['crosstalk']:.2f} %")
        if "best" in c:
            b = c["best"]
            head += (f", the front's design {b['sensitivity_V_per_N']:.3f} V/N ({100 * b['sensitivity_gain']:+.1f} %) "
                     f"at {100 * b['crosstalk']:.2f} %")
        head += "."
    return head


def write(problem, mf: MultiFidelity, out: Path) -> dict:
    def row(d):
        return {**{f"{n} ({u})": v for n, v, u in zip(problem.names, d.x, problem.units)},
                "sensitivity 2D (V/N)": d.cheap[0], "crosstalk 2D": d.cheap[1],
                "sensitivity 3D (V/N)": d.fine[0] if d.fine else None, "crosstalk 3D": d.fine[1] if d.fine else None,
                "predicted sensitivity": d.predicted[0] if d.predicted else None,
                "predicted crosstalk": d.predicted[1] if d.predicted else None}
    a = answer(mf)
    rec = {"verify_3d": VERIFY_3D, "confirm_3d": {k: str(v) for k, v in CONFIRM_3D.items()}, "cheap_front": [row(d) for d in mf.cheap_front],
           "verified": [row(d) for d in mf.verified], "front_3d": [row(d) for d in mf.front_3d],
           "reference": row(mf.reference), "rounds": mf.rounds, "plan": mf.plan, "spent": mf.spent,
           "answer": a, "sentence": sentence(problem, a)}
    (Path(out) / "front-3d.json").write_text(json.dumps(rec, indent=1))
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
    cf = sorted(mf.cheap_front, key=lambda d: d.cheap[1])
    ax.plot([100 * d.cheap[1] for d in cf], [d.cheap[0] for d in cf], "o-", color="tab:blue", label="cheap (2D) front")
    ax.plot([100 * d.fine[1] for d in mf.verified], [d.fine[0] for d in mf.verified], ".", color="0.6",
            label="designs verified in 3D")
    f3 = sorted(mf.front_3d, key=lambda d: d.fine[1])
    ax.plot([100 * d.fine[1] for d in f3], [d.fine[0] for d in f3], "s-", color="tab:red", label="3D-verified front")
    ax.plot(100 * mf.reference.cheap[1], mf.reference.cheap[0], "*", color="tab:blue", ms=13, mfc="none",
            label="thesis design, 2D")
    ax.plot(100 * mf.reference.fine[1], mf.reference.fine[0], "*", color="tab:red", ms=14, label="thesis design, 3D")
    ax.set_xscale("log")
    ax.set_xlabel("crosstalk (%)")
    ax.set_ylabel("sensitivity (V/N)")
    ax.set_title(f"{problem.spec.name}: cheap front and its 3D verification", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(True, alpha=0.3)
    fig.savefig(Path(out) / "pareto-3d.png", dpi=120)
    plt.close(fig)
    return rec
