"""The skin at the simulator's step: contact forces and points -> each taxel's voltage.

Numpy only (no FEM, no simulator): any simulator that can list the normal contact
forces on the skin body and their points in the skin's frame calls

    skin = SkinRuntime(SkinModel.load("skin.npz"), noise=True, seed=0)
    v = skin.step(points, forces)      # every dt: points (m, 2) in m, forces (m,) in N -> (rows, cols) V

The model (taxel.skin.model): u_rc = g_rc sum_j F_j G_r(y_j) G_c(x_j), then each taxel's
state x_rc advances through the discretized readout dynamics, v = Cd x + Dd u. All
taxels share Ad, which is block diagonal (the modal form of taxel.skin.build, real
poles and 2 x 2 blocks of complex pairs, kept by the exponential), so the states of
all taxels advance as x_i <- a_i x_i + up_i x_(i+1) + low_i x_(i-1), elementwise on a
(states, taxels) array; a dense product when a file's Ad is not tridiagonal.

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


class SkinRuntime:
    """A skin's state between simulator steps (module docstring)."""

    def __init__(self, model: SkinModel, noise: bool = False, seed: int | None = None, dt: float | None = None):
        if dt is not None and abs(dt - model.dt) > 1e-9 * model.dt:
            raise ValueError(f"dt = {dt:g} s: this skin is discretized at {model.dt:g} s; rebuild it with "
                             f"taxel skin SCENE --dt {dt:g} or step the simulator at {model.dt:g} s")
        self.model = model
        self.Ad, self.Bd = model.Ad, model.Bd[:, 0][:, None]
        self.Cd, self.Dd = model.Cd[0], float(model.Dd[0, 0])
        self.g = model.gain.ravel()
        self.shape = (model.rows, model.cols)
        self.sigma = self.noise_rms() if noise else 0.0
        self.rng = np.random.default_rng(seed)
        a = model.adc
        self.adc = None if a is None else (a["gain"], a["offset"], a["lo"], (a["hi"] - a["lo"]) / 2 ** a["bits"],
                                           2 ** a["bits"] - 1)
        self.x = np.zeros((model.Ad.shape[0], model.taxels))
        A = model.Ad
        self.tridiagonal = np.array_equal(A, np.diag(np.diag(A)) + np.diag(np.diag(A, 1), 1) + np.diag(np.diag(A, -1), -1))
        self.main = np.diag(A)[:, None].copy()
        self.up, self.low = np.diag(A, 1)[:, None].copy(), np.diag(A, -1)[:, None].copy()

    def noise_rms(self) -> float:
        """V rms per taxel and step: the PSDs integrated up to 1 / (2 dt) (module docstring)."""
        f = self.model.noise_freqs
        hi = min(0.5 / self.model.dt, f[-1])
        keep = f <= hi
        total = self.model.noise_psd[:, keep].sum(axis=0)
        return float(np.sqrt(np.trapezoid(total, f[keep]))) if keep.sum() > 1 else 0.0

    def reset(self) -> None:
        self.x[:] = 0.0

    def loads(self, points, forces) -> np.ndarray:
        """u (taxels,) N: the force each taxel sees from normal forces at points."""
        forces = np.asarray(forces, float).reshape(-1)
        if forces.size == 0:
            return np.zeros(self.g.size)
        p = np.asarray(points, float).reshape(-1, 2)
        G = self.model.influence(np.concatenate([p[:, 0], p[:, 1]]))     # one spline call for x and y
        m = len(forces)
        gx, gy = G[:m, :self.model.cols], G[m:, :self.model.rows]
        return ((gy * forces[:, None]).T @ gx).ravel() * self.g

    def step(self, points, forces) -> np.ndarray:
        """Advance one dt with the normal forces (m,) N at points (m, 2) m (skin frame); (rows, cols) V."""
        u = self.loads(points, forces)
        x = self.x
        v = self.Cd @ x + self.Dd * u
        if self.tridiagonal:
            new = self.main * x + self.Bd * u
            if len(x) > 1:
                new[:-1] += self.up * x[1:]
                new[1:] += self.low * x[:-1]
            self.x = new
        else:
            self.x = self.Ad @ x + self.Bd * u
        return self.output(v).reshape(self.shape)

    def output(self, v) -> np.ndarray:
        """Noise, saturation and the ADC applied to clean voltages v."""
        if self.sigma:
            v = v + self.sigma * self.rng.standard_normal(v.shape)
        s = self.model.saturation
        if np.isfinite(s):
            v = np.clip(v, -s, s)
        if self.adc is not None:                 # ADC input gain v + offset, coded, referred back to the output
            gain, offset, lo, lsb, top = self.adc
            code = np.clip(np.round((gain * v + offset - lo) / lsb), 0, top)
            v = (lo + code * lsb - offset) / gain
        return v

    def run(self, points, forces) -> np.ndarray:
        """A whole history: points (nt, m, 2), forces (nt, m) -> (nt, rows, cols) V (from the current state)."""
        return np.stack([self.step(p, f) for p, f in zip(points, forces)])
