"""The skin at the simulator's step: contact forces and points -> each taxel's voltage.

Numpy only (no FEM, no simulator, no compiled code of its own): any simulator that
can list the normal contact forces on the skin body and their points in the skin's
frame calls

    skin = SkinRuntime(SkinModel.load("skin.npz"), noise=True, seed=0)
    v = skin.step(points, forces)      # every dt: points (m, 2) in m, forces (m,) in N -> (rows, cols) V

or, for E environments stepped together (one skin each, same file),

    skins = SkinRuntime(model, envs=E)
    v = skins.step(points, forces)     # points (E, m, 2), forces (E, m) -> (E, rows, cols) V

(an environment with fewer contacts pads with zero forces), and `run` takes a whole
history of steps in one call.

The model (taxel.skin.model): u_rc = g_rc sum_j F_j G_r(y_j) G_c(x_j), then each taxel's
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
- The influence spline in a scaled variable: with the knots evenly spaced by h,
  s -> t = (s - s0) / h, interval i = floor(t), d = t - i in [0, 1), and the stored
  coefficients rescaled once to d, G(s) = (d^3, d^2, d, 1) . C_i: one divmod, one
  power, one gather, one dot product (np.vecdot: a loop in numpy, not a BLAS call per
  contact) for the x and y of all contacts (s beyond the knots takes the end value
  through a constant piece at each end and a clipped index); sum_j F_j G_r(y_j) G_c(x_j)
  is then one scaling and one product.
- Noise drawn in blocks of `block` steps from the seeded generator.
- `check=False` skips the input checks (shapes; finite values, checked on the loads)
  for callers that guarantee finite float arrays of the right shapes.

Noise (on request): independent per taxel and step, Gaussian with the variance of the
stored per-source PSDs integrated from their lowest frequency to the step's Nyquist
frequency 1 / (2 dt) (white at the step rate: the spectral shape inside the band is
not reproduced), then the saturation (clip at +-saturation) and, with an ADC, its
quantization (the ADC's input gain v + offset coded in 2^bits steps over its range,
referred back to the readout output).
"""

from __future__ import annotations

import numpy as np

from taxel.skin.model import SkinModel

_POWERS = np.array([3.0, 2.0, 1.0, 0.0])
_CHECK_STEPS = 400
_RUN_BLOCK = 1024               # steps per block of `run`'s convolution


def diagonal_form(Ad, Bd, Cd, Dd) -> tuple[np.ndarray, np.ndarray] | None:
    """(lambda (k,), w (k + 1,)) of the diagonal form (module docstring), or None if it
    does not reproduce Ad..Dd's impulse response to 1e-9 of its peak."""
    lam, V = np.linalg.eig(Ad)
    try:
        b = np.linalg.solve(V, Bd[:, 0])
    except np.linalg.LinAlgError:
        return None
    cb = (Cd[0] @ V) * b
    keep = (lam.imag >= 0) & (np.abs(cb) > 0)
    lam, w = lam[keep], np.where(lam[keep].imag > 0, 2.0, 1.0) * cb[keep]
    h_ref, x = np.empty(_CHECK_STEPS), Bd[:, 0].copy()          # impulse response: Dd, then Cd Ad^(k-1) Bd
    h_ref[0] = Dd[0, 0]
    for k in range(1, _CHECK_STEPS):
        h_ref[k], x = Cd[0] @ x, Ad @ x
    h = np.empty(_CHECK_STEPS)
    h[0] = Dd[0, 0]
    h[1:] = (lam[None, :] ** np.arange(_CHECK_STEPS - 1)[:, None] @ w).real
    if not np.all(np.isfinite(h)) or np.abs(h - h_ref).max() > 1e-9 * max(np.abs(h_ref).max(), 1e-300):
        return None
    return lam, np.append(w, Dd[0, 0])


class SkinRuntime:
    """One skin's (or E skins') state between simulator steps (module docstring)."""

    def __init__(self, model: SkinModel, noise: bool = False, seed: int | None = None, dt: float | None = None,
                 envs: int | None = None, check: bool = True, block: int = 256):
        if dt is not None and abs(dt - model.dt) > 1e-9 * model.dt:
            raise ValueError(f"dt = {dt:g} s: this skin is discretized at {model.dt:g} s; rebuild it with "
                             f"taxel skin SCENE --dt {dt:g} or step the simulator at {model.dt:g} s")
        if envs is not None and (int(envs) != envs or envs < 1):
            raise ValueError(f"envs = {envs}: the number of environments is a whole number >= 1")
        self.model, self.envs, self.check = model, envs, check
        rows, cols, T = model.rows, model.cols, model.taxels
        self.shape = (rows, cols) if envs is None else (int(envs), rows, cols)
        E = 1 if envs is None else int(envs)
        self.g = model.gain.reshape(T).astype(float)
        self.sigma = self.noise_rms() if noise else 0.0
        self.rng, self.block = np.random.default_rng(seed), int(block)
        self._noise, self._k = np.zeros((0, E, T)), 0
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
        # the influence spline in the scaled variable (module docstring)
        k = np.asarray(model.knots, float)
        h = float((k[-1] - k[0]) / (len(k) - 1))
        if not np.allclose(np.diff(k), h, rtol=1e-9, atol=0):
            raise ValueError("skin file: the influence knots are not evenly spaced; rebuild the skin")
        self._t0, self._inv_h = float(k[0]) / h - 1.0, 1.0 / h
        # rescaled to d, and one constant piece added at each end (the end values): an index
        # clipped to the table then gives G at the nearer end for s beyond the knots, whatever d is
        co = (model.coef * h ** _POWERS[:, None, None]).transpose(1, 0, 2)            # (intervals, 4, n)
        ends = np.zeros((2, 4, co.shape[2]))
        ends[0, 3], ends[1, 3] = co[0, 3], co[-1].sum(axis=0)                       # G(s0), G(s_end) (d = 1)
        self._coef = np.ascontiguousarray(np.concatenate([ends[:1], co, ends[1:]]).transpose(0, 2, 1))   # (., n, 4)
        self._rows, self._cols, self._T = rows, cols, T
        # the dynamics: diagonal form, or the dense product where it does not hold
        form = diagonal_form(model.Ad, model.Bd, model.Cd, model.Dd)
        self.diagonal = form is not None
        if self.diagonal:
            lam, w = form
            n = len(lam)
            # Z = [modes (n rows); u (1 row)]: w @ Z is the output; lambda stored repeated per taxel
            # (broadcasting it along the inner axis costs more than the arithmetic here)
            self._lam = np.repeat(lam[:, None], T, axis=1)
            self._w = w[None, :]
            self._gc = self.g.astype(complex)                 # u g complex: no cast writing into Z
            self._Z = np.zeros((E, n + 1, T), complex)
            self._modes, self._urep = self._Z[:, :n], self._Z[:, n:]
            self._out = np.zeros((E, 1, T), complex)
        else:
            n = model.Ad.shape[0]
            self._M = np.block([[model.Ad, model.Bd[:, :1]], [model.Cd[:1], model.Dd[:1, :1]]])
            self._Z, self._Znew = np.zeros((E, n + 1, T)), np.zeros((E, n + 1, T))
            self._urep = self._Z[:, n:]

    def noise_rms(self) -> float:
        """V rms per taxel and step: the PSDs integrated up to 1 / (2 dt) (module docstring)."""
        f = self.model.noise_freqs
        hi = min(0.5 / self.model.dt, f[-1])
        keep = f <= hi
        total = self.model.noise_psd[:, keep].sum(axis=0)
        return float(np.sqrt(np.trapezoid(total, f[keep]))) if keep.sum() > 1 else 0.0

    def reset(self) -> None:
        self._Z[:] = 0.0

    def _inputs(self, points, forces, lead: tuple) -> tuple[np.ndarray, np.ndarray]:
        """points (*lead, m, 2), forces (*lead, m) as float arrays; ValueError (one line) otherwise.
        (Finite values are checked on the loads they give: a NaN or inf anywhere reaches them.)"""
        p, f = np.asarray(points, float), np.asarray(forces, float)
        if f.shape[:-1] != lead or p.shape != (*f.shape, 2) or f.ndim != len(lead) + 1:
            want = "".join(f"{n}, " for n in lead)
            raise ValueError(f"points {p.shape}, forces {f.shape}: give points ({want}m, 2) m and forces ({want}m,) N")
        return p, f

    @staticmethod
    def _finite(u) -> None:
        if not np.isfinite(u).all():
            raise ValueError("points or forces not finite: give finite contact points (m) and forces (N)")

    def loads(self, points, forces) -> np.ndarray:
        """u (..., rows, cols) N: the force each taxel sees from normal forces (..., m) at points (..., m, 2)."""
        p = np.asarray(points, float)
        f = np.asarray(forces, float)
        if f.ndim == 0 or p.shape != (*f.shape, 2):
            raise ValueError(f"points {p.shape}, forces {f.shape}: give points (..., m, 2) m and forces (..., m) N")
        u = self._loads(p, f) * self.g.reshape(self._rows, self._cols)
        self._finite(u)
        return u

    def _loads(self, p, f) -> np.ndarray:
        """sum_j F_j G_r(y_j) G_c(x_j) (..., rows, cols), without the gains (module docstring)."""
        t = p * self._inv_h
        t -= self._t0                                         # t = (s - s0) / h + 1: interval + 1 (the end piece)
        i, d = np.divmod(t, 1.0)
        d = d[..., None] ** _POWERS                           # (..., m, 2, 4)
        # (..., m, 2, n); vecdot, not matmul: a loop in numpy, not one BLAS call per contact
        G = np.vecdot(self._coef.take(i.astype(np.intp), axis=0, mode="clip"), d[..., None, :])
        return (G[..., 1, :self._rows].mT * f[..., None, :]) @ G[..., 0, :self._cols]   # sum_j F_j G_r(y_j) G_c(x_j)

    def step(self, points, forces) -> np.ndarray:
        """Advance one dt with normal forces (m,) N at points (m, 2) m (skin frame): (rows, cols) V;
        with envs = E, points (E, m, 2) and forces (E, m): (E, rows, cols) V."""
        if self.check:
            points, forces = self._inputs(points, forces, self.shape[:-2])
        u = self._loads(points, forces).reshape(-1, 1, self._T)
        if self.check:
            self._finite(u)
        if self.diagonal:
            np.multiply(u, self._gc, out=self._urep)
            np.matmul(self._w, self._Z, out=self._out)
            v = self._out.real.copy() if not self.sigma else self._out.real + self._draw()
            self._modes *= self._lam
            self._modes += self._urep
        else:
            np.multiply(u, self.g, out=self._urep)
            np.matmul(self._M, self._Z, out=self._Znew)
            self._Z, self._Znew = self._Znew, self._Z
            n = self._Z.shape[1] - 1
            v = self._Z[:, n:].copy() if not self.sigma else self._Z[:, n:] + self._draw()
            self._urep = self._Z[:, n:]
        return self._output(v).reshape(self.shape)

    def _draw(self) -> np.ndarray:
        """The next step's noise (envs, 1, taxels) V, from blocks of `block` steps."""
        if self._k == len(self._noise):
            self._noise = self.sigma * self.rng.standard_normal((self.block, *self._noise.shape[1:]))
            self._k = 0
        self._k += 1
        return self._noise[self._k - 1][:, None, :]

    def _draws(self, nt: int) -> np.ndarray:
        """The next nt steps' noise (nt, envs, taxels) V: the same numbers nt calls of _draw give."""
        parts = []
        while nt:
            if self._k == len(self._noise):
                self._noise = self.sigma * self.rng.standard_normal((self.block, *self._noise.shape[1:]))
                self._k = 0
            take = min(nt, len(self._noise) - self._k)
            parts.append(self._noise[self._k:self._k + take])
            self._k, nt = self._k + take, nt - take
        return np.concatenate(parts)

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
        """A whole history from the current state: points (nt, [E,] m, 2), forces (nt, [E,] m)
        -> (nt, [E,] rows, cols) V; the same voltages (and noise) as nt calls of `step`, for
        contacts known ahead (a recorded or scripted trajectory, a data set): the loads of
        all steps are one vectorized evaluation and, in the diagonal form, the dynamics a
        convolution per block of steps (`_block`) instead of a loop over steps."""
        forces = np.asarray(forces, float)
        points, forces = self._inputs(points, forces, (len(forces), *self.shape[:-2]))
        nt = len(forces)
        U = self._loads(points, forces).reshape(nt, -1, self._T) * self.g          # (nt, E, taxels)
        self._finite(U)
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
        lam, w, D = self._lam[:, 0], self._w[0, :-1], self._w[0, -1].real
        Pk = lam[None, :] ** np.arange(L + 1)[:, None]                              # (L + 1, n): lambda^k (0^0 = 1)
        h = np.empty(L)
        h[0] = D
        h[1:] = (Pk[:L - 1] @ w).real
        N = 2 * L
        V = np.fft.irfft(np.fft.rfft(U, N, axis=0) * np.fft.rfft(h, N)[:, None, None], N, axis=0)[:L]
        z0 = self._modes                                                            # (E, n, T)
        if z0.any():                                                                # the free response
            V += (Pk[:L] @ (w[:, None] * z0)).real.transpose(1, 0, 2)
        R = np.ascontiguousarray(Pk[L - 1::-1].T)                                   # (n, L): lambda^(L-1-j)
        U2 = U.reshape(L, E * T)                                                    # real: two real products
        ends = (R.real @ U2 + 1j * (R.imag @ U2)).reshape(-1, E, T).transpose(1, 0, 2)
        z0 *= Pk[L][:, None]
        z0 += ends
        return V
