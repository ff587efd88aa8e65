"""The thesis's own model beside linear silicone, for a thesis-model study
(studies/builtin/fig-2-5-thesis.toml, fig-2-8-thesis.toml: plane stress, Yeoh silicone,
homogeneous pressure, every point also solved with linear silicone).

A Yeoh point whose Newton stops short of its force is its last converged state (its
force the row's stopped_at, N; studies.evaluate); its outputs are at that force. The
figure draws it with a cross at its value there, the table counts such points and gives
the range of their last converged force. Per point, the Yeoh output against the linear
one of the same point: the sensitivity |V|/F is compared as is (linear: V is
proportional to F, so its V/N holds at the reached force too), as is the crosstalk.
"""

from __future__ import annotations

import statistics
from pathlib import Path

from taxel.reports.figures import pyplot
from taxel.reports.findings import finite_number

YEOH = "Yeoh (thesis)"
LINEAR = "linear"
FIXED = ("piezo", "force", "silicone")


def is_thesis_model(rows: list[dict]) -> bool:
    """Rows of a study that varies the silicone law between linear and the thesis's Yeoh."""
    laws = {r.get("silicone") for r in rows}
    return YEOH in laws and LINEAR in laws


def _num(v) -> float:
    """A parameter's value in its own unit ("0.5 mm" -> 0.5; 0.2 -> 0.2)."""
    return float(str(v).split()[0])


def swept(rows: list[dict]) -> str:
    """The geometric parameter the study sweeps (silicone_thickness for Fig. 2.5, gap for 2.8)."""
    params = [k for k in rows[0] if k != "status" and not k.startswith(("voltage_", "short_circuit_charge_"))]
    return next(k for k in params if k not in FIXED and k not in ("pressed_voltage", "sensitivity", "crosstalk",
                                                                   "max_strain", "seconds", "error", "stopped_at"))


def output(rows: list[dict]) -> str:
    """What the figure shows: crosstalk for a gap sweep (Fig. 2.8/2.9), else sensitivity (2.5/2.6)."""
    return "crosstalk" if swept(rows) == "gap" and any(finite_number(r.get("crosstalk")) is not None for r in rows) else "sensitivity"


def _stopped(r: dict) -> float | None:
    return finite_number(r.get("stopped_at"))


def _value(r: dict, out: str) -> float | None:
    v = finite_number(r.get(out))
    if v is None or r.get("status") != "done":
        return None
    return 100 * abs(v) if out == "crosstalk" else abs(v)


def draw(rows: list[dict], out: Path, name: str) -> Path:
    """OUT/NAME-thesis-model.png: the `figure` of the rows."""
    fig = figure(rows, name)
    path = Path(out) / f"{name}-thesis-model.png"
    fig.savefig(path, dpi=110)
    pyplot().close(fig)
    return path


def figure(rows: list[dict], name: str):
    """Per piezo (one axes each), the output over the swept parameter: linear silicone
    (dashed, force-independent) beside Yeoh at each force (solid); crosses: Yeoh points
    stopped short, at their last converged force."""
    plt = pyplot()
    x_name, what = swept(rows), output(rows)
    piezos = list(dict.fromkeys(r["piezo"] for r in rows))
    forces = sorted({_num(r["force"]) for r in rows})
    fig, axes = plt.subplots(1, len(piezos), figsize=(5.2 * len(piezos), 3.9), constrained_layout=True, squeeze=False)
    colors = plt.get_cmap("viridis")
    for ax, pz in zip(axes[0], piezos):
        for law, style in ((LINEAR, "--"), (YEOH, "-")):
            for i, f in enumerate(forces if law == YEOH else forces[:1]):
                pts = sorted((_num(r[x_name]), _value(r, what), _stopped(r) or 0.0) for r in rows
                             if r["piezo"] == pz and r["silicone"] == law and _num(r["force"]) == f
                             and _value(r, what) is not None)
                c = "k" if law == LINEAR else colors(i / max(len(forces) - 1, 1))
                ok = [(x, y) for x, y, s in pts if not s]
                if ok:
                    ax.plot(*zip(*ok), style + "o", color=c, ms=3.5,
                            label="linear (every force)" if law == LINEAR else f"Yeoh {f:g} N")
                stop = [(x, y) for x, y, s in pts if s]
                if stop:
                    ax.plot(*zip(*stop), "x", color=c, ms=7, mew=1.5)
        ax.plot([], [], "x", color="0.3", label="Yeoh stopped short: at its last converged force")
        ax.set_title(f"{pz}", fontsize=10)
        ax.set_xlabel(f"{x_name.replace('_', ' ')} ({str(rows[0][x_name]).split()[1] if ' ' in str(rows[0][x_name]) else ''})")
        ax.set_ylabel("crosstalk (%)" if what == "crosstalk" else "sensitivity |V|/F (V/N)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"{name}: the thesis's model (plane stress, Yeoh) beside linear silicone", fontsize=10)
    return fig


def comparison(rows: list[dict]) -> list[dict]:
    """Per piezo and force: Yeoh points solved, stopped short (their last converged
    forces), and Yeoh / linear - 1 of the figure's output over the points of both."""
    x_name, what = swept(rows), output(rows)
    lin = {(r["piezo"], r["force"], r[x_name]): _value(r, what) for r in rows if r["silicone"] == LINEAR}
    out = []
    for pz in dict.fromkeys(r["piezo"] for r in rows):
        for f in sorted({r["force"] for r in rows}, key=_num):
            ys = [r for r in rows if r["piezo"] == pz and r["force"] == f and r["silicone"] == YEOH]
            done = [r for r in ys if r.get("status") == "done"]
            stop = [_stopped(r) for r in done if _stopped(r)]
            d = [_value(r, what) / lin[k] - 1 for r in done
                 if (lin.get(k := (pz, f, r[x_name])) or 0) > 0 and _value(r, what) is not None]
            out.append({"piezo": pz, "force": f, "Yeoh points": len(ys), "solved to the force": len(done) - len(stop),
                        "stopped short": len(stop),
                        "last converged force (N)": f"{min(stop):.3g}-{max(stop):.3g}" if stop else "",
                        f"Yeoh / linear - 1 of {what}, median (%)": f"{100 * statistics.median(d):+.1f}" if d else "",
                        "range (%)": f"{100 * min(d):+.1f} to {100 * max(d):+.1f}" if d else ""})
    return out


def sentence(rows: list[dict]) -> str:
    ys = [r for r in rows if r["silicone"] == YEOH]
    done = [r for r in ys if r.get("status") == "done"]
    stop = [_stopped(r) for r in done if _stopped(r)]
    lin = [r for r in rows if r["silicone"] == LINEAR]
    return (f"The thesis's model (plane stress, Yeoh silicone, homogeneous pressure) beside linear silicone on the "
            f"same points: {len(done)} Yeoh points with a result, {len(done) - len(stop)} of them at their force "
            f"({len(ys)} Yeoh and {len(lin)} linear points in the folder)"
            + (f"; {len(stop)} stopped short of their force (the silicone creases at the pressure patch's edge), "
               f"last converged at {min(stop):.3g}-{max(stop):.3g} N, shown at that force (crosses)" if stop else "")
            + ". Each Yeoh value is compared with the linear one of the same point.")
