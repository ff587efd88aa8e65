"""Figures of the report pages (matplotlib on the Agg backend, no screen needed):
a study's output against its parameters, a scene's cross-section to scale, a Yeoh fit.
The figures of one result (Bode, transient, the solved fields, ...) are the result
folder's own (taxel.analyses.results.figures and .fields); `pyplot()` is theirs.
"""

from __future__ import annotations

import numpy as np

from taxel.analyses import layout, scene_materials
from taxel.analyses.results.figures import pyplot
from taxel.fem.constitution import stability_limit
from taxel.units import magnitude


# outputs of a study: (axis label, scale from SI, absolute value?)
_OUTPUT_AXES = {"pressed_voltage": ("pressed taxel |V|", "V"), "sensitivity": ("pressed taxel |V| per newton", "V/N"),
                "max_strain": ("largest silicone strain", "%"), "crosstalk": ("crosstalk", "%")}
_PREFIX = [(1.0, ""), (1e-3, "m"), (1e-6, "µ"), (1e-9, "n"), (1e-12, "p")]


def _axis(out, values):
    """(label with unit, scale) for an output: volts and coulombs with the SI prefix
    that suits the largest value, strains and ratios in %."""
    label, unit = _OUTPUT_AXES.get(out, (out.replace("_", " "), "C" if out.startswith(("charge", "short_circuit_charge")) else "V"))
    if unit == "%":
        return f"{label} (%)", 100.0
    big = max([abs(v) for v in values if np.isfinite(v)] or [1.0])
    scale, prefix = next(((s, p) for s, p in _PREFIX if big >= s), _PREFIX[-1])
    return f"{label} ({prefix}{unit})", 1 / scale


def _param_value(v):
    """(number, unit) of a parameter value such as "0.5 mm"; (SI number, "SI") for a bare
    number; None when it is not a number."""
    if isinstance(v, str):
        parts = v.split(maxsplit=1)
        try:
            return float(parts[0]), (parts[1] if len(parts) > 1 else "-")
        except ValueError:
            return None
    m = magnitude(v)
    return (m, "SI") if isinstance(m, float) else None


def study_plots(rows, parameters, outputs, folder, title=""):
    """Each output against each numeric parameter, as small multiples: one panel per
    value of the categorical parameters (material, model), each with its own y
    range; one line per value of the other numeric parameters, in one colour per
    value on every plot of the study; the legend outside the panels. Axis labels
    carry the unit. Returns the files written."""
    plt = pyplot()
    folder.mkdir(parents=True, exist_ok=True)
    done = [r for r in rows if r["status"] == "done"]
    numeric = [p for p in parameters if done and all(_param_value(r.get(p)) is not None for r in done)]
    facets = [p for p in parameters if p not in numeric]
    panels = list(dict.fromkeys(tuple(str(r.get(q)) for q in facets) for r in done)) or [()]
    files = []
    for p in numeric:
        unit = _param_value(done[0][p])[1]
        others = [q for q in numeric if q != p]
        keys = sorted({tuple(_param_value(r[q])[0] for q in others) for r in done})
        colour = {k: f"C{i % 10}" for i, k in enumerate(keys)}
        for out in outputs:
            if not any(isinstance(r.get(out), (int, float)) for r in done):
                continue
            ylabel, yscale = _axis(out, [abs(r[out]) for r in done if isinstance(r.get(out), (int, float))])
            fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels) + 1.8, 3.8), squeeze=False,
                                     layout="constrained")
            for ax, panel in zip(axes[0], panels):
                sub = [r for r in done if tuple(str(r.get(q)) for q in facets) == panel]
                for k in keys:
                    grp = sorted((r for r in sub if tuple(_param_value(r[q])[0] for q in others) == k),
                                 key=lambda r: _param_value(r[p])[0])
                    ys = [abs(r[out]) * yscale if isinstance(r.get(out), (int, float)) else np.nan for r in grp]
                    label = ", ".join(f"{q.replace('_', ' ')} {v:g} {_param_value(done[0][q])[1]}"
                                      for q, v in zip(others, k)) or None
                    ax.plot([_param_value(r[p])[0] for r in grp], ys, "o-", ms=3, color=colour[k], label=label)
                if out == "max_strain":       # the linear silicone's range (2 % voltage error), drawn
                    from taxel.analyses import LINEAR_ERROR_PER_STRAIN
                    lim = 100 * 0.02 / LINEAR_ERROR_PER_STRAIN
                    ax.axhline(lim, color="tab:red", lw=0.9, ls="--")
                    ax.axhspan(lim, ax.get_ylim()[1], color="tab:red", alpha=0.06)
                    ax.annotate(f"linear silicone valid below {lim:.2g} %", (0.02, lim), xycoords=("axes fraction",
                                "data"), xytext=(0, 3), textcoords="offset points", fontsize=7, color="tab:red")
                ax.set_title(", ".join(f"{q}: {v}" for q, v in zip(facets, panel)) or title, fontsize=10)
                ax.set_xlabel(f"{p.replace('_', ' ')} ({unit})")
                ax.set_ylabel(ylabel)
                ax.grid(True, alpha=0.3)
            if len(keys) > 1:
                handles, labels = axes[0][0].get_legend_handles_labels()
                fig.legend(handles, labels, loc="outside right upper", fontsize=8, frameon=False)
            if facets and title:
                fig.suptitle(title, fontsize=10)
            path = folder / f"{out}-vs-{p}.png"
            fig.savefig(path, dpi=110)
            plt.close(fig)
            files.append(path)
    return files


def scene_layout(scene):
    return layout(scene, scene_materials(scene))


def _indenter(ax, load, x: float, top: float) -> None:
    """The rigid probe of a contact load at x (mm) on the surface `top` (mm): a sphere or a
    cylinder as a circle, a flat punch as a block with rounded edges, to scale."""
    from matplotlib.patches import Circle, FancyBboxPatch
    r = load.radius * 1e3
    style = dict(fc="0.75", ec="crimson", lw=1.0)
    if load.shape in ("sphere", "cylinder"):
        ax.add_patch(Circle((x, top + r), r, **style))
    else:
        e = (load.edge_radius or load.radius / 20) * 1e3
        ax.add_patch(FancyBboxPatch((x - r + e, top + e), 2 * (r - e), 2 * r - 2 * e,
                                    boxstyle=f"round,pad={e:g}", **style))


def scene_drawing(scene):
    """The scene's cross-section to scale (x-z, mm): layers, taxels, load footprint,
    with dimensions and materials. Returns a matplotlib figure."""
    plt = pyplot()
    from matplotlib.patches import Rectangle

    lay = scene_layout(scene)
    x0, x1 = lay.x_range
    fig, ax = plt.subplots(figsize=(9, 3.2), constrained_layout=True)
    colours = {}
    palette = ["#cfe3f3", "#f6c89f", "#c7e9c0", "#e5c6e8", "#f2e394"]
    for L in lay.layers:
        c = colours.setdefault(L.material, palette[len(colours) % len(palette)])
        ax.add_patch(Rectangle((x0 * 1e3, L.z0 * 1e3), (x1 - x0) * 1e3, L.thickness * 1e3, fc=c, ec="0.4", lw=0.6))
        for p in L.patches:
            cp = colours.setdefault(L.patch_material, palette[len(colours) % len(palette)])
            ax.add_patch(Rectangle(((p.x - p.half) * 1e3, L.z0 * 1e3), 2 * p.half * 1e3, L.thickness * 1e3,
                                   fc=cp, ec="k", lw=0.8))
    H = lay.height * 1e3
    if lay.load is not None:
        a, b = (lay.load.x - lay.load.half) * 1e3, (lay.load.x + lay.load.half) * 1e3
    else:
        a, b = x0 * 1e3, x1 * 1e3
    load = scene.load
    what = f"{load.force:g} N" if load.kind != "pressure" else f"{load.pressure:g} Pa"
    if load.contact and load.radius:            # a rigid indenter: drawn as the probe it is, resting on the top
        _indenter(ax, load, (a + b) / 2, H)
        what = f"{load.shape} probe, radius {load.radius * 1e3:.3g} mm, " + (
            f"{load.force:g} N" if load.travel is None else f"travel {load.travel * 1e3:.3g} mm")
        ax.text((a + b) / 2 + load.radius * 1e3 + 0.3, H + load.radius * 1e3, what, ha="left", va="center",
                color="crimson", fontsize=8)
    else:
        for xa in np.linspace(a, b, 7):
            ax.annotate("", (xa, H), (xa, H + 0.6), arrowprops=dict(arrowstyle="->", color="crimson"))
        ax.text((a + b) / 2, H + 0.7, f"{load.kind}: {what}", ha="center", color="crimson", fontsize=8)
    for L in lay.layers:
        ax.text(x1 * 1e3 + 0.3, (L.z0 + L.thickness / 2) * 1e3, f"{L.thickness * 1e3:.3g} mm", va="center", fontsize=7)
    if lay.taxels:
        p = lay.taxels[0]
        ax.annotate("", ((p.x - p.half) * 1e3, -0.35), ((p.x + p.half) * 1e3, -0.35),
                    arrowprops=dict(arrowstyle="<->", lw=0.7))
        ax.text(p.x * 1e3, -0.75, f"{2 * p.half * 1e3:.2f} mm", ha="center", fontsize=7)
        if len(lay.taxels) > 1:
            q = lay.taxels[1]
            ax.annotate("", ((p.x + p.half) * 1e3, -0.35), ((q.x - q.half) * 1e3, -0.35),
                        arrowprops=dict(arrowstyle="<->", lw=0.7, color="0.3"))
            ax.text((p.x + p.half + q.x - q.half) / 2 * 1e3, -0.75, f"gap {(q.x - q.half - p.x - p.half) * 1e3:.2f} mm",
                    ha="center", fontsize=7)
    handles = [Rectangle((0, 0), 1, 1, fc=c, ec="0.4") for c in colours.values()]
    ax.legend(handles, list(colours), loc="upper right", fontsize=7, ncol=len(colours))
    ax.set_xlim(x0 * 1e3 - 0.5, x1 * 1e3 + 2.5)
    ax.set_ylim(-1.2, H + (2.2 * load.radius * 1e3 + 0.8 if load.contact and load.radius else 1.6))
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)" if lay.model != "axisymmetric" else "r (mm)")
    ax.set_ylabel("z (mm)")
    ax.set_title(f"{scene.name}: {lay.model.replace('_', ' ')}"
                 + (f", depth {lay.depth * 1e3:g} mm" if lay.model.startswith("plane") else ""), fontsize=9)
    return fig


def yeoh_fit(strain, stress, fit, out, check_strain: float | None = None, title: str = ""):
    """PNG of the data, the fit over its range (solid) and beyond it (dashed).

    The fit range 0 < strain <= fit_strain is shaded; the plot extends to
    max(3 fit_strain, check_strain); where the uniaxial fit loses stability within
    it, a marker shows the point.
    """
    plt = pyplot()

    strain, stress = np.asarray(strain, float), np.asarray(stress, float)
    x_hi = max(3.0 * fit.fit_strain, check_strain or 0.0)
    show = (strain >= 0) & (strain <= x_hi)
    order = np.argsort(strain[show])
    xs, ys = strain[show][order], stress[show][order]

    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    ax.axvspan(0, 100 * fit.fit_strain, color="0.9", label=f"fit range (<= {100 * fit.fit_strain:g} %)")
    ax.plot(100 * xs, ys / 1e3, ".", ms=4, color="k", label="test data")
    x_in = np.linspace(0, fit.fit_strain, 200)
    x_out = np.linspace(fit.fit_strain, x_hi, 400)
    lbl = (f"Yeoh: C10 {fit.C10 / 1e3:.3g}, C20 {fit.C20 / 1e3:.3g}, C30 {fit.C30 / 1e3:.3g} kPa"
           f" (R² {fit.r2:.4f})")
    ax.plot(100 * x_in, fit.stress(x_in) / 1e3, "-", color="C0", lw=2, label=lbl)
    ax.plot(100 * x_out, fit.stress(x_out) / 1e3, "--", color="C0", lw=1.5, label="fit, extrapolated")
    lost = stability_limit(fit, (0.5, 1.0 + x_hi))["uniaxial"]["tension"]
    if lost is not None:
        ax.plot(100 * (lost - 1), fit.stress(lost - 1) / 1e3, "x", color="C3", ms=10, mew=2,
                label=f"uniaxial stability lost ({100 * (lost - 1):.0f} %)")
    y_data = ys.max() if len(ys) else float(fit.stress(x_hi))
    ax.set_ylim(min(0.0, ys.min() / 1e3 if len(ys) else 0.0) - 0.05 * y_data / 1e3, 1.3 * y_data / 1e3)
    ax.set_xlim(0, 100 * x_hi)
    ax.set_xlabel("engineering strain (%)")
    ax.set_ylabel("nominal stress (kPa)")
    if title:
        ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
