"""The warm-touch section: a warm finger's heat in the stack (the temperature field at the
touch's end, to scale) and the pressed taxel's readout output for the touch alone, the
press alone and both, with the false force beside the minimum detectable force; and the
answer's row of it (the main job writes FILE into each optimization folder: taxel.jobs.warm_touch).
Reads FILE from a folder (written by taxel.analyses.solves.warm_touch.WarmTouchResult.write);
never solves. Every word a page shows is plain (reports.plain): the model by its name
(findings.MODEL_NAMES), numbers to 3 significant figures."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from taxel.analyses.solves.warm_touch import FILE, drift_words
from taxel.reports.findings import MODEL_NAMES
from taxel.reports.page import data_uri
from taxel.reports.tables import eng, table

FIGURE = "warm-touch.png"


def record(folder) -> dict | None:
    """The folder's warm-touch record, None when it holds none."""
    path = None if folder is None else Path(folder) / FILE
    return json.loads(path.read_text()) if path is not None and path.exists() else None


def figure(rec: dict, path: Path) -> Path:
    """The temperature field at the touch's end (left; 2D and axisymmetric models) and the
    output traces (right)."""
    from taxel.reports.figures import pyplot
    plt = pyplot()
    field = rec.get("field")
    fig, axes = plt.subplots(1, 2 if field else 1, figsize=(11 if field else 6, 4.2), layout="constrained",
                             squeeze=False)
    if field:
        ax = axes[0, 0]
        p = np.asarray(field["points_m"]) * 1e3
        T = np.asarray(field["temperature_K"]) - 273.15
        im = ax.tripcolor(p[0], p[1], np.asarray(field["triangles"]), T, shading="gouraud", cmap="inferno")
        ax.set_aspect("equal")
        ax.set(xlabel="r (mm)" if rec["model"] == "axisymmetric" else "x (mm)", ylabel="z (mm)",
               title=f"temperature at {rec['field_time_s']:g} s (the finger lifts)")
        fig.colorbar(im, ax=ax, label="°C", shrink=0.8)
    bx = axes[0, -1]
    t = np.asarray(rec["t_s"])
    scale = max(np.abs(rec["warm_press"]).max(), 1e-30)
    unit, k = ("V", 1.0) if scale >= 0.1 else ("mV", 1e3)
    bx.plot(t, k * np.asarray(rec["press"]), label=f"press {rec['force_N']:.3g} N", lw=1)
    bx.plot(t, k * np.asarray(rec["warm_press"]), label="warm press (both)", lw=1, ls="--")
    bx.plot(t, k * np.asarray(rec["touch"]) * 10, label="warm touch alone (x10)", lw=1.5)
    bx.axvline(rec["duration_s"], color="k", lw=0.6, ls=":")
    bx.set(xlabel="time (s)", ylabel=f"{rec['readout']} ({unit})",
           title=f"false force {eng(rec['false_force_N'], 'N', 3)}")
    bx.legend(fontsize=8)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def block(folder) -> dict | None:
    """Template data of the section ({caption, cols, rows, note, png: the figure's bytes, drawn
    in a temporary folder}); None without a record."""
    rec = record(folder)
    if rec is None:
        return None
    mdf = rec["min_detectable_force_N"]
    rows = [["finger / skin", f"{rec['finger_K'] - 273.15:.1f} °C / {rec['ambient_K'] - 273.15:.1f} °C, "
                              f"held {rec['duration_s']:g} s"],
            ["film: rise, fastest rate", f"{rec['film_rise_K']:.3g} K, {rec['film_max_rate_K_per_s']:.3g} K/s"],
            ["pyroelectric charge (largest)", eng(rec["pyro_charge_C"], "C", 3)],
            ["false force", eng(rec["false_force_N"], "N", 3)],
            ["minimum detectable force", "-" if mdf is None else eng(mdf, "N", 3)],
            ["false force / minimum detectable", "-" if rec["ratio"] is None else f"{rec['ratio']:.3g}"],
            ["sensitivity drift, 0 to 50 °C", drift_text(rec)]]
    import tempfile
    with tempfile.TemporaryDirectory(prefix="taxel-report-") as tmp:    # redrawn from the stored record
        png = figure(rec, Path(tmp) / FIGURE).read_bytes()
    return {"caption": "warm touch: a finger's heat at the readout", "cols": ["", rec["scene"]], "rows": rows,
            "png": png,
            "note": (f"{rec['readout']}; {_model(rec)} model. The false force is the press, held as long, with the "
                     "same peak output (docs/theory/heat.md).")}


def drift_text(rec: dict) -> str:
    """The record's sensitivity drift in words (taxel.analyses.solves.warm_touch.drift_words)."""
    return drift_words(rec.get("drift"), rec["readout"])


def _model(rec: dict) -> str:
    """The record's model for a person ("2D plane strain", not the scene key)."""
    return MODEL_NAMES.get(rec["model"], rec["model"].replace("_", " "))


def section(folder) -> dict | None:
    """The page's "Warm touch" section (its table and figure), None without a record."""
    warm = block(folder)
    if warm is None:
        return None
    return {"title": "Warm touch", "blocks": [
        {"type": "table", "table": table([{"": k, warm["cols"][1]: v} for k, v in warm["rows"]], title=warm["caption"])},
        {"type": "figures", "images": [{"src": data_uri(warm["png"]), "caption": warm["note"]}]}]}


ANSWER_COLS = ["design", "finger", "film rise", "false force", "minimum detectable force", "false / detectable"]


def answer_row(folder) -> dict | None:
    """The answer's warm-touch table of an optimization folder ({caption, cols, rows, note}):
    one row, the design the record is of; None without a record."""
    rec = record(folder)
    if rec is None:
        return None
    mdf, ratio = rec["min_detectable_force_N"], rec["ratio"]
    row = [f"thesis ({rec['scene']})", f"{rec['finger_K'] - 273.15:.0f} °C held {rec['duration_s']:g} s",
           f"{rec['film_rise_K']:.2g} K", eng(rec["false_force_N"], "N", 3), "—" if mdf is None else eng(mdf, "N", 3),
           "—" if ratio is None else f"{ratio:.3g}"]
    verdict = ("" if ratio is None else " It fakes a press the readout can see." if ratio > 1 else
               " It stays below what the readout can see.")
    return {"caption": "a warm finger on the skin: the false press at the readout", "cols": ANSWER_COLS, "rows": [row],
            "note": (f"A warm touch alone (no force), through the {rec['readout']}, {_model(rec)} model; the false "
                     f"force is the press that gives the same peak output.{verdict} Sensitivity drift from 0 to "
                     f"50 °C: {drift_text(rec)}. The temperature field and the traces: this folder's page, Warm touch.")}
