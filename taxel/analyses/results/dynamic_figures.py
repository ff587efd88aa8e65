"""The figures of a dynamic result's folder (matplotlib on the Agg backend, results.figures'
`pyplot()`): the Bode plot of a frequency sweep or of the lumped model (`bode`, its resonance
marked: `resonance`), and the force and output of a transient (`time_response`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from taxel.analyses.results.figures import pyplot, readable


def resonance(freqs, mag) -> int | None:
    """The index of a sweep's resonance: the largest |H| above the sweep's lowest decade
    (where the readout's high-pass and the notch shape the response), when it is a peak
    inside the sweep, not at its edge; None otherwise (no resonance in the sweep)."""
    freqs, mag = np.asarray(freqs), np.asarray(mag)
    upper = freqs >= 10 * freqs[0]
    if not upper.any():
        return None
    i = int(np.argmax(np.where(upper, mag, -np.inf)))
    return i if 0 < i < len(freqs) - 1 else None


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
    i = resonance(freqs, mag)
    if i is not None:                           # a peak inside the sweep (resonance)
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
