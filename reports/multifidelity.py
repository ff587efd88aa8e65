"""The 3D-verified front's figure, pareto-3d.png: the cheap (2D) front, every design
verified in 3D, the 3D front and the thesis design in 2D and 3D. Its numbers
(front-3d.json) are written by the result itself (MultiFidelity.to_folder)."""

from __future__ import annotations

from pathlib import Path

from taxel.optimize.metrics import METRIC_TABLE, axis_label
from taxel.optimize.multifidelity import MultiFidelity
from taxel.reports.figures import pyplot


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
