r"""The skin's spatial model W (taxels, 3, ny, nx): the load each taxel sees per newton of
a point force along x, y, z at each point of an evenly spaced grid of the surface
(taxel.skin.model), from the 3D surface map or from a 2D section.

From the 3D surface map (`from_map`; taxel.analyses.surface.surface_map, issue 54). The map
gives every taxel's short-circuit charge Q_kd(p) per newton along d at p (C/N, z the
outward normal, its origin at the array's centre, its rows numbered from +y down). The
skin's h is a path "per newton on the reference taxel's footprint" (taxel.skin.build),
so W is that charge over the path's own static charge per newton of such a press,
Qp_path (what the charge amplifier and the resistor integrate):

    W_kd(p) = Q_kd(p) / Qp_path            (a press on the reference footprint: u = Qp_3D / Qp_path)

and, for an open-circuit readout, the open-circuit voltages V = -C^-1 Q (every taxel
open, the map's capacitance matrix) over the path's Vp_path. Non-separable, with both
shear components. Frames: the skin's origin is taxel (0, 0)'s centre and its row r lies
at y = r pitch, so the skin's row r is the scene's (and the map's) row rows - 1 - r
(the scene numbers rows from +y down); x_skin = x_map + (cols - 1) pitch / 2,
y_skin = y_map + (rows - 1) pitch / 2, z alike (a right-handed frame kept).
The skin samples the map's bicubic spline on the map's grid halved (or on the map's
grid itself where the halved table would pass TABLE_BYTES: an 8 x 8 array), and
interpolates bilinearly between its points; its error is measured at every cell's centre
against the map's bicubic spline there (`influence_error`, of the largest |W_z|).

From a 2D section (`separable`, the skin before the map): W_rc,z(x, y) = -g_rc G_r(y) G_c(x)
with G the row's influence from static FEM presses of a taxel-wide flat probe
(taxel.analyses.surface.influence), g_rc = S_r S_c / S_ref^2; shear columns zero. Sampled on a
grid of pitch / (2 per_pitch); its check is `checks` FEM presses between the knots.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from taxel.schema import electrode_name

TABLE_BYTES = 64e6            # the map's grid halved (its bicubic spline sampled) while the table stays below this


@dataclass(frozen=True)
class Spatial:
    grid_x: np.ndarray
    grid_y: np.ndarray
    W: np.ndarray                # (taxels, 3, ny, nx)
    label: str
    check_points: np.ndarray     # (k, 2) m, skin frame
    check_source: np.ndarray     # (k, taxels) W_z from the source
    error: float                 # of max |W_z|
    solves: int = 0


def bilinear(grid_x, grid_y, W, points) -> np.ndarray:
    """(k, taxels, 3) W at points (k, 2), bilinear (the runtime's rule, for checks)."""
    p = np.atleast_2d(points)
    tx = np.clip((p[:, 0] - grid_x[0]) / (grid_x[1] - grid_x[0]), 0, len(grid_x) - 1)
    ty = np.clip((p[:, 1] - grid_y[0]) / (grid_y[1] - grid_y[0]), 0, len(grid_y) - 1)
    i, j = np.minimum(tx.astype(int), len(grid_x) - 2), np.minimum(ty.astype(int), len(grid_y) - 2)
    a, b = (tx - i)[:, None, None], (ty - j)[:, None, None]
    Wt = np.moveaxis(W, (2, 3), (0, 1))                                  # (ny, nx, T, 3)
    return ((1 - a) * (1 - b) * Wt[j, i] + a * (1 - b) * Wt[j, i + 1] + (1 - a) * b * Wt[j + 1, i]
            + a * b * Wt[j + 1, i + 1])


def footprint_average(m, taxel: str, half: float, n: int = 8) -> np.ndarray:
    """(taxels, 3) the map's charge per newton averaged over a square footprint of
    half-width `half` on `taxel` (Gauss-Legendre n x n)."""
    t, w = np.polynomial.legendre.leggauss(n)
    cx, cy = m.centres[m.index(taxel)]
    X, Y = np.meshgrid(cx + half * t, cy + half * t)
    R = m.response(np.stack([X.ravel(), Y.ravel()], axis=1))            # (n n, taxels, 3)
    return np.einsum("qtk,q->tk", R, np.outer(w, w).ravel() / 4)


def from_map(m, rows: int, cols: int, pitch: float, taxel_width: float, per_newton: float,
             voltage: bool) -> Spatial:
    """W from a SurfaceMap (module docstring); per_newton the path's static charge (C/N) or,
    with `voltage`, its open-circuit voltage (V/N) per newton pressing its footprint."""
    order = [m.index(electrode_name(rows - 1 - r, c)) for r in range(rows) for c in range(cols)]
    T = len(order)
    refine = 2 if (2 * len(m.x)) * (2 * len(m.y)) * 3 * T * 8 <= TABLE_BYTES else 1
    xs = np.linspace(m.x[0], m.x[-1], refine * (len(m.x) - 1) + 1)
    ys = np.linspace(m.y[0], m.y[-1], refine * (len(m.y) - 1) + 1)
    X, Y = np.meshgrid(xs, ys)
    Q = m.response(np.stack([X.ravel(), Y.ravel()], axis=1))[:, order]          # (ny nx, T, 3), skin order
    Q = Q.reshape(len(ys), len(xs), T, 3).transpose(2, 3, 0, 1)                  # (T, 3, ny, nx)
    if voltage:
        Ci = np.linalg.inv(m.capacitance[np.ix_(order, order)])
        Q = -np.einsum("kl,ldyx->kdyx", Ci, Q)
    W = Q / per_newton
    gx, gy = xs + (cols - 1) * pitch / 2, ys + (rows - 1) * pitch / 2
    # the check: every cell's centre, the map's bicubic spline against the bilinear table
    cx, cy = 0.5 * (gx[1:] + gx[:-1]), 0.5 * (gy[1:] + gy[:-1])
    X, Y = np.meshgrid(cx, cy)
    pts = np.stack([X.ravel(), Y.ravel()], axis=1)
    R = m.response(pts - [(cols - 1) * pitch / 2, (rows - 1) * pitch / 2])[:, order]     # (k, T, 3)
    if voltage:
        R = -np.einsum("kl,qld->qkd", Ci, R)
    src = R / per_newton
    lin = bilinear(gx, gy, W, pts)
    err = float(np.abs(lin - src).max() / np.abs(W[:, 2]).max())
    sel = np.argsort(-np.abs(lin - src).max(axis=(1, 2)))[:16]            # the worst cells kept as the record
    return Spatial(gx, gy, W, f"3D surface map ({m.info.get('scene', '')}, grid {1e3 * (gx[1] - gx[0]):.3g} mm; "
                   "normal and shear, non-separable)", pts[sel], src[sel, :, 2], err,
                   int(m.info.get("right_hand_sides", 0)))


def separable(rows: int, cols: int, pitch: float, infl, per_pitch: int, check_x=None, G_fem=None) -> Spatial:
    """W from a 2D section's influence `infl` (module docstring); check_x, G_fem: FEM presses
    on the middle row (taxel.skin.build.influence_check)."""
    S = np.asarray(infl.sensitivity, float)
    mid = cols // 2
    g = np.outer(S[:rows], S) / S[mid] ** 2
    sp = CubicSpline(infl.x, infl.G, axis=0)
    h = pitch / (2 * per_pitch)
    lo, hi = float(infl.x[0]), float(infl.x[-1])
    grid = np.linspace(lo, hi, int(round((hi - lo) / h)) + 1)
    G = sp(grid)                                                           # (n, cols)
    W = np.zeros((rows * cols, 3, len(grid), len(grid)))
    W[:, 2] = -np.einsum("rc,yr,xc->rcyx", g, G[:, :rows], G[:, :cols]).reshape(rows * cols, len(grid), len(grid))
    pts = np.zeros((0, 2))
    src = np.zeros((0, rows * cols))
    err = float("nan")
    if check_x is not None and len(check_x):
        y = mid * pitch
        pts = np.stack([check_x, np.full(len(check_x), y)], axis=1)
        gy = sp(y)[:rows]
        src = -(g[None] * gy[None, :, None] * G_fem[:, None, :cols]).reshape(len(check_x), -1)
        err = float(np.abs(bilinear(grid, grid, W, pts)[..., 2] - src).max() / np.abs(W[:, 2]).max())
    return Spatial(grid, grid, W, f"2D section, separable (normal only; grid {1e3 * h:.3g} mm)", pts, src, err,
                   int(infl.solves))
