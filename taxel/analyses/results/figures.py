"""The figures a result folder holds beside its numbers (matplotlib on the Agg
backend, no screen needed): the Bode plot of a frequency sweep or of the lumped model,
the force and output of a transient, the press of an indenter. `pyplot()` is the one
place the backend is chosen. The report pages (taxel.reports) reuse them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from taxel.units import engineering


def pyplot():
    """matplotlib.pyplot on the Agg backend."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def readable(label: str) -> str:
    """A readout label for a person: resistances with an SI prefix ("voltage across
    5e+08 ohm" -> "voltage across 500 MΩ")."""
    import re
    return re.sub(r"(\d[\d.]*(?:e[+-]?\d+)?) ?ohm", lambda m: eng(float(m.group(1)), "Ω"), label)


def eng(value: float | None, unit: str, digits: int = 3) -> str:
    """A number with an SI prefix, 3 significant figures, micro as µ: eng(2.33e-4, "N") -> "233 µN"."""
    import re
    return re.sub(r"^(\S+) u", r"\1 µ", engineering(value, unit, digits))




def bode(freqs, H, names, label, path, title="", notch: float | None = None):
    """Magnitude and phase (unwrapped) of H (nf, na) against frequency, with the
    resonance (the largest |H| above the lowest decade) and the notch marked."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6.2), sharex=True, layout="constrained")
    freqs = np.asarray(freqs)
    for k, name in enumerate(names):
        a1.loglog(freqs, np.abs(H[:, k]), label=name.replace("_", " "))
        a2.semilogx(freqs, np.degrees(np.unwrap(np.angle(H[:, k]))), label=name.replace("_", " "))
    mag = np.abs(H[:, 0])
    upper = freqs >= 10 * freqs[0]
    if upper.any():
        i = int(np.argmax(np.where(upper, mag, -np.inf)))
        if 0 < i < len(freqs) - 1:              # a peak inside the sweep, not its edge
            for a in (a1, a2):
                a.axvline(freqs[i], color="tab:red", lw=0.8, ls="--")
            a1.annotate(f"resonance {freqs[i]:.3g} Hz", (freqs[i], mag[i]), xytext=(-8, -4),
                        textcoords="offset points", ha="right", va="top", fontsize=8, color="tab:red")
    if notch:
        for a in (a1, a2):
            a.axvline(notch, color="tab:purple", lw=0.8, ls=":")
        a1.annotate(f"notch {notch:g} Hz", (notch, mag.min()), xytext=(6, 0), textcoords="offset points",
                    fontsize=8, color="tab:purple")
    a1.set_ylabel("|output per newton| (V/N)")
    a2.set_ylabel("phase, unwrapped (deg)")
    a2.set_xlabel("frequency (Hz)")
    a1.set_title(f"{title}: {readable(label)}" if title else readable(label), fontsize=10)
    if len(names) > 1:
        a1.legend(fontsize=8, loc="upper left")
    for a in (a1, a2):
        a.grid(True, which="both", alpha=0.3)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def time_response(t, force, y, names, label, path, title=""):
    """Force and output voltages over time."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True, layout="constrained")
    a1.plot(t, force, color="k")
    a1.set_ylabel("force (N)")
    a1.set_title(f"{title}: {readable(label)}" if title else readable(label), fontsize=10)
    y = np.asarray(y)
    big = float(np.nanmax(np.abs(y))) if y.size else 1.0
    scale, unit = (1e3, "mV") if big < 1 else (1.0, "V")
    for k, name in enumerate(names):
        a2.plot(t, scale * y[:, k], label=name.replace("_", " "))
    a2.set_ylabel(f"output ({unit})")
    a2.set_xlabel("time (s)")
    if len(names) > 1:
        a2.legend(fontsize=8, loc="best")
    for a in (a1, a2):
        a.grid(True, alpha=0.3)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def bode_png(result, path: Path) -> Path:
    """The Bode plot of a frequency result (fresh or read back), the notch marked."""
    r = result.scene.readout
    notch = r.notch_frequency if getattr(r, "notch", False) else None
    return bode(result.freqs, result.output, result.names, result.label, path, title=result.scene.name,
                notch=notch)


def transient_png(result, path: Path) -> Path:
    """The force and output of a transient result (fresh or read back)."""
    return time_response(result.t, result.force, result.output, result.names, result.label, path,
                         title=result.scene.name)


def lumped_png(result, path: Path) -> Path:
    """The Bode plot of the lumped model's response."""
    return bode(result.freqs, result.output[:, None], ["lumped 3-DoF"], result.label, path,
                title=f"{result.scene.name} (lumped)")


def contact_curves(rec: dict, path: Path, title: str = "") -> Path:
    """The press of an indenter scene: force against travel, and each open
    electrode's voltage against force (StaticResult.contact_record)."""
    plt = pyplot()
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
