"""Figures of a solution (matplotlib, no screen needed).

`python -m reports.figures SCENE OUT.png` draws the deformed cross-section of a
2D or axisymmetric scene coloured by electric potential, and the vertical
displacement; the README's picture is made this way.
"""

from __future__ import annotations

import sys

import numpy as np


def cross_section(sol, path, exaggerate=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    mesh = sol.mesh.mesh
    if mesh.dim() != 2:
        raise ValueError("cross_section draws 2D and axisymmetric scenes")
    p, u = mesh.p * 1e3, sol.fields["u"] * 1e3                       # mm
    scale = exaggerate or max(1.0, round(0.1 * np.ptp(p[1]) / max(np.abs(u).max(), 1e-30)))
    deformed = p + scale * u.T
    fig, axes = plt.subplots(2, 1, figsize=(9, 6), constrained_layout=True)
    piezo = np.zeros(mesh.nelements, bool)
    for region in sol.mesh.materials:
        if region != "silicone":
            piezo[sol.mesh.regions[region]] = True
    ax = axes[0]
    ax.tripcolor(Triangulation(*deformed, mesh.t[:, ~piezo].T), np.zeros((~piezo).sum()),
                 cmap="Greys", vmin=-1, vmax=4, edgecolors="0.75", linewidth=0.1)
    pc = ax.tripcolor(Triangulation(*deformed, mesh.t[:, piezo].T), sol.fields["phi"],
                      shading="gouraud", cmap="coolwarm")
    fig.colorbar(pc, ax=ax, label="electric potential (V)")
    ax.set_xlim(p[0].min() / 2, p[0].max() / 2)
    ax.set_title(f"{sol.scene.name}: potential in the piezo (silicone grey), deformation x{scale:g}")
    ax = axes[1]
    pc = ax.tripcolor(Triangulation(*p, mesh.t.T), u[:, 1] * 1e3, shading="gouraud", cmap="viridis")
    fig.colorbar(pc, ax=ax, label="vertical displacement (um)")
    volts = ", ".join(f"{k}: {e.voltage * 1e3:.0f} mV" for k, e in sol.electrodes.items() if e.state != "reference")
    ax.set_title(f"{sol.applied_force:g} N on the taxel; open-circuit {volts}")
    axes[1].set_aspect("equal")
    for a in axes:
        a.set_xlabel("x (mm)")
        a.set_ylabel("z (mm)")
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main(argv=None):
    from fem.solve import solve
    from studies.scene import load
    scene, out = (argv or sys.argv[1:])[:2]
    cross_section(solve(load(scene)), out)
    print(out)


if __name__ == "__main__":
    main()


def bode(freqs, H, names, label, path, title=""):
    """Magnitude and phase of H (nf, na) against frequency."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, constrained_layout=True)
    for k, name in enumerate(names):
        a1.loglog(freqs, np.abs(H[:, k]), label=name)
        a2.semilogx(freqs, np.degrees(np.angle(H[:, k])), label=name)
    a1.set_ylabel(f"|{label}| (V/N)")
    a2.set_ylabel("phase (deg)")
    a2.set_xlabel("frequency (Hz)")
    a1.set_title(title)
    a1.legend(fontsize=8)
    for a in (a1, a2):
        a.grid(True, which="both", alpha=0.3)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def time_response(t, force, y, names, label, path, title=""):
    """Force and output voltages over time."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True, constrained_layout=True)
    a1.plot(t, force, color="k")
    a1.set_ylabel("force (N)")
    a1.set_title(title)
    for k, name in enumerate(names):
        a2.plot(t, y[:, k], label=name)
    a2.set_ylabel(f"{label} (V)")
    a2.set_xlabel("time (s)")
    a2.legend(fontsize=8)
    for a in (a1, a2):
        a.grid(True, alpha=0.3)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def study_plots(rows, parameters, outputs, folder, title=""):
    """Each output against each numeric varied parameter; one line per combination
    of the other parameters (labels in the legend). Returns the files written."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from studies.study import magnitude
    folder.mkdir(parents=True, exist_ok=True)
    done = [r for r in rows if r["status"] == "done"]
    files = []
    for p in parameters:
        xs = [magnitude(r.get(p)) for r in done]
        if not xs or not all(isinstance(x, float) for x in xs):
            continue
        others = [q for q in parameters if q != p]
        for out in outputs:
            if not any(out in r for r in done):
                continue
            fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
            groups = {}
            for r in done:
                groups.setdefault(tuple(str(r.get(q)) for q in others), []).append(r)
            for key, grp in sorted(groups.items()):
                grp = sorted(grp, key=lambda r: magnitude(r[p]))
                ys = [abs(r[out]) if isinstance(r.get(out), (int, float)) else np.nan for r in grp]
                ax.plot([magnitude(r[p]) for r in grp], ys, "o-", ms=3,
                        label=", ".join(f"{q}={v}" for q, v in zip(others, key)) or None)
            ax.set_xlabel(f"{p} (SI)")
            ax.set_ylabel(f"|{out}|")
            ax.set_title(title)
            if len(groups) > 1:
                ax.legend(fontsize=6, ncol=2)
            ax.grid(True, alpha=0.3)
            path = folder / f"{out}-vs-{p}.png"
            fig.savefig(path, dpi=110)
            plt.close(fig)
            files.append(path)
    return files
