r"""Closed forms of transient conduction the thermal FEM is checked against.

* Semi-infinite solid, initially at T0, its surface exchanging heat with a body at Tb
  through a conductance h from t = 0 (Carslaw and Jaeger, Conduction of Heat in
  Solids, 2nd ed., 1959, sec. 2.7, eq. (1)): with a = x / (2 sqrt(alpha t)), H = h / k,

      (T - T0) / (Tb - T0) = erfc(a) - exp(H x + H^2 alpha t) erfc(a + H sqrt(alpha t)),

  written with erfcx for large arguments: exp(Hx + H^2 alpha t) erfc(a + b) =
  exp(-a^2) erfcx(a + b), b = H sqrt(alpha t). h -> infinity: the step surface
  temperature, erfc(a).
* Two-layer slab: layer 1 (top, thickness L1) on layer 2 (L2), bottom insulated, the top
  held at Ts from t = 0, both initially at T0. Separation of variables with the weight
  rho c (a Sturm-Liouville problem with an interface): theta = T - Ts = sum c_n X_n
  exp(-lam_n^2 t), X_n = sin(lam x / sqrt(alpha1)) in layer 1 (x down from the top),
  A_n cos(lam (L1 + L2 - x) / sqrt(alpha2)) in layer 2, with continuity of T and of k dT/dx
  at x = L1:

      (k1 / sqrt(alpha1)) cos(u) cos(v) = (k2 / sqrt(alpha2)) sin(u) sin(v),
      u = lam L1 / sqrt(alpha1),  v = lam L2 / sqrt(alpha2),

  c_n = int rho c theta0 X_n / int rho c X_n^2 (both integrals in closed form).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq
from scipy.special import erfc, erfcx


def semi_infinite(x, t, k, alpha, h=np.inf):
    """(T - T0) / (Tb - T0) at depth x (m), time t (s) > 0; h = inf: the step surface temperature."""
    x, t = np.asarray(x, float), np.asarray(t, float)
    a = x / (2 * np.sqrt(alpha * t))
    if np.isinf(h):
        return erfc(a)
    b = (h / k) * np.sqrt(alpha * t)
    return erfc(a) - np.exp(-a ** 2) * erfcx(a + b)


def two_layer_film_mean(t, L1, k1, c1, L2, k2, c2, terms=400):
    """(T - T0) / (Ts - T0), the mean over layer 2 (the film at the bottom) at times t (s);
    c1, c2: volumetric heat capacities rho c (J/(m^3 K))."""
    t = np.atleast_1d(np.asarray(t, float))
    a1, a2 = k1 / c1, k2 / c2
    s1, s2 = np.sqrt(a1), np.sqrt(a2)

    def F(lam):
        u, v = lam * L1 / s1, lam * L2 / s2
        return (k1 / s1) * np.cos(u) * np.cos(v) - (k2 / s2) * np.sin(u) * np.sin(v)

    period = min(np.pi * s1 / L1, np.pi * s2 / L2)       # the grid resolves each half-period of F
    grid = np.linspace(1e-9, terms * period, terms * 200)
    f = F(grid)
    roots = [brentq(F, grid[i], grid[i + 1], xtol=1e-14) for i in np.flatnonzero(np.sign(f[:-1]) != np.sign(f[1:]))]
    mean = np.zeros_like(t)
    for lam in roots:
        u, v = lam * L1 / s1, lam * L2 / s2
        A = (np.sin(u) / np.cos(v) if abs(np.cos(v)) > abs(np.sin(v))
             else (k1 / s1) * np.cos(u) / ((k2 / s2) * np.sin(v)))
        norm = c1 * (L1 / 2 - s1 * np.sin(2 * u) / (4 * lam)) + c2 * A ** 2 * (L2 / 2 + s2 * np.sin(2 * v) / (4 * lam))
        proj = c1 * (s1 / lam) * (1 - np.cos(u)) + c2 * A * (s2 / lam) * np.sin(v)    # int rho c X_n (theta0 = 1)
        film = A * (s2 / lam) * np.sin(v) / L2                                         # mean of X_n over layer 2
        mean += (proj / norm) * film * np.exp(-lam ** 2 * t)
    return 1.0 - mean            # theta / theta0 = mean; (T - T0) / (Ts - T0) = 1 - theta / theta0
