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
    elif isinstance(result, StaticResult) and result.contact_record() is not None:
        files.append(contact_curves(result.contact_record(), out / f"{name}-contact.png", title=name))
    summary = result.summary() if hasattr(result, "summary") else str(result).splitlines()
    (out / "summary.txt").write_text("\n".join(summary) + "\n")
    return files, summary


def contact_curves(rec: dict, path: Path, title: str = "") -> Path:
    """The press of an indenter scene: force against travel, and each open
    electrode's voltage against force (StaticResult.contact_record)."""
    plt = figures.pyplot()
    cv = rec["curve"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(8, 3.4), constrained_layout=True)
    a1.plot([1e3 * d for d in cv["travel_m"]], cv["force_N"], "o-", ms=3, color="k")
    a1.set_xlabel("indenter travel (mm)")
    a1.set_ylabel("force (N)")
    for k, v in cv["voltages_V"].items():
        a2.plot(cv["force_N"], v, "o-", ms=3, label=k)
    a2.set_xlabel("force (N)")
    a2.set_ylabel("open-circuit voltage (V)")
    a2.legend(fontsize=8)
    for a in (a1, a2):
        a.grid(True, alpha=0.3)
    fig.suptitle(f"{title}: {rec['indenter']['shape']} indenter, {rec['load_steps']} load steps", fontsize=9)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
