"""The skin file: everything a simulator needs of a designed taxel array (numpy only).

Frame: the skin's surface plane, x along the columns, y along the rows, in metres
from taxel (0, 0)'s centre; taxel (r, c) is centred at (c pitch, r pitch).

The sensor model (built by taxel.skin.build from the FEM, the module docstring there
derives it): a normal force F_j(t) at the point p_j = (x_j, y_j) of the surface drives
taxel (r, c) through the separable influence of taxel.analyses.surface.influence,

    u_rc(t) = g_rc * sum_j F_j(t) G_r(y_j) G_c(x_j)          (N, the force "seen" by the taxel)
    v_rc    = h(s) u_rc                                      (V, the readout's output)

G_c the influence function of column c (1 at its own centre), a cubic spline stored
as its piecewise coefficients (`knots`, `coef`); g_rc = S_r S_c / S_ref^2 the taxels'
sensitivities relative to the reference taxel's S_ref; h the reference taxel's path
from a force on its footprint to its readout output (the reduced FEM model,
`taxel reduce`), discretized at the skin's step `dt` (first-order hold, exact for
forces linear between steps) as x[k+1] = Ad x[k] + Bd u[k], v[k] = Cd x[k] + Dd u[k].
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

FORMAT = "taxel-skin/1"

_POWERS = np.array([3.0, 2.0, 1.0, 0.0])
_ARRAYS = ("knots", "coef", "gain", "Ad", "Bd", "Cd", "Dd", "A", "B", "C", "D", "noise_freqs", "noise_psd",
           "check_x", "check_G_fem", "check_G_spline")


@dataclass
class SkinModel:
    """A skin's sensor model (module docstring); `save`/`load` as .npz."""

    rows: int
    cols: int
    pitch: float                 # m, taxel centre to centre
    taxel_width: float           # m
    margin: float                # m, silicone beyond the outer taxels' edges
    knots: np.ndarray            # (m,) m, the influence spline's breakpoints (the FEM press positions)
    coef: np.ndarray             # (4, m-1, n) cubic coefficients of G_c on each interval (scipy PPoly layout)
    gain: np.ndarray             # (rows, cols) g_rc, relative sensitivities
    sensitivity: float           # V/N, S_ref: the reference taxel's open-circuit voltage per newton on its centre
    dt: float                    # s, the step Ad..Dd are discretized at
    Ad: np.ndarray
    Bd: np.ndarray
    Cd: np.ndarray
    Dd: np.ndarray
    A: np.ndarray                # the continuous h(s) (V per N), SI
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    noise_freqs: np.ndarray      # (nf,) Hz
    noise_psd: np.ndarray        # (sources, nf) V^2/Hz at the readout output
    noise_sources: list[str]
    saturation: float            # V, the largest |output| before clipping (inf: none)
    adc: dict | None             # {bits, lo, hi, gain, offset} or None (no ADC)
    influence_error: float       # max |G_spline - G_fem| at the check points, of G's peak (1)
    check_x: np.ndarray          # (k,) m, FEM presses between the spline's knots
    check_G_fem: np.ndarray      # (k, n)
    check_G_spline: np.ndarray   # (k, n)
    reduction_error: float       # h's error: the reduced model's against direct FEM solves + its modal cut's
    readout: str                 # the readout chain in words
    provenance: dict = field(default_factory=dict)   # scene (data), scene_sha256, taxel_version, built
    format: str = FORMAT

    @property
    def taxels(self) -> int:
        return self.rows * self.cols

    def centres(self) -> np.ndarray:
        """(rows, cols, 2) m, each taxel's centre (x, y)."""
        r, c = np.meshgrid(np.arange(self.rows), np.arange(self.cols), indexing="ij")
        return np.stack([c * self.pitch, r * self.pitch], axis=-1).astype(float)

    def extent(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) m of the sensor's surface."""
        e = self.taxel_width / 2 + self.margin
        return -e, (self.cols - 1) * self.pitch + e, -e, (self.rows - 1) * self.pitch + e

    def influence(self, s) -> np.ndarray:
        """G_c(s) of every column (the spline; s clipped to the knots' span): (len(s), n).
        The knots are evenly spaced (taxel.analyses.surface.influence samples), so the interval
        is found by division, not by a search."""
        if not hasattr(self, "_pp"):
            k = self.knots
            self._pp = (float(k[0]), float((k[-1] - k[0]) / (len(k) - 1)), len(k) - 1,
                        np.ascontiguousarray(self.coef.transpose(1, 0, 2)))     # (intervals, 4, n)
            if not np.allclose(np.diff(k), self._pp[1], rtol=1e-9, atol=0):
                raise ValueError("skin file: the influence knots are not evenly spaced; rebuild the skin")
        x0, h, m, co = self._pp
        t = np.minimum(np.maximum((np.asarray(s, float) - x0) / h, 0.0), m)
        i = np.minimum(t.astype(np.intp), m - 1)
        powers = ((t - i) * h)[:, None, None] ** _POWERS          # (k, 1, 4): d^3, d^2, d, 1
        return np.matmul(powers, co[i])[:, 0, :]

    def save(self, path):
        """Write the skin as .npz to a path (returned as a Path) or a binary file object."""
        path = path if hasattr(path, "write") else Path(path)
        meta = {k: getattr(self, k) for k in ("rows", "cols", "pitch", "taxel_width", "margin", "sensitivity", "dt",
                                               "noise_sources", "saturation", "adc", "influence_error",
                                               "reduction_error", "readout", "provenance", "format")}
        meta["saturation"] = None if not np.isfinite(self.saturation) else self.saturation
        np.savez_compressed(path, meta=np.array(json.dumps(meta)), **{k: getattr(self, k) for k in _ARRAYS})
        return path

    @classmethod
    def load(cls, path) -> "SkinModel":
        """A skin written by `save`; ValueError (one line) for another file or format."""
        try:
            with np.load(path, allow_pickle=False) as z:
                arrays = {k: z[k] for k in _ARRAYS}
                meta = json.loads(str(z["meta"]))
        except (OSError, ValueError, KeyError) as exc:
            raise ValueError(f"{path}: not a skin file ({exc}); write one with taxel skin SCENE -o FILE.npz") from None
        if meta.get("format") != FORMAT:
            raise ValueError(f"{path}: skin format {meta.get('format')!r}, this taxel reads {FORMAT!r}; "
                             "rebuild it with taxel skin SCENE -o FILE.npz")
        meta["saturation"] = np.inf if meta["saturation"] is None else meta["saturation"]
        return cls(**meta, **arrays)
