"""The figures of the thesis chapter-4 reproduction (taxel.jobs.thesis_ch4), drawn
from analysis results: step and impulse through the 500 MOhm input, the chirp
through the charge amplifier against the frequency sweep, the silicone thickness
on the frequency response, and the FEM against the lumped 3-DoF model."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from taxel.analyses.results import FrequencyResult, LumpedResult, TransientResult
from taxel.reports.figures import pyplot


def step_impulse(results: list[TransientResult], path: Path) -> Path:
    """One panel per transient: the first electrode's voltage against time."""
    plt = pyplot()
    fig, axes = plt.subplots(1, len(results), figsize=(10, 3.6), constrained_layout=True)
    for ax, res in zip(np.atleast_1d(axes), results):
        s = res.scene
        ax.plot(res.t, res.output[:, 0])
        ax.set_title(f"{s.analysis.input}, {s.load.force:g} N, 500 MOhm input")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("voltage (V)")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def chirp_ratio(res: TransientResult, band: tuple[float, float] = (1.0, 100.0)) -> tuple[np.ndarray, np.ndarray]:
    """(frequency Hz, |FFT(output) / FFT(force)| in V/N) of a chirp's transient, inside `band`."""
    t = res.t
    freqs = np.fft.rfftfreq(len(t), t[1] - t[0])
    inside = (freqs > band[0]) & (freqs < band[1])
    return freqs[inside], np.abs(np.fft.rfft(res.output[:, 0]) / np.fft.rfft(res.force))[inside]


def chirp(transients: dict[bool, TransientResult], sweeps: dict[bool, FrequencyResult], path: Path) -> Path:
    """The chirp's amplifier output over time, and its FFT ratio against the frequency
    sweep, without and with the notch (keys: notch on)."""
    plt = pyplot()
    fig, axes = plt.subplots(2, 1, figsize=(8, 6), constrained_layout=True)
    for notch in (False, True):
        res, sw = transients[notch], sweeps[notch]
        axes[0].plot(res.t, res.output[:, 0], lw=0.6, label="with notch" if notch else "no notch")
        f, H = chirp_ratio(res)
        axes[1].semilogy(f, H, lw=0.8, label=f"chirp FFT ratio{' + notch' if notch else ''}")
        axes[1].semilogy(sw.freqs, np.abs(sw.output[:, 0]), "--", label=f"frequency sweep{' + notch' if notch else ''}")
    axes[0].set_xlabel("time (s)")
    axes[0].set_ylabel("amplifier output (V)")
    axes[0].legend()
    axes[1].set_xlabel("frequency (Hz)")
    axes[1].set_ylabel("|V/F| (V/N)")
    axes[1].legend(fontsize=8)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def silicone_thickness(sweeps: dict[float, FrequencyResult], path: Path) -> Path:
    """The readout's gain for each total silicone thickness (keys, m)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
    for total, sw in sweeps.items():
        ax.loglog(sw.freqs, np.abs(sw.output[:, 0]), label=f"silicone {1e3 * total:g} mm in total")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("|charge amplifier + notch| (V/N)")
    ax.legend()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fem_vs_lumped(fem: FrequencyResult, lumped: LumpedResult, path: Path) -> Path:
    """The FEM's readout gain against the lumped 3-DoF model's."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
    ax.loglog(fem.freqs, np.abs(fem.output[:, 0]), label="FEM (2D plane strain)")
    ax.loglog(lumped.freqs, np.abs(lumped.output), label="lumped 3-DoF (errata corrected)")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("|charge amplifier + notch| (V/N)")
    ax.legend()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
