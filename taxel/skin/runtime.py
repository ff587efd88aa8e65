"""The skin at the simulator's step: contact forces and points -> each taxel's voltage.

Numpy only (no FEM, no simulator, no compiled code of its own): any simulator that
can list the contact forces on the skin body and their points in the skin's frame
(taxel.skin.model: x, y along the surface, z its outward normal) calls

    skin = SkinRuntime(SkinModel.load("skin.npz"), noise=True, seed=0)
    v = skin.step(points, forces)      # every dt: points (m, 2) in m, forces (m, 3) in N -> (rows, cols) V
    v = skin.step(points, presses)     # or normal only: (m,) N, > 0 pressing (the same as (0, 0, -F))

or, for E environments stepped together (one skin each, same file),

    skins = SkinRuntime(model, envs=E)
    v = skins.step(points, forces)     # points (E, m, 2), forces (E, m) -> (E, rows, cols) V

(an environment with fewer contacts pads with zero forces), and `run` takes a whole
history of steps in one call. `reset(envs)` clears the state of some environments
(all by default) and, with a `Randomization`, draws their gain, unit-to-unit spread
and time constant anew.

The model (taxel.skin.model): u_k = sum_j sum_d W_kd(p_j) f_jd, then each taxel's
state advances through the discretized readout dynamics x' = Ad x + Bd u,
v = Cd x + Dd u (one input, one output, shared by all taxels).

How a step stays a handful of numpy calls (the interpreter's cost per call, not the
arithmetic, sets the time at these sizes):

- The dynamics in diagonal form. Ad = V diag(lambda) V^-1 (its poles are distinct:
  taxel.skin.build merges equal ones), so with z = V^-1 x / b (b = V^-1 Bd, each mode
  scaled by its own input weight) every mode obeys z' = lambda z + u and
  v = sum_k c_k b_k z_k + Dd u (c = Cd V). Complex modes come in conjugate pairs whose
  contributions are conjugate; only the one with Im lambda > 0 is kept, weighted 2,
  and v is the real part. The states of all taxels (and environments) are one complex
  array Z (modes + 1, taxels) whose last row holds u, so the output is one product
  w @ Z with w = (2 c b | c b | Dd) and the update two in-place calls, Z[:modes] *=
  lambda, Z[:modes] += u. At load the diagonal form is checked against Ad..Dd (their impulse responses
  over 400 steps); a file where it does not hold (V ill-conditioned) is stepped through
  the dense product [x'; v] = [[Ad, Bd], [Cd, Dd]] [x; u] instead.
- The influence, bilinear on its grid (taxel.skin.influence: one gather and one product).
- Noise drawn in blocks of `block` steps (2048: the FIR filter of 1024 taps costs one FFT per block).
- `check=False` skips the input checks (shapes; finite values, checked on the loads)
  for callers that guarantee finite float arrays of the right shapes.

Noise (on request): independent per taxel, Gaussian with the stored per-source PSDs'
sum (taxel.analyses.solves.noise: the scene's noise model, 1/f corners and all) from their
lowest frequency to the step's Nyquist frequency 1 / (2 dt): white noise filtered by
an FIR filter of NOISE_TAPS taps whose gain is sqrt(S(f) / (2 dt)) (zero below the
lowest stored frequency; Hann-windowed), drawn in blocks of `block` steps with the
filter's memory carried between blocks. Then the saturation (clip at +-saturation)
and, with an ADC, its quantization (the ADC's input gain v + offset coded in 2^bits
steps over its range, referred back to the readout output).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from taxel.skin.discrete import balanced_form, diagonal_form, first_order_hold
from taxel.skin.influence import InfluenceTable, check_finite
from taxel.skin.model import SkinModel

_RUN_BLOCK = 1024               # steps per block of `run`'s convolution
_FEW = 8                        # contacts up to which one skin's step finds cells in Python floats
NOISE_TAPS = 1024
ORDER_TOL = 1e-6                # the balanced cut of the modes: its error bound, of the peak |H|
FLUSH_BELOW = 1e-100             # modes' parts zeroed below this (SkinRuntime._flush)
_FLUSH_MASK = 63                # every 64 steps
_SLOW = 2 * np.pi * 20.0        # rad/s: real poles slower than this are the readout's time constants


@dataclass(frozen=True)
class Randomization:
    """Per-environment draws at `reset` (relative standard deviations, log-normal):
    `gain` one factor per environment on every taxel, `spread` one per taxel (unit-to-unit),
    `tau` one factor per environment on the readout's time constants (every real pole of
    h slower than 20 Hz: the resistor's R C or the charge amplifier's R_f C_f, and the
    silicone's slow relaxation; its residue scaled alike, so the passband gain stays)."""

    gain: float = 0.0
    spread: float = 0.0
    tau: float = 0.0


class SkinRuntime:
    """One skin's (or E skins') state between simulator steps (module docstring)."""

    def __init__(self, model: SkinModel, noise: bool = False, seed: int | None = None, dt: float | None = None,
                 envs: int | None = None, check: bool = True, block: int = 2048,
                 randomization: Randomization | None = None, order_tol: float = ORDER_TOL):
        if dt is not None and abs(dt - model.dt) > 1e-9 * model.dt:
            raise ValueError(f"dt = {dt:g} s: this skin is discretized at {model.dt:g} s; rebuild it with "
                             f"taxel skin SCENE --dt {dt:g} or step the simulator at {model.dt:g} s")
        if envs is not None and (int(envs) != envs or envs < 1):
            raise ValueError(f"envs = {envs}: the number of environments is a whole number >= 1")
        self.model, self.envs, self.check = model, envs, check
        rows, cols, T = model.rows, model.cols, model.taxels
        self.shape = (rows, cols) if envs is None else (int(envs), rows, cols)
        self._E = E = 1 if envs is None else int(envs)
        self.rng, self.block = np.random.default_rng(seed), int(block)
        self.randomization = randomization
        self._noise_setup(noise)
        a = model.adc
        # ADC: code = clip(rint(gain / lsb v + (offset - lo) / lsb), 0, 2^bits - 1), v = lsb / gain code + (lo - offset) / gain
        if a is not None:
            lsb = (a["hi"] - a["lo"]) / 2 ** a["bits"]
            self._adc = (a["gain"] / lsb, (a["offset"] - a["lo"]) / lsb, float(2 ** a["bits"] - 1),
                         lsb / a["gain"], (a["lo"] - a["offset"]) / a["gain"])
        else:
            self._adc = None
        s = model.saturation
        self._sat = float(s) if np.isfinite(s) else None
        self._table = InfluenceTable(model)
        self._loads, self._loads_few = self._table.loads, self._table.few
        self._rows, self._cols, self._T = rows, cols, T
        self._steps = 0
        self.g = np.ones((E, 1, T))
        # the dynamics: diagonal form, or the dense product where it does not hold
        form = diagonal_form(model.Ad, model.Bd, model.Cd, model.Dd)
        self.diagonal = form is not None
        self.order_error = 0.0           # the balanced cut's measured error (max |H_r - H| / max |H|)
        if self.diagonal and order_tol > 0 and not (randomization is not None and randomization.tau):
            cut = balanced_form(form[0], form[1][:-1], float(form[1][-1].real), order_tol)
            if cut is not None:
                form, self.order_error = (cut[0], np.append(cut[1], form[1][-1])), cut[2]
        if self.diagonal:
            lam, w = form[0].astype(complex), form[1].astype(complex)
            n = len(lam)
            # Z = [modes (n rows); u (1 row)]: w @ Z is the output; lambda stored repeated per taxel
            # (broadcasting it along the inner axis costs more than the arithmetic here)
            self._lam = np.repeat(np.repeat(lam[None, :, None], T, axis=2), E, axis=0)
            self._w = np.repeat(w[None, None, :], E, axis=0)
            self._Z = np.zeros((E, n + 1, T), complex)
            self._modes, self._urep = self._Z[:, :n], self._Z[:, n:]
            self._ureal = self._urep.real
            self._out = np.zeros((E, 1, T), complex)
            # one environment: the output product as one gemv on 2D views (a stacked matmul costs more)
            self._one_env = (self._w[0, 0], self._Z[0], self._out[0, 0]) if E == 1 else None
        else:
            self._one_env = None
            if randomization is not None and randomization.tau:
                raise ValueError("randomization.tau needs the diagonal form; this skin's Ad has none")
            n = model.Ad.shape[0]
            self._M = np.block([[model.Ad, model.Bd[:, :1]], [model.Cd[:1], model.Dd[:1, :1]]])
            self._Z, self._Znew = np.zeros((E, n + 1, T)), np.zeros((E, n + 1, T))
            self._urep = self._ureal = self._Z[:, n:]
        # one skin, diagonal form, unit gains, no noise, saturation or ADC: step's shortest path
        self._plain = (self.diagonal and E == 1 and randomization is None and not self.sigma and self._sat is None
                       and self._adc is None)
        if randomization is not None:
            self.reset()

    # -- noise ---------------------------------------------------------------------
    def _noise_setup(self, on: bool) -> None:
        """The noise's FIR taps (module docstring); sigma its rms per step (0: off)."""
        self.sigma = self.noise_rms() if on else 0.0
        self._noise, self._k = np.zeros((0, self._E, self.model.taxels)), 0
        if not self.sigma:
            return
        m = self.model
        f = np.fft.rfftfreq(NOISE_TAPS, m.dt)
        S = np.interp(f, m.noise_freqs, m.noise_psd.sum(axis=0), left=0.0, right=0.0)
        h = np.fft.fftshift(np.fft.irfft(np.sqrt(S / (2 * m.dt)), NOISE_TAPS)) * np.hanning(NOISE_TAPS)
        self._taps = h
        self._white = self.rng.standard_normal((NOISE_TAPS - 1, self._E, m.taxels))

    def noise_rms(self) -> float:
        """V rms per taxel and step: the PSDs integrated up to 1 / (2 dt) (module docstring)."""
        f = self.model.noise_freqs
        hi = min(0.5 / self.model.dt, f[-1])
        keep = f <= hi
        total = self.model.noise_psd[:, keep].sum(axis=0)
        return float(np.sqrt(np.trapezoid(total, f[keep]))) if keep.sum() > 1 else 0.0

    def _fill(self) -> None:
        """The next `block` steps of noise: white filtered by the taps, the memory carried."""
        L, B = NOISE_TAPS, self.block
        white = np.concatenate([self._white, self.rng.standard_normal((B, self._E, self.model.taxels))])
        N = 1 << int(np.ceil(np.log2(len(white) + L)))
        col = _fft_filter(white, self._taps, N)
        self._noise, self._k = col[L - 1:L - 1 + B], 0
        self._white = white[-(L - 1):]

    def _draw(self) -> np.ndarray:
        """The next step's noise (envs, 1, taxels) V."""
        if self._k == len(self._noise):
            self._fill()
        self._k += 1
        return self._noise[self._k - 1][:, None, :]

    def _draws(self, nt: int) -> np.ndarray:
        """The next nt steps' noise (nt, envs, taxels) V: the same numbers nt calls of _draw give."""
        parts = []
        while nt:
            if self._k == len(self._noise):
                self._fill()
            take = min(nt, len(self._noise) - self._k)
            parts.append(self._noise[self._k:self._k + take])
            self._k, nt = self._k + take, nt - take
        return np.concatenate(parts)

    # -- environments ------------------------------------------------------------------
    def reset(self, envs=None) -> None:
        """Clear the state of environments `envs` (indices or a boolean mask; all by default)
        and, with a Randomization, draw their gain, spread and time constants anew."""
        sel = np.arange(self._E)[np.asarray(envs)] if envs is not None else np.arange(self._E)
        sel = np.atleast_1d(sel)
        self._Z[sel] = 0.0
        r = self.randomization
        if r is None or not len(sel):
            return
        k = len(sel)
        self.g[sel] = (np.exp(r.gain * self.rng.standard_normal((k, 1, 1)))
                       * np.exp(r.spread * self.rng.standard_normal((k, 1, self._T))))
        if r.tau and self.diagonal:
            lam0, W0 = np.linalg.eig(self.model.A)
            res = (self.model.C[0] @ W0) * np.linalg.solve(W0, self.model.B[:, 0])
            slow = (np.abs(lam0.imag) == 0) & (np.abs(lam0) < _SLOW)
            for e, fac in zip(sel, np.exp(r.tau * self.rng.standard_normal(k))):
                lam, rr = np.where(slow, lam0 / fac, lam0), np.where(slow, res / fac, res)
                mu, w, D = first_order_hold(lam, rr, float(self.model.D[0, 0]), self.model.dt)
                up = mu.imag >= 0
                wu = np.where(mu[up].imag > 0, 2.0, 1.0) * w[up]
                if len(wu) != self._lam.shape[1]:
                    raise ValueError("skin file: A and Ad have different modes; rebuild the skin")
                self._lam[e] = mu[up][:, None]
                self._w[e, 0] = np.append(wu, D)

    # -- loads -----------------------------------------------------------------------
    def _inputs(self, points, forces, lead: tuple) -> tuple[np.ndarray, np.ndarray]:
        """points (*lead, m, 2), forces (*lead, m) or (*lead, m, 3) as float arrays; ValueError (one line) otherwise."""
        p, f = np.asarray(points, float), np.asarray(forces, float)
        ps, fs = p.shape, f.shape
        if not lead and len(ps) == 2 and ps[1] == 2 and (fs == ps[:1] or fs == (ps[0], 3)):
            return p, f                                         # one skin's well-formed contacts, at once
        if p.ndim != len(lead) + 2 or p.shape[:-2] != lead or p.shape[-1] != 2 or f.shape not in (
                p.shape[:-1], (*p.shape[:-1], 3)):
            want = "".join(f"{n}, " for n in lead)
            raise ValueError(f"points {p.shape}, forces {f.shape}: give points ({want}m, 2) m and forces ({want}m, 3) "
                             f"N in the skin frame, or normal forces ({want}m,) N")
        return p, f

    def loads(self, points, forces) -> np.ndarray:
        """u (..., rows, cols) N: the force each taxel sees from forces (..., m, 3) in the skin
        frame, or normal forces (..., m) > 0 pressing, at points (..., m, 2)."""
        p, f = np.asarray(points, float), np.asarray(forces, float)
        if p.ndim < 2 or p.shape[-1] != 2 or f.shape not in (p.shape[:-1], (*p.shape[:-1], 3)):
            raise ValueError(f"points {p.shape}, forces {f.shape}: give points (..., m, 2) m and forces "
                             "(..., m, 3) or (..., m) N")
        u = self._loads(p, f).reshape(*p.shape[:-2], self._rows, self._cols)
        check_finite(u)
        return u

    def step(self, points, forces) -> np.ndarray:
        """Advance one dt with forces (m, 3) N in the skin frame (or normal forces (m,) N,
        > 0 pressing) at points (m, 2) m: (rows, cols) V; with envs = E, points (E, m, 2)
        and forces (E, m, 3) or (E, m): (E, rows, cols) V."""
        if self.check:
            points, forces = self._inputs(points, forces, self.shape[:-2])
        few = self.envs is None and len(points) <= _FEW
        if few and self._plain:           # the common case in the fewest calls (the general path below alike)
            self._ureal[...] = self._loads_few(np.asarray(points, float), np.asarray(forces, float), self.check)
            np.dot(*self._one_env)
            v = self._out.real.copy()
            self._modes *= self._lam
            self._modes += self._urep
            self._steps += 1
            if not self._steps & _FLUSH_MASK:
                self._flush()
            return v.reshape(self.shape)
        if few:
            u = self._loads_few(np.asarray(points, float), np.asarray(forces, float), self.check)
        else:
            u = self._loads(points, forces).reshape(-1, 1, self._T)
            if self.check:
                check_finite(u)
        if self.randomization is None:             # unit gains: the input row's real part is u
            self._ureal[...] = u
        else:
            np.multiply(u, self.g, out=self._urep)
        if self.diagonal:
            if self._one_env is not None:
                np.dot(*self._one_env)
            else:
                np.matmul(self._w, self._Z, out=self._out)
            v = self._out.real.copy() if not self.sigma else self._out.real + self._draw()
            self._modes *= self._lam
            self._modes += self._urep
        else:
            np.matmul(self._M, self._Z, out=self._Znew)
            self._Z, self._Znew = self._Znew, self._Z
            n = self._Z.shape[1] - 1
            v = self._Z[:, n:].copy() if not self.sigma else self._Z[:, n:] + self._draw()
            self._urep = self._ureal = self._Z[:, n:]
        self._steps += 1
        if not self._steps & _FLUSH_MASK:
            self._flush()
        if self._sat is None and self._adc is None:
            return v.reshape(self.shape)
        return self._output(v).reshape(self.shape)

    def _flush(self) -> None:
        """Zero the modes' parts below FLUSH_BELOW: a skin left idle decays its modes towards
        zero and, past 1e-308, into subnormal numbers, whose arithmetic costs the processor
        ten times more (an 8 x 8 skin's step went from 12 to 110 us after 3000 idle steps).
        Every 64 steps: a mode with |lambda| >= 1e-3 cannot fall from FLUSH_BELOW to 1e-308 in
        64 steps (a faster one crosses the subnormals in a few steps); what it drops is below 1e-100 of a
        newton's load. The dense form's state alike."""
        parts = self._Z.view(float)
        parts[np.abs(parts) < FLUSH_BELOW] = 0.0

    def _output(self, v) -> np.ndarray:
        """Saturation and the ADC applied in place to voltages v (noise already added)."""
        if self._sat is not None:
            np.minimum(v, self._sat, out=v)
            np.maximum(v, -self._sat, out=v)
        if self._adc is not None:
            scale, shift, top, back, base = self._adc
            v *= scale
            v += shift
            np.rint(v, out=v)
            np.minimum(v, top, out=v)
            np.maximum(v, 0.0, out=v)
            v *= back
            v += base
        return v

    def run(self, points, forces) -> np.ndarray:
        """A whole history from the current state: points (nt, [E,] m, 2), forces (nt, [E,] m, 3)
        or (nt, [E,] m) -> (nt, [E,] rows, cols) V; the same voltages (and noise) as nt calls of `step`, for
        contacts known ahead (a recorded or scripted trajectory, a data set): the loads of
        all steps are one vectorized evaluation and, in the diagonal form, the dynamics a
        convolution per block of steps (`_block`) instead of a loop over steps."""
        forces = np.asarray(forces, float)
        points, forces = self._inputs(points, forces, (len(forces), *self.shape[:-2]))
        nt = len(forces)
        U = self._loads(points, forces).reshape(nt, -1, self._T) * self.g[:, 0]    # (nt, E, taxels)
        check_finite(U)
        V = np.empty(U.shape)
        if self.diagonal:
            for k in range(0, nt, _RUN_BLOCK):
                V[k:k + _RUN_BLOCK] = self._block(U[k:k + _RUN_BLOCK])
        else:
            n = self._Z.shape[1] - 1
            for k in range(nt):
                self._urep[:] = U[k][:, None, :]
                np.matmul(self._M, self._Z, out=self._Znew)
                self._Z, self._Znew = self._Znew, self._Z
                self._urep = self._Z[:, n:]
                V[k] = self._Z[:, n]
        if self.sigma:
            V += self._draws(nt)
        return self._output(V).reshape(nt, *self.shape)

    def _block(self, U) -> np.ndarray:
        """Voltages (L, E, taxels) of L steps with loads U (L, E, taxels) from the modes' state z0,
        which it advances L steps. From z' = lambda z + u, v = Re(w z) + D u:
            v_k = Re(sum_m w_m lambda_m^k z0_m) + sum_(j <= k) h_(k-j) u_j,
            h_0 = D, h_k = Re(sum_m w_m lambda_m^(k-1)),
            z_L = lambda^L z0 + sum_(j < L) lambda^(L-1-j) u_j,
        the free response and the end state as products with the powers lambda^k, the
        forced response a linear convolution by FFT (zero-padded to 2 L: no wrap-around)."""
        L, E, T = U.shape
        V = np.empty(U.shape)
        for e in range(E):                  # each environment its own modes (Randomization.tau)
            lam, w, D = self._lam[e, :, 0], self._w[e, 0, :-1], self._w[e, 0, -1].real
            Pk = lam[None, :] ** np.arange(L + 1)[:, None]                          # (L + 1, n): lambda^k (0^0 = 1)
            h = np.empty(L)
            h[0] = D
            h[1:] = (Pk[:L - 1] @ w).real
            N = 2 * L
            V[:, e] = _fft_filter(U[:, e], h, N)[:L]
            z0 = self._modes[e]                                                     # (n, T)
            if z0.any():                                                            # the free response
                V[:, e] += (Pk[:L] @ (w[:, None] * z0)).real
            R = np.ascontiguousarray(Pk[L - 1::-1].T)                               # (n, L): lambda^(L-1-j)
            z0 *= Pk[L][:, None]
            z0 += R.real @ U[:, e] + 1j * (R.imag @ U[:, e])
        return V


def _fft_filter(x: np.ndarray, h: np.ndarray, n: int) -> np.ndarray:
    """x (time first, any trailing axes) filtered by the impulse response h, by FFTs of length n
    (n >= len(x) + len(h) - 1 for a linear, not circular, convolution): the one copy the noise
    and the replay share (the runtime is numpy only, so not scipy.signal.fftconvolve)."""
    H = np.fft.rfft(h, n).reshape((-1,) + (1,) * (x.ndim - 1))
    return np.fft.irfft(np.fft.rfft(x, n, axis=0) * H, n, axis=0)
