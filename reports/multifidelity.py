"""The 3D-verified front's figure, pareto-3d.png: the cheap (2D) front, every design
verified in 3D, the 3D front and the thesis design in 2D and 3D. Its numbers
(front-3d.json) are written by the result itself (MultiFidelity.to_folder)."""

from __future__ import annotations

from pathlib import Path

from taxel.optimize.metrics import METRIC_TABLE, axis_label
from taxel.optimize.multifidelity import MultiFidelity
from taxel.reports.figures import pyplot
from taxel.reports.tables import eng, percent


def draw(mf: MultiFidelity, name: str, out: Path) -> Path:
    """Draw OUT/pareto-3d.png of the verified front `mf` of the optimization `name`."""
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
    ax.set_xlabel(f"{METRIC_TABLE['crosstalk'].label} (%)")
    ax.set_ylabel(axis_label("sensitivity"))
    ax.set_title(f"{name}: cheap front and its 3D verification", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(True, alpha=0.3)
    path = Path(out) / "pareto-3d.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def draw_probe(pf, mf: MultiFidelity, name: str, out: Path) -> Path:
    """OUT/pareto-probe.png: the probe-Yeoh front (the headline, optimize.probe_front)
    beside the linear pressure-patch front verified in 3D, the thesis design under each,
    each front design's move joined by a line."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
    f3 = sorted(mf.front_3d, key=lambda d: d.fine[1])
    ax.plot([100 * d.fine[1] for d in f3], [d.fine[0] for d in f3], "s-", color="tab:blue",
            label="linear pressure patch, 3D-verified front")
    fr = pf.front
    ax.plot([100 * r["crosstalk"] for r in fr], [r["sensitivity (V/N)"] for r in fr], "o-", color="tab:red",
            label=f"probe on Yeoh silicone ({pf.level})")
    for m in pf.movements:                       # the thesis design's move too (its stars)
        ax.plot([100 * m["linear crosstalk"], 100 * m["probe crosstalk"]],
                [m["linear sensitivity (V/N)"], m["probe sensitivity (V/N)"]], "-", color="0.7", lw=0.8)
    ax.plot(100 * mf.reference.fine[1], mf.reference.fine[0], "*", color="tab:blue", ms=13, mfc="none",
            label="thesis design, linear patch")
    ref = pf.reference
    if ref.get("sensitivity (V/N)") is not None:
        ax.plot(100 * ref["crosstalk"], ref["sensitivity (V/N)"], "*", color="tab:red", ms=14,
                label="thesis design, probe")
    ax.set_xscale("log")
    ax.set_xlabel(f"{METRIC_TABLE['crosstalk'].label} (%)")
    ax.set_ylabel(axis_label("sensitivity"))
    ax.set_title(f"{name}: the front under the rig's probe (grey: each design's move)", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(True, alpha=0.3)
    path = Path(out) / "pareto-probe.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def probe_blocks(rec: dict) -> list[dict]:
    """The report's blocks of a probe front (probe-front.json, kind "probe-front"): the
    sentence, the front with each design's estimated error, the movements against the
    linear front, the definitions and the cost."""
    from taxel.reports import tables
    from taxel.reports.ladder import PROBE_COLUMNS, named
    front = [named(_readable(r), PROBE_COLUMNS) for r in rec["front"] if r["x"] != rec["reference"]["x"]]
    ref = named(_readable(rec["reference"]), PROBE_COLUMNS)
    over = [r for r in rec["front"] if not r.get("within 2 %", True)]
    row = 7 if rec.get("level") == "3D press" else 6          # reports.ladder.ROW: its numbers' model
    blocks = [{"type": "text", "text": f"Headline (ladder row {row}): " + rec["sentence"]},
              {"type": "table", "table": tables.table(front + [{**ref, "how": f"thesis design ({ref.get('how', '')})"}])},
              {"type": "text", "text": "Movements against the linear pressure-patch front (3D-verified), design by design:"},
              {"type": "table", "table": tables.table([named(_readable(m), PROBE_COLUMNS) for m in rec["movements"]])},
              {"type": "note", "text": "Definitions: " + "; ".join(f"{k.replace('tangent_sensitivity', 'small-signal sensitivity')}: {v}"
                                                          for k, v in rec["definitions"].items())
               + ". " + ranking_sentence(rec["ranking"])},
              {"type": "table", "table": tables.table(
                  [{"item": k.replace("seconds", "time (s)"), "value": f"{v:.3g}" if isinstance(v, float) else
                    ("not measured" if v is None else v)} for k, v in rec["spent"].items()],
                  title="solves spent")}]
    if over:
        blocks.append({"type": "note", "text": f"{len(over)} of {len(rec['front'])} front designs have an estimated "
                                               f"error above 2 % (column 'estimated error')."})
    pressed = [r for r in rec["front"] + [rec["reference"]] if r.get("how") == "3D press"]
    if pressed:
        blocks.append({"type": "note", "text": "Pressed in 3D on " + ", ".join(
            f"{k} {v}" for k, v in (rec.get("press_3d_model") or {}).items()) + ": " + "; ".join(
            f"{', '.join(f'{v:.3g}' for v in r['x'])} mm: estimated error {100 * r['estimated error']:.2g} % "
            f"({'within' if r['within 2 %'] else 'above'} 2 %)" for r in pressed) + "."})
    presses = [p for p in (rec.get("answer_3d") or {}).get("designs", []) if p.get("sensitivity") is not None]
    if presses:
        bound = rec["answer_3d"].get("within", 0.02)
        ok = all(p.get("error") is not None and p["error"] <= bound for p in presses)
        blocks.append({"type": "text", "text": "The answer's designs pressed in 3D by the same probe (ladder row 7, "
                                               + ("the answer's numbers" if ok else
                                                  f"not the answer's: an estimate above {100 * bound:g} %")
                                               + "): " + "; ".join(
            f"{p['role']} design ({', '.join(f'{v:.3g}' for v in p['x'])} mm) {eng(p['sensitivity'], 'V/N', 3)} "
            f"± {100 * p['error']:.2g} % at {percent(p['crosstalk'])} ± {100 * p['crosstalk_error']:.2g} % crosstalk"
            if p.get("error") is not None and p.get("crosstalk_error") is not None else
            f"{p['role']} design {eng(p['sensitivity'], 'V/N', 3)} at {percent(p['crosstalk'])} (error not estimated)"
            for p in presses) + "."})
    return blocks


def ranking_sentence(r: dict) -> str:
    """The probe record's ranking (optimize.probe_front.movements) in words."""
    order = ("The order of the linear front's designs by sensitivity is unchanged under the probe"
             if r["same order by sensitivity"] else
             "The order of the linear front's designs by sensitivity changes under the probe")
    n = r.get("designs dominating the thesis (probe)", 0)
    was = "dominated" if r["thesis dominated (linear 3D)"] else "on the front"
    now = f"dominated by {n} front design{'s' if n != 1 else ''}" if r["thesis dominated (probe)"] else "on the front"
    return f"{order}; the thesis design was {was} under the linear patch and is {now} under the probe."


def _readable(row: dict) -> dict:
    """A probe record's row for a table: the estimated error in %, flags in words (the
    relative moves are put in % by reports.tables)."""
    out = {}
    for k, v in row.items():
        if k == "x":
            continue
        if k in ("estimated error", "estimated crosstalk error") and isinstance(v, float):
            out[f"{k} (%)"] = f"{100 * v:.3g}"
        elif k == "estimate before the 3D press (V/N, crosstalk)" and v:
            out["estimated before the 3D press"] = f"{v[0]:.4g} V/N, {100 * v[1]:.3g} %"
        elif isinstance(v, bool):
            out[k] = "yes" if v else "no"
        else:
            out[k] = v
    return out
