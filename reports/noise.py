"""The noise-budget page: a noise result folder (taxel.analyses.solves.noise, result.json of
kind "noise") drawn as the PSD of each source at the readout output, stacked, and
the share of each source in the band's variance. Reads the folder; never solves."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from taxel.analyses import read
from taxel.reports.tables import eng

FIGURE = "noise-budget.png"


def figure(folder, path: Path | None = None) -> Path:
    """FOLDER/noise-budget.png (or `path`): the stacked PSD per source (left) and each
    source's share (right)."""
    from taxel.reports.figures import pyplot
    plt = pyplot()
    folder = Path(folder)
    res = read(folder)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4.6), gridspec_kw={"width_ratios": [2.2, 1]},
                                 layout="constrained")
    order = sorted(res.psd, key=lambda k: -res.variance()[k])
    base = np.zeros_like(res.freqs)
    for k in reversed(order):
        top = base + res.psd[k]
        ax.fill_between(res.freqs, np.sqrt(base), np.sqrt(top), label=k, alpha=0.8, linewidth=0)
        base = top
    for f, p in res.lines:
        ax.axvline(f, color="k", lw=0.8, ls=":")
    ax.set(xscale="log", yscale="log", xlabel="frequency (Hz)", ylabel="noise density at the readout (V/sqrt(Hz))",
           title=f"{res.electrode}: {eng(res.noise_rms, 'V')} rms in "
                 f"{res.band[0]:g}-{res.band[1]:g} Hz")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=4, frameon=False)
    sh = res.shares()
    names = sorted(sh, key=lambda k: sh[k])
    bx.barh(names, [100 * sh[k] for k in names], color="tab:blue")
    bx.set(xscale="log", xlabel="share of the band's variance (%, log)",
           title=f"min. detectable force {eng(res.min_detectable_force, 'N')}")
    bx.tick_params(axis="y", labelsize=7)
    path = path or folder / FIGURE
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def is_noise(folder: Path) -> bool:
    from taxel.analyses.results import ResultError, result_kind
    try:
        return result_kind(folder) == "noise"
    except ResultError:
        return False


def page(folder: Path, out: Path, scene_data) -> dict:
    """The page's sections, headline numbers and thumbnail (reports.build's PAGE_KINDS)."""
    from taxel.reports.scene_sections import data_uri
    res = read(folder)
    import tempfile
    with tempfile.TemporaryDirectory(prefix="taxel-report-") as tmp:   # redrawn from the stored result
        png_bytes = figure(folder, Path(tmp) / FIGURE).read_bytes()
    o = res.outputs()
    from taxel.reports.captions import caption
    from taxel.reports.findings import model_label
    from taxel.reports.page import Headline
    model = f"{model_label(res.scene)}, {res.label}, {res.band[0]:g}-{res.band[1]:g} Hz"
    numbers = [Headline("minimum detectable force", eng(o["min_detectable_force"], "N"), model),
               Headline("noise at the readout (rms)", eng(o["noise_rms"], "V"), model),
               Headline("dynamic range", f"{o['dynamic_range']:.1f} dB", model)]
    blocks = [{"type": "pre", "text": "\n".join(res.summary())}, {"type": "note", "text": f"Model: {model}."}]
    blocks.append({"type": "figures", "images": [{"src": data_uri(png_bytes), "caption": caption(Path(FIGURE))}]})
    return {"sections": [{"title": "Noise budget", "blocks": blocks}], "numbers": numbers, "banners": [],
            "scene_banners": False, "thumb": png_bytes}
