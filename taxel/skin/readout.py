r"""The skin's readout dynamics h: the pressed taxel's path through its readout chain,
as poles and residues, and its discretization at the simulator's step, both measured
against the solver's own frequency sweep of the same scene.

Why poles and residues, and the chain split in two. The reduced model's real state
space (fem.dynamics.realize) is exact, but a charge amplifier in series with the
charge path (SI units: R_f = 1 Gohm, C_f = 100 pF, charges of 1e-11 C) makes its
eigenvectors so badly scaled that a modal form built from them by eigendecomposition
is wrong by a factor 2-20 below 10 Hz, with the sign flipped (issue 55: a held press
rose instead of decaying with R_f C_f). So:

1. the path up to the chain's per-electrode stages (the open-circuit voltage, the
   voltage across the resistors, which couple the electrodes, or, for a charge
   amplifier, the short-circuit charge at a virtual ground) is realized by
   fem.dynamics and cut to its dominant modes (`truncate`), well conditioned;
2. the per-electrode stages, each a rational function of s with known poles (the
   charge amplifier -(R_f s) / ((1 + s R_f C_f)(1 + s R_i (C_p + C_c))) on the pressed
   electrode's charge, C_p its static capacitance; the 50 Hz notch
   (s^2 + w0^2) / (s^2 + w0 bw s + w0^2)), multiply it in closed form: for
   h1 = d1 + sum r_k / (s - l_k) and h2 = d2 + sum q_m / (s - p_m) with distinct poles,
   h1 h2 = d1 d2 + sum r_k h2(l_k) / (s - l_k) + sum q_m h1(p_m) / (s - p_m).

Sign: the solver's (fem.readout): the charge amplifier's output is -Q_sc / C_f in its
passband, Q_sc the short-circuit charge.

Discretization (`discretize`): first-order hold, mode by mode in closed form (each
continuous pole l maps exactly to e^(l dt): a held press decays with the circuit's own
time constant). It is exact for forces linear between steps; against the sweep, for a
sampled sinusoid, it loses about 1 - sinc^2(w dt / 2) in the worst case, measured 0.2 %
at 50 Hz and 0.7 % at 100 Hz for dt = 1 ms on a 4 x 4 PVDF skin with a charge
amplifier. (A least-squares fit of the residues to the sweep over 0.01 Hz-0.4 / dt,
tried, widened that band to 150 Hz but broke the exactness for ramps: 0.6 % of the
peak on a 5 ms step, and near the Nyquist frequency the fitted residues grew large and
cancelled.) The discrete response's error against the sweep is measured from 1 Hz to
0.4 / dt and stored as the skin's dynamics error over the band where it holds 1 % in
magnitude and 1 degree in phase (in a notch's stop band, where the sweep falls below a
tenth of its peak, the magnitude's error is taken of that tenth and the phase is not
judged).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from taxel.fem import dynamics
from taxel.fem.readout import Readout
from taxel.skin.discrete import first_order_hold


@dataclass(frozen=True)
class Poles:
    """A SISO transfer function d + sum_k r_k / (s - l_k) (conjugate pairs both listed)."""

    lam: np.ndarray
    r: np.ndarray
    d: float

    def frf(self, s) -> np.ndarray:
        s = np.asarray(s, complex)
        return (self.r[None, :] / (s[:, None] - self.lam[None, :])).sum(axis=1) + self.d

    def frf_hz(self, f) -> np.ndarray:
        return self.frf(2j * np.pi * np.asarray(f, float))

    def state_space(self):
        """Real (A, B, C, D), block diagonal (`real_blocks`)."""
        return real_blocks(self.lam, self.r, self.d)

    def times(self, other: "Poles") -> "Poles":
        """The product (module docstring, 2.)."""
        return Poles(np.concatenate([self.lam, other.lam]),
                     np.concatenate([self.r * other.frf(self.lam), other.r * self.frf(other.lam)]),
                     float(self.d * other.d))

    @classmethod
    def rational(cls, num, den) -> "Poles":
        """num(s) / den(s) (polynomial coefficients, highest power first), proper, simple poles."""
        num, den = np.atleast_1d(np.asarray(num, float)), np.atleast_1d(np.asarray(den, float))
        d = num[0] / den[0] if len(num) == len(den) else 0.0
        rest = np.polysub(num, d * den) if d else num
        p = np.roots(den).astype(complex)
        return cls(p, np.polyval(rest, p) / np.polyval(np.polyder(den), p), float(d))


def _merge(lam, r, rtol: float = 1e-5):
    """Poles equal within rtol merged into one with the summed residue (exact for equal
    poles: every taxel's electrode has the same RC pole, and eig splits such a cluster
    into eigenvectors whose residues are large and cancel)."""
    order = np.argsort(lam.real + 1e-3j * lam.imag)
    lam, r = lam[order], r[order]
    out_l, out_r = [lam[0]], [r[0]]
    for l_, r_ in zip(lam[1:], r[1:]):
        if abs(l_ - out_l[-1]) <= rtol * abs(l_):
            out_r[-1] += r_
        else:
            out_l.append(l_)
            out_r.append(r_)
    return np.array(out_l), np.array(out_r)


def truncate(A, B, C, D, band, tol: float = 3e-3, points: int = 300) -> tuple[Poles, float]:
    """A SISO state space cut to its dominant modes: modal truncation with the dropped
    modes' static parts kept, dropped smallest first while the measured error
    max |h - h_full| / max |h_full| on `points` log-spaced frequencies over `band` stays
    within tol (python-control's balanced truncation, tried, lost the path at every
    order 4-16 on this stiff SI-scaled system). Returns the kept Poles and the error."""
    lam, W = np.linalg.eig(A)
    r = (C @ W)[0] * np.linalg.solve(W, B)[:, 0]
    lam, r = _merge(lam, r)
    s = 2j * np.pi * np.geomspace(band[0], band[1], points)
    full = Poles(lam, r, float(D[0, 0]))
    H = full.frf(s)
    scale = np.abs(H).max()
    drop_err = r[None, :] * s[:, None] / (lam[None, :] * (s[:, None] - lam[None, :]))
    order = np.argsort(np.abs(drop_err).max(axis=0) / np.where(lam.imag > 0, 0.5, 1.0))
    total, dropped = np.zeros(len(s), complex), []
    for i in (k for k in order if lam[k].imag >= 0):
        members = [i] + ([int(np.argmin(np.abs(lam - lam[i].conj())))] if lam[i].imag > 0 else [])
        trial = total + drop_err[:, members].sum(axis=1)
        if np.abs(trial).max() > tol * scale:
            break
        total, dropped = trial, dropped + members
    keep = np.setdiff1d(np.arange(len(lam)), dropped)
    d = float((D[0, 0] - (r[dropped] / lam[dropped]).sum()).real)
    cut = Poles(lam[keep], r[keep], d)
    return cut, float(np.abs(cut.frf(s) - H).max() / scale)


def stages(r: Readout, C_p: float) -> Poles:
    """The per-electrode stages after the path (module docstring, 2.); 1 for none."""
    out = Poles(np.zeros(0, complex), np.zeros(0, complex), 1.0)
    if r.circuit == "charge_amplifier":
        out = out.times(Poles.rational([-r.R_f, 0.0], np.polymul([r.R_f * r.C_f, 1.0], [r.R_i * (C_p + r.C_c), 1.0])))
    if r.notch:
        w0, bw = 2 * np.pi * r.notch_frequency, r.notch_bandwidth / r.notch_frequency
        out = out.times(Poles.rational([1.0, 0.0, w0 ** 2], [1.0, w0 * bw, w0 ** 2]))
    return out


def path(rm, band, tol: float = 3e-3, C_p: float | None = None) -> tuple[Poles, float, Poles]:
    """h of a reduced model's pressed path through its readout (module docstring), the
    modal cut's measured error against the uncut path over `band`, and the electrical
    correction `electrical` applied (1 without C_p).

    With C_p (F, the pressed electrode's static capacitance in the 3D model, when the path
    is a 2D section's), the circuit sees the 3D electrode: the charge amplifier's input pole
    R_i (C_p + C_c) takes it, and a resistor's voltage per charge R s / (1 + s R C) is
    moved from the section's C0 to C_p by (1 + s R C0) / (1 + s R C_p) (the plane-strain
    section's C0 is 1 / 1.23 of the 3D taxel's on the thesis 2 x 2: without it a resistor
    skin read 1.2 x the 3D model's voltages in its band)."""
    i, j = rm.pressed()
    r = rm.readout
    base = "charge" if r.circuit == "charge_amplifier" else replace(r, notch=False)
    ss = dynamics.realize(rm.red, base, rm.band)
    h, cut = truncate(ss.A, ss.B[:, [j]], ss.C[[i], :], ss.D[[i]][:, [j]], band, tol)
    C0 = float(np.linalg.inv(dynamics.ports(rm.red, [1e-3])[1][0]).real[i, i])        # static capacitance
    one = Poles(np.zeros(0, complex), np.zeros(0, complex), 1.0)
    electrical = one
    if C_p is not None and r.circuit == "resistor":
        electrical = Poles.rational([r.R * C0, 1.0], [r.R * C_p, 1.0])
    return h.times(stages(r, C0 if C_p is None else C_p)).times(electrical), cut, electrical


def sweep(rm, freqs) -> np.ndarray:
    """The solver's sweep of the pressed path (the reduced second-order model with the
    FEM's loss law and the readout of fem.readout, as a frequency analysis solves it)."""
    i, j = rm.pressed()
    return rm.frf(freqs)[:, i, j]


@dataclass(frozen=True)
class Discrete:
    """H_d(z) = D + sum_m w_m / (z - mu_m) with its measured error against the sweep."""

    mu: np.ndarray               # discrete poles e^(l dt), conjugate pairs both listed
    w: np.ndarray
    D: float
    error: float                 # max |H_d - H_sweep| / max |H_sweep| over 1 Hz .. band
    band: float                  # Hz: up to here magnitude within 1 % and phase within 1 degree
    worst_magnitude: float       # relative, over 1 Hz .. band
    worst_phase: float           # degrees

    def frf(self, f, dt) -> np.ndarray:
        z = np.exp(2j * np.pi * np.asarray(f, float) * dt)
        return (self.w[None, :] / (z[:, None] - self.mu[None, :])).sum(axis=1) + self.D

    def state_space(self):
        """Real (Ad, Bd, Cd, Dd), block diagonal (`real_blocks`)."""
        return real_blocks(self.mu, self.w, self.D)


def real_blocks(poles, residues, d):
    """A real block-diagonal (A, B, C, D) of d + sum_k r_k / (x - p_k): a real pole as
    [[p]], a conjugate pair (listed both) as [[a, -b], [b, a]] with B = (1, 0)."""
    blocks, Bs, Cs = [], [], []
    for m, w in zip(poles, residues):
        if m.imag < 0:
            continue
        if m.imag > 0:
            blocks.append(np.array([[m.real, -m.imag], [m.imag, m.real]]))
            Bs += [1.0, 0.0]
            Cs += [2 * w.real, -2 * w.imag]
        else:
            blocks.append(np.array([[m.real]]))
            Bs.append(1.0)
            Cs.append(w.real)
    from scipy.linalg import block_diag
    A = block_diag(*blocks) if blocks else np.zeros((0, 0))
    return A, np.array(Bs).reshape(-1, 1), np.array(Cs).reshape(1, -1), np.array([[float(d)]])


def discretize(h: Poles, dt: float, target, f_low: float = 1.0, points: int = 1600) -> Discrete:
    """h by first-order hold (module docstring), measured against `target(freqs)`, the
    solver's sweep (complex), on `points` log-spaced frequencies from f_low to 0.4 / dt."""
    mu, w, D = first_order_hold(h.lam, h.r, h.d, dt)
    fc = np.geomspace(f_low, 0.4 / dt, points)
    probe = Discrete(mu, w, D, 0.0, 0.0, 0.0, 0.0)
    Hd, Hs = probe.frf(fc, dt), target(fc)
    floor = 0.1 * np.abs(Hs).max()          # in a notch's stop band: of a tenth of the peak
    rel = np.abs(Hd - Hs) / np.maximum(np.abs(Hs), floor)
    ph = np.where(np.abs(Hs) >= floor, np.abs(np.degrees(np.angle(Hd / Hs))), 0.0)
    bad = np.flatnonzero((rel > 0.01) | (ph > 1.0))
    top = fc[bad[0] - 1] if len(bad) and bad[0] > 0 else (fc[-1] if not len(bad) else f_low)
    inside = fc <= top
    return Discrete(mu, w, D, float(np.abs(Hd - Hs)[inside].max() / np.abs(Hs[inside]).max()), float(top),
                    float(rel[inside].max()), float(ph[inside].max()))
