"""The layer stack of an answer's designs drawn to scale: a section through two
neighbouring taxels (silicone above, the piezo, silicone below; the gap between the
taxels), the recommended design above the reference design, every dimension written."""

from __future__ import annotations

from taxel.reports.scene_sections import data_uri, figure_png

SILICONE, PIEZO = "#c9dff2", "#d9822b"


def _draw(ax, d, y0: float, label: str, material: str, width: float) -> None:
    """One design's section at height y0 (mm), lengths from an AnswerDesign."""
    from matplotlib.patches import Rectangle
    piezo = 1e3 * d.values["total_thickness"] - d.silicone_above_mm - d.silicone_below_mm
    total = 2 * width + d.gap_mm + 2.0
    y = y0
    ax.add_patch(Rectangle((0, y), total, d.silicone_below_mm, color=SILICONE))
    y += d.silicone_below_mm
    for x in (1.0, 1.0 + width + d.gap_mm):
        ax.add_patch(Rectangle((x, y), width, piezo, color=PIEZO))
    ax.add_patch(Rectangle((1.0 + width, y), d.gap_mm, piezo, color=SILICONE))
    ax.add_patch(Rectangle((0, y), 1.0, piezo, color=SILICONE))
    ax.add_patch(Rectangle((1.0 + 2 * width + d.gap_mm, y), 1.0, piezo, color=SILICONE))
    y += piezo
    ax.add_patch(Rectangle((0, y), total, d.silicone_above_mm, color=SILICONE))
    top = y + d.silicone_above_mm
    ax.text(total + 0.3, y0 + d.silicone_below_mm / 2, f"silicone below {d.silicone_below_mm:.2f} mm", va="center",
            fontsize=8)
    ax.text(total + 0.3, y0 + d.silicone_below_mm + piezo / 2, f"{material} {1e3 * piezo:.3g} µm", va="center",
            fontsize=8)
    ax.text(total + 0.3, y + d.silicone_above_mm / 2, f"silicone above {d.silicone_above_mm:.2f} mm", va="center",
            fontsize=8)
    ax.annotate("", (1.0 + width, y0 - 0.25), (1.0 + width + d.gap_mm, y0 - 0.25),
                arrowprops={"arrowstyle": "<->", "lw": 0.8})
    ax.text(1.0 + width + d.gap_mm / 2, y0 - 0.35, f"gap {d.gap_mm:.2f} mm · pitch {d.pitch_mm:.2f} mm",
            ha="center", va="top", fontsize=8)
    ax.text(0, top + 0.15, f"{label}: total {1e3 * d.values['total_thickness']:.3g} mm, taxel {width:.2f} mm",
            fontsize=8.5, weight="bold")


def figure(answer, material: str) -> str | None:
    """The stack of the recommended and the reference design of `answer`
    (reports.answer.FrontAnswer) as a PNG data URI; None without their geometry."""
    from taxel.reports.figures import pyplot
    designs = [(d, n) for d, n in ((answer.recommended, "recommended"), (answer.thesis, answer.reference_name))
               if d is not None and "total_thickness" in d.values]
    if not designs:
        return None
    plt = pyplot()
    width = designs[0][0].pitch_mm - designs[0][0].gap_mm
    span = max(2 * width + d.gap_mm + 2.0 for d, _ in designs)
    heights = [1e3 * d.values["total_thickness"] for d, _ in designs]
    tall = sum(h + 1.6 for h in heights) + 0.2
    fig, ax = plt.subplots(figsize=(7.5, 7.5 * tall / (span + 9.2) + 0.2))
    y = 0.0
    for (d, name), h in zip(reversed(designs), reversed(heights)):
        _draw(ax, d, y + 0.8, name, material, width)
        y += h + 1.6
    ax.set_xlim(-0.2, span + 9)
    ax.set_ylim(0, y + 0.2)
    ax.set_aspect("equal")
    ax.axis("off")
    fig.tight_layout()
    return data_uri(figure_png(fig))
