"""Frequency response from chirp data, and the models against it.

Definitions (x the load cell's force in N, y a taxel's conditioning output in V,
both over the chirp's span, from the first to the last loading event):

H1 estimator: H1(f) = P_xy(f) / P_xx(f), with P_xy the Welch cross-spectrum
(scipy.signal.csd) and P_xx the Welch auto-spectrum (scipy.signal.welch), Hann
windows of nperseg = rate / resolution samples, 50 % overlap, mean removed per
segment. H1 is unbiased by noise on y (not on x). The coherence
gamma^2 = |P_xy|^2 / (P_xx P_yy) (scipy.signal.coherence, same segments) says
where H1 is trustworthy: 1 for a noise-free linear system.

Amplitude-spectrum ratio (the thesis's method): |FFT(y)| / |FFT(x)| of the
whole chirp span (one Hann-windowed FFT), averaged in magnitude over the bins of
each H1 frequency's resolution band. It has no phase and no noise rejection.

Model against measurement: a model's FRF H_m(f) of the pressed taxel through the
rig's own readout chain (fem.readout.readout: the charge amplifier or resistor,
and the notch): the lumped model, and the FEM (taxel.analyses.frequency of the
scene pressed on that taxel, from 1 Hz to the last coherent frequency) against the measured H1 of the channel of the pressed taxel:
    RMS error = 100 % x sqrt(mean_f ((|H_m(f)| - |H1(f)|) / |H1(f)|)^2)
over the frequencies f > 0 where the coherence exceeds 0.9 (the band is reported).
A chirp shorter than 4 segments of the requested resolution is refused (too few
averages for a coherence to mean anything).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from taxel.studies.measured.events import Record, segments
from taxel.studies.bench.folder import MeasurementError
from taxel.schema import electrode_name


class ChirpError(MeasurementError):
    """A chirp that cannot give the requested frequency response."""


@dataclass
class FRF:
    taxel: str
    freqs: np.ndarray            # Hz
    H1: np.ndarray               # complex, V/N
    coherence: np.ndarray
    ratio: np.ndarray            # amplitude-spectrum ratio, V/N
    span_s: tuple[float, float]
    nperseg: int
    models: dict = field(default_factory=dict)    # name -> complex model FRF on freqs

    def record(self) -> dict:
        return {"taxel": self.taxel, "span_s": list(self.span_s), "nperseg": self.nperseg,
                "resolution_Hz": float(self.freqs[1] - self.freqs[0]),
                "freqs_Hz": self.freqs.tolist(), "H1_abs_V_per_N": np.abs(self.H1).tolist(),
                "H1_phase_deg": np.degrees(np.angle(self.H1)).tolist(), "coherence": self.coherence.tolist(),
                "ratio_V_per_N": self.ratio.tolist(),
                "models": {k: {"abs_V_per_N": [float(x) if np.isfinite(x) else None for x in np.abs(v)],
                               "phase_deg": [float(x) if np.isfinite(x) else None for x in np.degrees(np.angle(v))],
                               **rms_error(self, k)} for k, v in self.models.items()}}

    @classmethod
    def from_record(cls, rec: dict) -> FRF:
        """The FRF of its `record()` (a model written without its phase reads back with phase 0)."""
        def cplx(mag, deg):
            m = np.array([np.nan if x is None else x for x in mag], float)
            d = np.array([np.nan if x is None else x for x in deg], float) if deg is not None else np.zeros(len(m))
            return m * np.exp(1j * np.radians(d))
        return cls(rec["taxel"], np.array(rec["freqs_Hz"], float), cplx(rec["H1_abs_V_per_N"], rec["H1_phase_deg"]),
                   np.array(rec["coherence"], float), np.array(rec["ratio_V_per_N"], float), tuple(rec["span_s"]),
                   int(rec["nperseg"]),
                   {k: cplx(v["abs_V_per_N"], v.get("phase_deg")) for k, v in rec.get("models", {}).items()})

    def csv_rows(self) -> list[list[float]]:
        cols = [self.freqs, np.abs(self.H1), np.degrees(np.angle(self.H1)), self.coherence, self.ratio]
        cols += [np.abs(v) for v in self.models.values()]
        return np.column_stack(cols).tolist()

    def csv_header(self) -> list[str]:
        return ["f_Hz", "H1_abs_V_per_N", "H1_phase_deg", "coherence", "ratio_V_per_N"] + \
               [f"{k}_abs_V_per_N" for k in self.models]


def chirp_span(rec: Record) -> tuple[int, int]:
    segs = segments(rec)
    if not segs:
        raise ChirpError("no chirp on the force channel")
    return segs[0][0], segs[-1][1]


def h1(rec: Record, k: int, resolution: float = 1.0) -> FRF:
    """H1, coherence and the amplitude-spectrum ratio of taxel channel k (module docstring)."""
    if not resolution > 0:
        raise ChirpError(f"--resolution must be positive, got {resolution}")
    a, b = chirp_span(rec)
    n = int(round(rec.rate / resolution))
    if b - a < 4 * n:
        raise ChirpError(f"the chirp lasts {(b - a) / rec.rate:.3g} s, too short for {resolution:g} Hz resolution "
                         f"(4 segments of {n / rec.rate:.3g} s); record a chirp of at least {4 * n / rec.rate:.3g} s "
                         f"or ask --resolution {4 * rec.rate / (b - a):.3g}")
    x, y = rec.force[a:b], rec.volts[a:b, k]
    kw = dict(fs=rec.rate, nperseg=n, noverlap=n // 2, window="hann", detrend="constant")
    f, Pxx = signal.welch(x, **kw)
    _, Pxy = signal.csd(x, y, **kw)
    _, coh = signal.coherence(x, y, **kw)
    H = Pxy / np.where(Pxx > 0, Pxx, np.inf)
    w = signal.windows.hann(b - a)
    X = np.fft.rfft((x - x.mean()) * w)
    Y = np.fft.rfft((y - y.mean()) * w)
    fb = np.fft.rfftfreq(b - a, 1 / rec.rate)
    ratio = np.zeros_like(f)
    for i, fi in enumerate(f):
        sel = np.abs(fb - fi) <= resolution / 2
        num, den = np.abs(Y[sel]), np.abs(X[sel])
        ratio[i] = np.mean(num) / np.mean(den) if sel.any() and np.mean(den) > 0 else np.nan
    return FRF(rec.names[k], f, H, coh, ratio, (a / rec.rate, b / rec.rate), n)


def rms_error(frf: FRF, model: str, min_coherence: float = 0.9) -> dict:
    """The RMS relative magnitude error of a model over the band where the coherence exceeds min_coherence."""
    Hm = frf.models[model]
    sel = (frf.coherence > min_coherence) & (frf.freqs > 0) & (np.abs(frf.H1) > 0) & np.isfinite(Hm)
    if not sel.any():
        return {"rms_error_pct": None, "band_Hz": None, "points": 0, "min_coherence": min_coherence}
    e = (np.abs(Hm[sel]) - np.abs(frf.H1[sel])) / np.abs(frf.H1[sel])
    return {"rms_error_pct": float(100 * np.sqrt(np.mean(e ** 2))),
            "band_Hz": [float(frf.freqs[sel].min()), float(frf.freqs[sel].max())], "points": int(sel.sum()),
            "min_coherence": min_coherence}


def lumped_frf(lm, readout, freqs: np.ndarray) -> np.ndarray:
    """The lumped model's V/N through a readout chain (fem.readout), at freqs (Hz)."""
    from taxel.fem import dynamics
    from taxel.fem import readout as circuits
    f = np.where(freqs > 0, freqs, 1e-6)
    port = dynamics.PortResponse(f, (lm.V_oc(f) / lm.force)[:, None], np.full((len(f), 1, 1), 1 / lm.C_p),
                              ["lumped"], "lumped", 0.0)
    return circuits.readout(port, readout)[:, 0]


def fem_frf(scene, readout, taxel: tuple[int, int], freqs: np.ndarray) -> np.ndarray:
    """The FEM's V/N of the pressed `taxel` through a readout chain, at freqs (Hz) from 1 Hz up
    (taxel.analyses.frequency, the scene's method; NaN below 1 Hz). The scene is pressed on `taxel`."""
    from dataclasses import asdict

    from taxel.analyses import frequency
    sel = freqs >= 1.0
    f = freqs[sel]
    ro = {f"readout.{k}": v for k, v in asdict(readout).items()}
    s = scene.replace(**{"analysis.type": "frequency", "analysis.f_min": float(f[0]), "analysis.f_max": float(f[-1]),
                         "analysis.points": len(f), "analysis.spacing": "linear", "load.kind": "taxel",
                         "load.taxel": list(taxel), **ro})
    r = frequency(s)
    name = electrode_name(taxel[0], taxel[1])
    out = np.full(len(freqs), np.nan, complex)
    out[sel] = np.interp(f, r.freqs, r.output[:, list(r.names).index(name)].real) + \
        1j * np.interp(f, r.freqs, r.output[:, list(r.names).index(name)].imag)
    return out
