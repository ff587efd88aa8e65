r"""Transient heat conduction through the layers of a tagged mesh, with Robin surfaces.

Strong form, in every region with its own conductivity k (W/(m K)), density rho
(kg/m^3) and specific heat c (J/(kg K)):

    rho c dT/dt = div(k grad T)                         in the body,
    -k grad T . n = h_j (T - T_j(t))                    on surface j (a facet set),
    -k grad T . n = 0                                   elsewhere (the axis, a mirror plane),

with h_j a contact conductance (a warm finger on its footprint) or a convection
coefficient (air on the rest), W/(m^2 K). Weak form: for every test function v,

    int_V rho c (dT/dt) v dV + int_V k grad T . grad v dV + sum_j int_Gj h_j T v dS
        = sum_j int_Gj h_j T_j(t) v dS,

dV and dS taken in 3D: the plane models' depth and the axisymmetric 2 pi r
(fem.constitution's kinematics `measure`, the same as the mechanics). Units: every
term is W (J/s) per unit test function. Discretized with continuous P1/P2 (or Q1/Q2
on hexahedra) on the mechanics' mesh:

    M dT/dt + (K + H(t)) T = f(t),     M = int rho c N N,  K = int k grad N grad N,
    H = sum_j h_j int_Gj N N,          f = sum_j h_j T_j(t) int_Gj N.

Time: the theta method, (M + theta dt A) T1 = (M - (1 - theta) dt A) T0 + dt (theta f1 +
(1 - theta) f0) with A = K + H; theta = 1 backward Euler (first order, L-stable), 1/2
Crank-Nicolson (second order) started by Rannacher's four backward-Euler quarter steps
so that the jump of a step load does not ring. One factorization per set of surfaces
(the contact on, then off) and step size.

Energy: 1^T K = 0, so 1^T M (T_n - T_0) = sum over steps of dt 1^T (theta (f - H T)_1 +
(1 - theta) (f - H T)_0), the heat that crossed the surfaces by the same rule:
`Conduction.heat_in` is that sum, and the balance holds to round-off (tests).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu
from skfem import (BilinearForm, Basis, ElementHex1, ElementHex2, ElementTetP1, ElementTetP2, ElementTriP1,
                   ElementTriP2, FacetBasis, LinearForm, MeshHex, MeshTet)

from taxel.fem.constitution import Kinematics


@dataclass(frozen=True)
class Surface:
    """A Robin condition on facets: conductance h (W/(m^2 K)) to a temperature history
    T(t) (K), active while `active(t)` (always when None)."""

    facets: np.ndarray
    h: float
    temperature: Callable[[float], float]
    active: Callable[[float], bool] | None = None

    def on(self, t: float) -> bool:
        return self.active is None or bool(self.active(t))


@dataclass(frozen=True)
class Heat:
    """The heat a region holds and conducts: conductivity k (W/(m K)) and volumetric heat
    capacity rho c (J/(m^3 K))."""

    conductivity: float
    capacity: float


@dataclass
class Conduction:
    """A temperature history: nodal temperatures T (nt, n) at times t, and the heat in
    through the surfaces up to each time (J, `heat_in`), with the model it came from."""

    t: np.ndarray
    T: np.ndarray
    heat_in: np.ndarray
    model: "ThermalModel" = field(repr=False)

    def stored(self) -> np.ndarray:
        """The heat stored since the start, int rho c (T - T(0)) dV (J), at each time."""
        return (self.T - self.T[0]) @ self.model.M_ones


class ThermalModel:
    """M, K and the surfaces' matrices of a mesh whose regions carry `Heat`.

    mesh: a scikit-fem mesh; regions: name -> element indices; heat: region name -> Heat
    (every element must be in exactly one region); kinematics: the measure (depth, 2 pi r);
    order 1 or 2."""

    def __init__(self, mesh, regions: dict, heat: dict, kinematics: Kinematics, order: int = 2):
        self.mesh, self.kinematics = mesh, kinematics
        self.element = _element(mesh, order)
        self.basis = Basis(mesh, self.element)
        n = self.basis.N
        covered = np.zeros(mesh.t.shape[1], int)
        M, K = sp.csr_matrix((n, n)), sp.csr_matrix((n, n))
        for name, cells in regions.items():
            if name not in heat:
                raise ValueError(f"region '{name}' has no thermal properties")
            h = heat[name]
            if not (h.conductivity > 0 and h.capacity > 0):
                raise ValueError(f"region '{name}': conductivity and heat capacity must be positive")
            covered[cells] += 1
            b = Basis(mesh, self.element, elements=cells)
            M = M + _mass(kinematics, h.capacity).assemble(b)
            K = K + _stiffness(kinematics, h.conductivity).assemble(b)
        if (covered != 1).any():
            raise ValueError(f"{int((covered != 1).sum())} elements are in no region or in two")
        self.M, self.K = M.tocsc(), K.tocsc()
        self.M_ones = np.asarray(self.M @ np.ones(n)).ravel()      # int rho c N_i dV
        self._face = {}

    @property
    def n(self) -> int:
        return self.basis.N

    def surface(self, facets: np.ndarray):
        """(int N N dS, int N dS) on facets, cached by their indices."""
        key = np.asarray(facets).tobytes()
        if key not in self._face:
            fb = FacetBasis(self.mesh, self.element, facets=np.asarray(facets))
            self._face[key] = (_mass(self.kinematics, 1.0).assemble(fb).tocsc(),
                               np.asarray(_load(self.kinematics).assemble(fb)).ravel())
        return self._face[key]

    def volume_load(self, cells: np.ndarray) -> np.ndarray:
        """int_V N_i dV over the elements `cells` (an integral of a nodal field is w . T)."""
        return np.asarray(_load(self.kinematics).assemble(Basis(self.mesh, self.element, elements=cells))).ravel()

    def probe(self, points) -> sp.csr_matrix:
        """P with T(points) = P @ T; points (dim, np) in the mesh's coordinates."""
        return self.basis.probes(np.asarray(points, float))

    def nodes(self) -> np.ndarray:
        """The coordinates of the DOFs (dim, n): vertices then edge midpoints for P2."""
        return self.basis.doflocs


def conduct(model: ThermalModel, t: np.ndarray, surfaces: list[Surface], initial: float,
            theta: float = 0.5) -> Conduction:
    """Temperatures on the time grid `t` (uniform steps) from a uniform `initial` (K)."""
    t = np.asarray(t, float)
    dt = np.diff(t)
    if len(t) < 2 or not np.allclose(dt, dt[0], rtol=1e-9, atol=0):
        raise ValueError("the time grid must have at least two points, evenly spaced")
    if not 0.5 <= theta <= 1:
        raise ValueError(f"theta = {theta} must be in [1/2, 1] (unconditionally stable)")
    dt = float(dt[0])
    T = np.empty((len(t), model.n))
    T[0] = initial
    heat = np.zeros(len(t))
    lu = {}

    def operators(tk):
        on = tuple(s.on(tk) for s in surfaces)
        H = sp.csc_matrix((model.n, model.n))
        for s, a in zip(surfaces, on):
            if a:
                H = H + s.h * model.surface(s.facets)[0]
        return on, H

    def rhs(tk, on):
        f = np.zeros(model.n)
        for s, a in zip(surfaces, on):
            if a:
                f += s.h * s.temperature(tk) * model.surface(s.facets)[1]
        return f

    def step(T0, t0, h, th):
        on0, H0 = operators(t0)
        on1, H1 = operators(t0 + h)        # the surfaces at the step's end (implicit side)
        key = (on1, h, th)
        if key not in lu:
            lu[key] = splu((model.M + th * h * (model.K + H1)).tocsc())
        f0, f1 = rhs(t0, on0), rhs(t0 + h, on1)
        b = model.M @ T0 - (1 - th) * h * ((model.K + H0) @ T0) + h * (th * f1 + (1 - th) * f0)
        T1 = lu[key].solve(b)
        q = h * (th * (f1.sum() - (H1 @ T1).sum()) + (1 - th) * (f0.sum() - (H0 @ T0).sum()))
        return T1, q

    for k in range(len(t) - 1):
        if theta < 1 and k < 2:            # Rannacher: the first two steps as four backward-Euler half steps
            Tk, q = T[k], 0.0
            for j in range(2):
                Tk, dq = step(Tk, t[k] + j * dt / 2, dt / 2, 1.0)
                q += dq
            T[k + 1], heat[k + 1] = Tk, heat[k] + q
            continue
        T[k + 1], q = step(T[k], t[k], dt, theta)
        heat[k + 1] = heat[k] + q
    return Conduction(t, T, heat, model)


def _element(mesh, order):
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order}")
    if isinstance(mesh, MeshHex):
        return ElementHex2() if order == 2 else ElementHex1()
    if isinstance(mesh, MeshTet):
        return ElementTetP2() if order == 2 else ElementTetP1()
    return ElementTriP2() if order == 2 else ElementTriP1()


def _mass(kin, coefficient):
    @BilinearForm
    def form(u, v, w):
        return coefficient * u * v * kin.measure(w.x)
    return form


def _stiffness(kin, k):
    @BilinearForm
    def form(u, v, w):
        return k * sum(u.grad[i] * v.grad[i] for i in range(u.grad.shape[0])) * kin.measure(w.x)
    return form


def _load(kin):
    @LinearForm
    def form(v, w):
        return v * kin.measure(w.x)
    return form
