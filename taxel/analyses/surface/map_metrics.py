"""Coverage, localization error and crosstalk of a design, from its 3D surface map
(taxel.analyses.surface.surface_map): no 2D section, no separability.

Coverage (the seed, section 2: a wider gap opens non-sensitive regions, where a press
gives no signal). The press: the user's probe footprint (a disc of the probe's radius,
flat or Hertzian pressure) pressed normally with the smallest force of interest F.
Taxel i's open-circuit voltage V_i(x, y) comes from the map (every taxel open, the
linear model: the small-force limit). A press is detected where the best taxel's
|voltage| reaches k sigma, sigma the noise's rms referred to a taxel's open-circuit
voltage, k = SIGMAS = 3:

    margin(x, y) = max_i |V_i(x, y)| / (k sigma)         detected where margin >= 1

The surface judged is the area between the outer taxels' centres (every press there
has a taxel on either side in each direction; beyond it a press is over an outer taxel
or off the sensing area). coverage = the fraction of that area where the press is
detected (on a grid of every map step / 2); the 3D minimum = the smallest margin over
the area, searched on the grid and refined by a bounded local search from the grid's
worst point (on the exact footprint; the grid reads the map averaged over the footprint
once, SurfaceMap.averaged), with its location. Dead zones: where margin < 1. The fraction
is the grid's; a dip below 1 narrower than the grid step shows in the minimum only.

Localization error: the Cramer-Rao bound of an unbiased estimate of (x, y, F) from the
taxels' open-circuit voltages with white noise sigma on each, cov = sigma^2 (J^T J)^-1,
J = dV/d(x, y, F) (central differences of the map, h = map step / 4); the position
error sqrt(cov_xx + cov_yy) over the same area, summarised as its rms, 95th percentile
and worst case.

Crosstalk: SurfaceMap.crosstalk(point, taxel) for any point and taxel; `crosstalk_matrix`
gives each taxel's voltage pressed at every taxel's centre, relative to the pressed one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from taxel.analyses.surface.surface_map import Footprint, SurfaceMap

SIGMAS = 3.0


def sensing_area(m: SurfaceMap) -> tuple[float, float, float, float]:
    """(x0, x1, y0, y1): the area between the outer taxels' centres."""
    c = np.asarray(m.centres)
    return float(c[:, 0].min()), float(c[:, 0].max()), float(c[:, 1].min()), float(c[:, 1].max())


def _grid(m: SurfaceMap, step: float | None):
    x0, x1, y0, y1 = sensing_area(m)
    h = step or 0.5 * float(np.diff(m.x).mean())
    x = np.linspace(x0, x1, max(2, int(np.ceil((x1 - x0) / h)) + 1))
    y = np.linspace(y0, y1, max(2, int(np.ceil((y1 - y0) / h)) + 1))
    return x, y


@dataclass
class MapCoverage:
    """A design's coverage on its 3D map (module docstring)."""

    fraction: float               # of the sensing area where a press is detected
    minimum: float                # the smallest best-taxel margin |V| / (k sigma) over the area (the 3D minimum)
    minimum_at: tuple[float, float]   # m, where it is
    force_N: float
    noise_V: float
    sigmas: float
    footprint: Footprint
    x: np.ndarray                 # (nx,) m, the judged grid
    y: np.ndarray                 # (ny,) m
    margin: np.ndarray            # (ny, nx) best-taxel |V| / (k sigma)

    @property
    def threshold_V(self) -> float:
        return self.sigmas * self.noise_V

    @property
    def dead(self) -> np.ndarray:
        return self.margin < 1.0

    def record(self) -> dict:
        return {"coverage": self.fraction, "minimum_margin": self.minimum,
                "minimum_at_mm": [1e3 * self.minimum_at[0], 1e3 * self.minimum_at[1]], "force_N": self.force_N,
                "noise_V": self.noise_V, "sigmas": self.sigmas, "footprint_radius_m": self.footprint.radius,
                "footprint_profile": self.footprint.profile}


def best_margin(m: SurfaceMap, points, force: float, noise_V: float, footprint: Footprint,
                sigmas: float = SIGMAS) -> np.ndarray:
    """(n,) max_i |V_i| / (k sigma) for a normal press of `force` N over `footprint` at points (n, 2)."""
    return np.abs(m.press(points, force, footprint)).max(axis=1) / (sigmas * noise_V)


def coverage(m: SurfaceMap, force: float, noise_V: float, footprint: Footprint | None = None,
             sigmas: float = SIGMAS, step: float | None = None) -> MapCoverage:
    """The coverage of map `m` for a press of `force` N over `footprint` (default a point
    force) against white noise of rms `noise_V` on each taxel's open-circuit voltage."""
    if not (force > 0 and noise_V > 0 and sigmas > 0):
        raise ValueError(f"coverage needs a positive force, noise and k (got {force}, {noise_V}, {sigmas})")
    if m.centres is None or len(m.taxels) < 2:
        raise ValueError("coverage needs a map of an array of at least two taxels (its centres)")
    fp = footprint or Footprint()
    ma = m.averaged(fp)                   # the footprint's press at every grid point, once
    x, y = _grid(m, step)
    X, Y = np.meshgrid(x, y)
    margin = best_margin(ma, np.column_stack([X.ravel(), Y.ravel()]), force, noise_V, Footprint(), sigmas
                         ).reshape(X.shape)
    i = np.unravel_index(np.argmin(margin), margin.shape)
    x0, x1, y0, y1 = sensing_area(m)
    res = minimize(lambda p: best_margin(m, [np.clip(p, [x0, y0], [x1, y1])], force, noise_V, fp, sigmas)[0],
                   [X[i], Y[i]],
                   method="Nelder-Mead",
                   options={"xatol": 1e-6, "fatol": 1e-9, "maxiter": 200})
    p = np.clip(res.x, [x0, y0], [x1, y1])
    low = float(best_margin(m, [p], force, noise_V, fp, sigmas)[0])
    best, at = (low, (float(p[0]), float(p[1]))) if low < margin[i] else (float(margin[i]), (float(X[i]), float(Y[i])))
    return MapCoverage(float((margin >= 1.0).mean()), best, at, float(force), float(noise_V), float(sigmas), fp,
                       x, y, margin)


@dataclass
class MapLocalization:
    """The predicted position error over the sensing area (module docstring)."""

    rms_m: float
    p95_m: float
    worst_m: float
    worst_at: tuple[float, float]
    force_N: float
    noise_V: float
    x: np.ndarray
    y: np.ndarray
    error_m: np.ndarray           # (ny, nx), NaN where the bound is singular

    def record(self) -> dict:
        return {"localization_error": self.rms_m, "localization_error_p95": self.p95_m,
                "localization_error_worst": self.worst_m,
                "worst_at_mm": [1e3 * self.worst_at[0], 1e3 * self.worst_at[1]]}


def localization(m: SurfaceMap, force: float, noise_V: float, footprint: Footprint | None = None,
                 step: float | None = None) -> MapLocalization:
    """The Cramer-Rao position error of map `m` (module docstring)."""
    if not (force > 0 and noise_V > 0):
        raise ValueError(f"localization needs a positive force and noise (got {force}, {noise_V})")
    fp = footprint or Footprint()
    ma = m.averaged(fp)
    x, y = _grid(m, step)
    X, Y = np.meshgrid(x, y)
    P = np.column_stack([X.ravel(), Y.ravel()])
    h = 0.25 * float(np.diff(m.x).mean())
    V = ma.press(P, force)
    dx = (ma.press(P + [h, 0], force) - ma.press(P - [h, 0], force)) / (2 * h)
    dy = (ma.press(P + [0, h], force) - ma.press(P - [0, h], force)) / (2 * h)
    J = np.stack([dx, dy, V / force], axis=2)                     # (n, ntaxels, 3): V is linear in F
    JTJ = np.einsum("nti,ntj->nij", J, J)
    err = np.full(len(P), np.nan)
    ok = np.linalg.cond(JTJ) < 1e14
    cov = noise_V ** 2 * np.linalg.inv(JTJ[ok])
    err[ok] = np.sqrt(np.clip(cov[:, 0, 0] + cov[:, 1, 1], 0, None))
    e = err[np.isfinite(err)]
    if not len(e):
        raise ValueError("the Cramer-Rao bound is singular everywhere: the taxels' voltages do not depend on position")
    k = int(np.nanargmax(err))
    return MapLocalization(float(np.sqrt(np.mean(e ** 2))), float(np.percentile(e, 95)), float(e.max()),
                           (float(P[k, 0]), float(P[k, 1])), float(force), float(noise_V), x, y,
                           err.reshape(X.shape))


def crosstalk_matrix(m: SurfaceMap, footprint: Footprint | None = None) -> np.ndarray:
    """(ntaxels, ntaxels): row i, taxel j's open-circuit voltage pressed at taxel i's centre,
    relative to taxel i's own (signed; 1 on the diagonal)."""
    V = m.press(np.asarray(m.centres), 1.0, footprint)
    return V / np.diag(V)[:, None]
