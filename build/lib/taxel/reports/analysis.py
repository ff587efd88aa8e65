"""An analysis result written into its folder: the result's own files (scene,
CSV or JSON), a plot, and the summary lines. Used by the command line and the
main job."""

from __future__ import annotations

from pathlib import Path

from taxel.analyses import FrequencyResult, LumpedResult, StaticResult, TransientResult
from taxel.reports import figures


def write(result: StaticResult | FrequencyResult | TransientResult | LumpedResult, out) -> tuple[list[Path], list[str]]:
    """Write a result into `out`; returns (files written, summary lines). The
    summary is also kept as summary.txt."""
    out = Path(out)
    files = result.to_folder(out)
    name = result.scene.name
    if isinstance(result, FrequencyResult):
        files.append(figures.bode(result.freqs, result.output, result.names, result.label, out / f"{name}-bode.png",
                                  title=name))
    elif isinstance(result, TransientResult):
        files.append(figures.time_response(result.t, result.force, result.output, result.names, result.label,
                                           out / f"{name}-transient.png", title=name))
    elif isinstance(result, LumpedResult):
        files.append(figures.bode(result.freqs, result.output[:, None], ["lumped 3-DoF"], result.label,
                                  out / f"{name}-lumped.png", title=f"{name} (lumped)"))
    summary = result.summary() if hasattr(result, "summary") else str(result).splitlines()
    (out / "summary.txt").write_text("\n".join(summary) + "\n")
    return files, summary
