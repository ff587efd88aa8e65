"""The skin runtime's influence table: contact points and forces -> the force each taxel sees,
u_k = sum_j sum_d W_kd(p_j) f_jd (taxel.skin.model's W, bilinear on its grid; numpy only).

Each contact's cell (one scaling, one floor), its four corners' rows of the table W
(one gather: (cells x 3, taxels), or the z plane alone for normal-only forces) and their
weights times the force's components, summed over contacts, corners and directions in one
product. One skin with up to 8 contacts (`few`) finds the cells and weights in Python
floats (a dozen numpy calls cost more than the arithmetic at that size): one gather and
one product.
"""

from __future__ import annotations

import math

import numpy as np


def check_finite(u) -> None:
    """ValueError (one line) unless every value of u is finite."""
    if not np.isfinite(u).all():
        raise ValueError("points or forces not finite: give finite contact points (m) and forces (N)")


class InfluenceTable:
    """W of a SkinModel laid out for gathers: rows cell * 3 + direction (`W3`), and the z
    plane alone, negated (`Wz`: a press F > 0 is f_z = -F)."""

    def __init__(self, model):
        T = model.taxels
        gx, gy = np.asarray(model.grid_x, float), np.asarray(model.grid_y, float)
        for g, name in ((gx, "grid_x"), (gy, "grid_y")):
            if len(g) < 2 or not np.allclose(np.diff(g), (g[-1] - g[0]) / (len(g) - 1), rtol=1e-9, atol=0):
                raise ValueError(f"skin file: {name} is not evenly spaced; rebuild the skin")
        self.nx, self.ny = len(gx), len(gy)
        self.ih = np.array([(len(gx) - 1) / (gx[-1] - gx[0]), (len(gy) - 1) / (gy[-1] - gy[0])])
        self.oih = np.array([gx[0], gy[0]]) * self.ih
        self.stride, self.xyz = np.array([1, len(gx)], dtype=np.intp), np.arange(3)
        self.sgn, self.one = np.array([-1.0, 1.0]), np.array([1.0, 0.0])
        self.scalars = (float(self.ih[0]), float(self.ih[1]), float(self.oih[0]), float(self.oih[1]),
                        len(gx) - 1.0, len(gy) - 1.0, len(gx) - 2, len(gy) - 2, len(gx))
        self.top = np.array([len(gx) - 1.0, len(gy) - 1.0])
        W = np.asarray(model.influence, float).transpose(2, 3, 1, 0)                 # (ny, nx, 3, T)
        self.W3 = np.ascontiguousarray(W.reshape(-1, T))
        self.Wz = np.ascontiguousarray(-W[:, :, 2, :].reshape(-1, T))               # a press F > 0 is f_z = -F
        self.corner = np.array([0, 1, self.nx, self.nx + 1])
        self.last = np.array([len(gx) - 2, len(gy) - 2])

    def loads(self, p, f) -> np.ndarray:
        """sum_j sum_d W_kd(p_j) f_jd (..., T), bilinear (module docstring)."""
        t = p * self.ih
        t -= self.oih                                                                 # grid units
        np.maximum(t, 0.0, out=t)
        np.minimum(t, self.top, out=t)
        i = t.astype(np.intp)
        np.minimum(i, self.last, out=i)                                               # the last cell at the far end
        d = t - i
        cell = (i @ self.stride)[..., None] + self.corner                             # (..., m, 4)
        a = d[..., None] * self.sgn
        a += self.one                                                                  # (..., m, xy, 2): 1 - d, d
        w = a[..., 1, :, None] * a[..., 0, None, :]                                     # (..., m, 2, 2): corners
        lead = p.shape[:-2]
        if f.shape == p.shape[:-1]:                                                      # normal only
            w *= f[..., None, None]
            return (w.reshape(*lead, 1, -1) @ self.Wz.take(cell.reshape(*lead, -1), axis=0))[..., 0, :]
        c = (w[..., None] * f[..., None, None, :]).reshape(*lead, 1, -1)                 # (..., 1, m 4 3)
        rows = (cell[..., None] * 3 + self.xyz).reshape(*lead, -1)
        return (c @ self.W3[rows])[..., 0, :]

    def few(self, p, f, finite: bool = False) -> np.ndarray:
        """`loads` for one skin and a few contacts: the cell and the weights in Python floats
        (cheaper than a dozen numpy calls at this size), then one gather and one product;
        with `finite`, ValueError (one line) unless the points and forces are finite."""
        ihx, ihy, ox, oy, tx_, ty_, lx, ly, nx = self.scalars
        rows, coef, at = [], [], 0.0
        normal = f.ndim == 1
        for (x, y), F in zip(p.tolist(), f.tolist()):
            at += x + y
            tx, ty = x * ihx - ox, y * ihy - oy
            tx = tx if 0.0 <= tx <= tx_ else tx_ if tx > tx_ else 0.0        # clamped; nan -> 0 (checked below)
            ty = ty if 0.0 <= ty <= ty_ else ty_ if ty > ty_ else 0.0
            ix, iy = int(tx), int(ty)
            ix, iy = lx if ix > lx else ix, ly if iy > ly else iy
            dx, dy = tx - ix, ty - iy
            c = iy * nx + ix
            ex, ey = 1.0 - dx, 1.0 - dy
            if normal:
                rows += (c, c + 1, c + nx, c + nx + 1)
                a, b = F * ey, F * dy
                coef += (a * ex, a * dx, b * ex, b * dx)
            else:
                for cc, wc in zip((c, c + 1, c + nx, c + nx + 1), (ex * ey, dx * ey, ex * dy, dx * dy)):
                    rows += (3 * cc, 3 * cc + 1, 3 * cc + 2)
                    coef += (wc * F[0], wc * F[1], wc * F[2])
        if finite and not math.isfinite(sum(coef) + at):   # inf - inf is nan: caught too
            check_finite([np.nan])
        return np.dot(coef, (self.Wz if normal else self.W3).take(rows, axis=0))

