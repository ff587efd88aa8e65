"""The coverage map of a design (its 3D surface map, taxel.analyses.surface.map_metrics): a figure
of the top surface with the best taxel's margin over the detection threshold, the dead
zones (margin < 1) shaded, the taxels outlined and the 3D minimum marked; and the
section's text: the definition (force, threshold, noise, footprint), the 3D minimum,
the localization error (rms, 95th percentile, worst case).

    figure(m, cov, path)              # PNG
    draw_folder(folder)               # every design's map into the folder (coverage-map-*.png)

The figure is drawn from the map file OUT/maps/<key>.npz the row names, so the report
needs no solve.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from taxel.analyses.results.figures import pyplot


def figure(m, cov, path, title: str = "") -> Path:
    """The coverage map `cov` (map_metrics.MapCoverage) of surface map `m`, to `path` (PNG)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.2, 4.4))
    X, Y = 1e3 * cov.x, 1e3 * cov.y
    from matplotlib.colors import LogNorm
    lo, hi = min(0.5, float(cov.margin.min())), max(2.0, float(cov.margin.max()))
    im = ax.pcolormesh(X, Y, cov.margin, shading="auto", cmap="viridis", norm=LogNorm(lo, hi))
    fig.colorbar(im, ax=ax, label="best taxel |V| over the threshold (ratio, log scale)")
    ax.contour(X, Y, cov.margin, levels=[2.0], colors="orange", linewidths=0.6, linestyles="dashed")
    if cov.dead.any():
        ax.contourf(X, Y, cov.dead.astype(float), levels=[0.5, 1.5], colors="none", hatches=["////"])
        ax.contour(X, Y, cov.margin, levels=[1.0], colors="red", linewidths=1.2)
    half = 1e3 * m.info.get("taxel_width", 0) / 2
    for (cx, cy) in (1e3 * np.asarray(m.centres) if m.centres is not None else []):
        if half > 0:
            ax.add_patch(plt.Rectangle((cx - half, cy - half), 2 * half, 2 * half, fill=False, ec="white", lw=0.8))
        ax.plot(cx, cy, "+", color="white", ms=5)
    mx, my = 1e3 * np.asarray(cov.minimum_at)
    ax.plot(mx, my, "o", mfc="none", mec="red", ms=9)
    ax.annotate(f"3D minimum {cov.minimum:.3g}x", (mx, my), textcoords="offset points", xytext=(6, 6),
                color="red", fontsize=8)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_aspect("equal")
    ax.set_title(title or f"coverage {100 * cov.fraction:.1f} % at {cov.force_N:g} N", fontsize=7, wrap=True)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


DEFINITION = ("Coverage: the fraction of the surface between the outer taxels' centres where a press of "
              "{force:g} N over the probe's footprint ({fp}) gives the best taxel an open-circuit voltage of at "
              "least k = {k:g} times the noise (sigma = {noise}, {source}); from the design's 3D surface map "
              "(linear silicone, every taxel open). Hatched: dead zones. The 3D minimum: the smallest best-taxel "
              "margin over that surface, searched.")


def definition(row: dict) -> str:
    fp = row.get("footprint") or {}
    r = fp.get("radius_m", 0.0)
    foot = f"a {fp.get('profile', 'flat')} disc of radius {1e3 * r:g} mm" if r else "a point force"
    return DEFINITION.format(force=row.get("force_N", 0.0), fp=foot, k=row.get("sigmas", 3.0),
                             noise=f"{1e3 * row.get('noise_V', 0.0):.3g} mV",
                             source=row.get("noise_source", "noise on each open-circuit peak"))


def row_text(row: dict) -> str:
    """One design's numbers, one line."""
    if row.get("error"):
        return f"not checked: {row['error']}"
    parts = [f"coverage {100 * row['coverage']:.1f} %"] if row.get("coverage") is not None else []
    if row.get("coverage_minimum") is not None:
        at = row.get("coverage_minimum_at_mm") or [0, 0]
        parts.append(f"3D minimum {row['coverage_minimum']:.3g}x the threshold at ({at[0]:.2f}, {at[1]:.2f}) mm")
    if row.get("localization_error") is not None:
        parts.append(f"localization error rms {1e3 * row['localization_error']:.3g} mm, 95th percentile "
                     f"{1e3 * row.get('localization_error_p95', np.nan):.3g} mm, worst "
                     f"{1e3 * row.get('localization_error_worst', np.nan):.3g} mm")
    return "; ".join(parts)


def draw_rows(folder: Path, rows: list[dict], scratch: Path | None = None) -> list[tuple[dict, Path | None]]:
    """Each row of OUT/coverage.json with its figure (drawn into `scratch`, default next to
    its map file; None when the row has no map)."""
    from taxel.analyses.surface import map_metrics
    from taxel.analyses.surface.surface_map import Footprint, SurfaceMap
    out = []
    for row in rows:
        path = None
        if row.get("map") and (Path(folder) / row["map"]).exists():
            m = SurfaceMap.from_file(Path(folder) / row["map"])
            fp = row.get("footprint") or {}
            cov = map_metrics.coverage(m, row["force_N"], row["noise_V"],
                                       Footprint(fp.get("radius_m", 0.0), fp.get("profile", "flat")),
                                       row.get("sigmas", map_metrics.SIGMAS))
            png = Path(row["map"]).with_suffix(".png").name
            path = figure(m, cov, (Path(scratch) / png) if scratch is not None else
                          (Path(folder) / row["map"]).with_suffix(".png"), f"{_name(row)}\n{row_text(row)}")
        out.append((row, path))
    return out


def draw_folder(folder: Path) -> list[Path]:
    """The coverage map of every design of OUT/coverage.json with a map, drawn into the
    folder as coverage-map-<design>.png (the optimization page embeds a folder's figures);
    nothing when the run judged no design's coverage."""
    out = []
    for row, path in draw_rows(folder, record_rows(folder), Path(folder)):
        if path is not None:
            named = Path(folder) / ("coverage-map-" + "-".join(f"{k}-{v:g}mm" for k, v in row.get("x_mm", {}).items())
                                    + ".png")
            out.append(path.replace(named))
    return out


def record_rows(folder: Path) -> list[dict]:
    """The rows of OUT/coverage.json (optimize.coverage.RECORD), read here: reports read files."""
    import json
    from taxel.optimize.coverage import RECORD
    path = Path(folder) / RECORD
    return json.loads(path.read_text())["designs"] if path.exists() else []


CAPTION = ("Coverage map on the design's 3D surface map: the best taxel's open-circuit voltage over the detection "
           "threshold for a press of the smallest force of interest over the probe's footprint (k = 3 times the "
           "noise), between the outer taxels' centres; hatched where it is below (dead zones), red the threshold's "
           "contour, dashed twice the threshold, the circle the searched 3D minimum; the title gives the coverage, the 3D minimum and the "
           "localization error's rms, 95th percentile and worst case.")


def _name(row: dict) -> str:
    return ", ".join(f"{k} {v:g} mm" for k, v in row.get("x_mm", {}).items())


def _mm(v):
    return None if v is None else 1e3 * v
