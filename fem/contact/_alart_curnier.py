r"""Frictionless and Coulomb contact as one nonsmooth equation: the Alart-Curnier
augmented-Lagrangian conditions, solved with the displacements by a semi-smooth Newton
method (Alart and Curnier 1991, Comput. Methods Appl. Mech. Eng. 92:353; Hueeber,
Stadler and Wohlmuth 2008, SIAM J. Sci. Comput. 30:572).

Unknowns: the reduced displacements, pressures and potentials y (x = P y) and, at every
contact point p (a node of the top surface in 3D, fem.contact's "nodal" rule, its copies in
the facets around it merged; a Gauss point in 2D), the traction vector lambda_p (Pa, per
reference area) that the indenter exerts on the silicone. With n, g, H = dn/dx the
indenter's normal, gap and curvature at x_p (fem.contact.gap), the anchor a (the point's
position at the last converged load step, moving with the indenter) and a penalty-like
parameter eps (Pa/m; it scales the conditions, it does not regularise them):

    lambda_N = n . lambda,   lambda_T = (I - n n^T) lambda,   s = (I - n n^T)(x - a),
    sigma_N = lambda_N - eps g,   tau = lambda_T - eps s,   b = mu <sigma_N>_+,

    C(x, lambda) = lambda                          (open: sigma_N <= 0)
                 = eps g n + eps s                 (stick: |tau| <= b)
                 = eps g n + lambda_T - b tau/|tau|  (slip)

C = 0 holds exactly the contact conditions g >= 0, lambda_N >= 0, g lambda_N = 0 and
Coulomb's |lambda_T| <= mu lambda_N, with lambda_T = -mu lambda_N s/|s| where the point slips
(s != 0), for any eps > 0. Frictionless is mu = 0 with every closed point slipping. The
weak form is the silicone's equilibrium with the tractions as loads,

    r_u(y, lambda; dv) = A x + R_yeoh(x) - \int lambda . dv dA = 0,
    E(y, lambda) = -(W_p / eps) C_p = 0   per point,   W_p = \sum dA of its copies,

i.e. r_u = A x + R_yeoh - B lambda with B = \int phi^T dA (assembled once, P^T B reduced).
Semi-smooth Newton: the generalized Jacobian of C is taken on the branch the point is on
(open, stick or slip, re-evaluated at every iterate: the primal-dual active set), with
dlambda_N/dx = (H^T lambda)^T, d(lambda_T)/dx = -(n . lambda) H - n (H^T lambda)^T,
ds/dx = P - (n . w) H - n (H^T w)^T (w = x - a), d(g n)/dx = n n^T + g H, and on slip
d(b tau/|tau|) = mu (tau/|tau|) d sigma_N + (b/|tau|)(I - e e^T) d tau (e = tau/|tau|). With
dx_p = W_p^{-1} (B^T dy)_p the Newton system is

    [ K_r                  -B_r             ] [dy     ]   [ -r_u ]
    [ -(1/eps) C_x B_r^T   -(W/eps) C_lambda ] [dlambda] = [ -E   ],

a saddle point: where points stick under the flat (H = 0) C_x = eps I and C_lambda = 0, so
the coupling is -B_r in both places (symmetric); open points are lambda = 0 rows. It is
factorized by PARDISO (fem.linalg.Refactorizer, the nonsymmetric mode where points slip),
scaled as the press's saddle point (fem.linalg.scaling: the multipliers as constraint rows).

Globalisation: a trust region (no Newton step moves a contact point by more than STEP_CAP x the
travel: without it, on a 3D Yeoh block at mu = 0.3, the iterates left the branch after failed
trials and converged to a state with the centre of the top open, 1.6 % off in force), then a
backtracking (Armijo) line search on the merit |D F| of the scaled residual F = (r_u, E), keeping
J > 0 in the Yeoh silicone; chord steps reuse the last factorization while no point changes
branch; the load path (fem.contact.travel, force) cuts the load step where Newton fails and
grows it after easy steps. Multipliers are unknowns only at candidate points (within CANDIDATE x
the travel of the indenter at the start, or carrying a traction; a point outside that closes
adds itself): the others are open, lambda = 0, and cost nothing. Convergence:
|D r_u| / |D B_r lambda| < tol (the press's relative residual) and max |C| / eps (m: the
penetration, or a stuck point's slip) below 1e-3 gap_tol x travel. Stops are PressError:
"inversion" (every step inverts silicone elements), "stagnation" (STALL_STEPS iterations
cutting the merit by less than STALL_CUT in all, or a step's linear solve left above INEXACT),
"iterations", "non-finite": each a failed trial that the load path cuts. A step's linear solve is
PARDISO's with refinement, then, where that stalls above 1e-6 (perturbed pivots of the saddle
point), GMRES preconditioned by the same factors; a residual up to INEXACT is an inexact Newton
step (the line search on the merit keeps it only if it descends; convergence is judged on the
nonlinear residual, so the converged state does not depend on it).

Each load step starts from the last converged multipliers (merged from the press's normal
pressure and tangential multipliers); the converged state is the press's ContactState with
these multipliers, whose augmented tractions equal lambda to the tolerance, so the press's
records, slip zone, re-anchoring and predictor are those of fem.contact's Uzawa path.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from taxel.fem import linalg
from ._friction import Coulomb
from ._geometry import gap
from ._newton import crush_where
from ._records import PressError

STALL_STEPS = 8      # Newton iterations ...
STALL_CUT = 0.5      # ... that cut the merit's root by less than this factor in all: stagnation
CANDIDATE = 0.2      # points within this fraction of the travel of the indenter get multiplier unknowns
CHORD_CUT = 0.25     # a chord step (the last factorization, the same branches) is kept if it cuts the merit so
STEP_CAP = 0.5      # the largest move of a contact point in one Newton step, x the travel
MIN_STEP = 1 / 256   # the line search's shortest step
INEXACT = 1e-2       # a Newton step's linear solve: the largest relative residual kept (an inexact Newton step:
#                      measured on the 3D probe, PARDISO's refinement stalled at 1.5e-5-4.8e-5 on the saddle point)


@dataclass
class Points:
    """The contact points as unknowns: the merge of the surface's (facet, point) copies."""

    first: np.ndarray        # (np,) a copy's flat (facet, point) index per point
    merge: np.ndarray        # (facets * points,) the point of every copy
    W: np.ndarray            # (np,) m^2, summed reference weight
    B: sp.csr_matrix         # (n_reduced, dim np): P^T \int phi^T dA
    Bc: sp.csc_matrix        # the same, by columns (the candidates' columns)
    free: np.ndarray         # (dim, np) bool: the components that move (False: fixed by a symmetry plane
    #                          or the axis, where the traction component is zero by symmetry: lambda_c = 0)


def points(pr) -> Points:
    """The press's contact points (built once per press)."""
    if getattr(pr, "_points", None) is not None:
        return pr._points
    surf, sy = pr.surf, pr.sy
    dim = surf.X.shape[0]
    X = surf.X.reshape(dim, -1)
    scale = 1e-9 * max(float(np.ptp(X)), 1e-300)
    _, first, merge = np.unique(np.round(X / scale).astype(np.int64), axis=1, return_index=True, return_inverse=True)
    merge = merge.ravel()
    dA = surf.dA.ravel()
    W = np.bincount(merge, dA)
    f, q, i, c = np.nonzero(np.abs(surf.phi) > 1e-12)      # phi[f, q, i, c]: local function i at point q
    rows = surf.dofs[f, i] + sy.offsets["u"].start
    cols = dim * merge[f * surf.phi.shape[1] + q] + c
    B = sp.csr_matrix((surf.dA[f, q] * surf.phi[f, q, i, c], (rows, cols)), shape=(sy.A.shape[0], dim * len(W)))
    B = (pr.red.P.T @ B).tocsr()
    free = (np.asarray(abs(B).sum(axis=0)).ravel() > 0).reshape(len(W), dim).T
    pr._points = Points(first, merge, W, B, B.tocsc(), free)
    return pr._points


@dataclass
class Conditions:
    """C, its derivatives and the branch of every point at one state."""

    C: np.ndarray            # (dim, np) Pa
    Cx: np.ndarray           # (dim, dim, np) Pa/m
    Cl: np.ndarray           # (dim, dim, np)
    closed: np.ndarray       # bool (np,)
    stick: np.ndarray        # bool (np,)


def conditions(ind, x, lam, a, z_top, travel, mu, eps, frictionless) -> Conditions:
    """The Alart-Curnier function C and its generalized Jacobian (module docstring) at points x."""
    dim = x.shape[0]
    g, n, H = gap(ind, x, z_top, travel)
    eye = np.eye(dim)[:, :, None]
    outer = lambda u, v: np.einsum("i...,j...->ij...", u, v)           # noqa: E731
    P = eye - outer(n, n)
    lN = (n * lam).sum(axis=0)
    lT = lam - n * lN
    w = x - a
    nw = (n * w).sum(axis=0)
    s = w - n * nw
    Hl = np.einsum("k...,kj...->j...", lam, H)                         # H^T lambda
    Hw = np.einsum("k...,kj...->j...", w, H)
    dlT = -lN * H - outer(n, Hl)
    ds = P - nw * H - outer(n, Hw)
    sig = lN - eps * g
    tau = lT - eps * s
    dsig = Hl - eps * n                                                 # d sigma_N / dx (a row per point)
    dtau = dlT - eps * ds
    closed = sig > 0
    b = mu * np.maximum(sig, 0.0)
    nt = np.sqrt((tau ** 2).sum(axis=0))
    stick = closed & (nt <= b) & (not frictionless)
    slip = closed & ~stick
    e = np.divide(tau, nt, out=np.zeros_like(tau), where=nt > 0)
    q = np.divide(b, nt, out=np.zeros_like(b), where=slip & (nt > 0))        # no overflow where b is large and tau small
    Q = eye - outer(e, e)
    gn = eps * (n * g)
    C = np.where(closed, gn + np.where(stick, eps * s, lT - b * e), lam)
    Cx_n = eps * (outer(n, n) + g * H)
    Cx_slip = Cx_n + dlT - mu * outer(e, dsig) - q * np.einsum("ik...,kj...->ij...", Q, dtau)
    Cl_slip = P - mu * outer(e, n) - q * np.einsum("ik...,kj...->ij...", Q, P)
    Cx = np.where(stick, Cx_n + eps * ds, np.where(slip, Cx_slip, 0.0))
    Cl = np.where(stick, 0.0, np.where(slip, Cl_slip, eye + 0 * Cl_slip))
    return Conditions(C, Cx, Cl, closed, stick)


def _block_diag(blocks):
    """(dim, dim, np) -> the sparse block diagonal (dim np, dim np)."""
    m = blocks.shape[-1]
    return sp.bsr_matrix((np.ascontiguousarray(blocks.transpose(2, 0, 1)), np.arange(m), np.arange(m + 1)),
                         shape=(blocks.shape[0] * m, blocks.shape[0] * m)).tocsr()


def newton(pr, x, d, lam_n, tol=None):
    """(x, contact state, iterations) at equilibrium at travel d: the semi-smooth Newton on
    (y, lambda) from x and the multipliers of the last converged state (module docstring)."""
    o, P, surf = pr.o, pr.red.P, pr.surf
    pts = points(pr)
    dim = surf.X.shape[0]
    eps = pr.eps * o.semismooth_factor / o.penalty_factor
    c = pr._stick                                          # Coulomb state, or None (frictionless)
    mu = 0.0 if c is None else c.mu
    uo = pr.sy.offsets["u"]

    def at_points(u):
        xc = surf.X + np.einsum("fqic,fi->cfq", surf.phi, u[surf.dofs])
        return xc.reshape(dim, -1)[:, pts.first]

    # the starting multipliers: the last converged tractions t_N n + lambda_T at x
    xp = at_points(x[uo])
    _, n0, _ = gap(pr.ind, xp, pr.z_top, d, with_curvature=False)
    lam = np.asarray(lam_n).ravel()[pts.first] * n0
    if c is not None:
        lam = lam + c.lam.reshape(dim, -1)[:, pts.first]
        a = c.anchor(d).reshape(dim, -1)[:, pts.first]
    else:
        a = xp.copy()
    lam = np.where(pts.free, lam, 0.0)
    tol_u = min(o.tol, 1e-3 * o.gap_tol)
    tol_c = 1e-3 * o.gap_tol * max(abs(d), 1e-12)
    fac = getattr(pr, "_ac_factorize", None)
    if fac is None:
        fac = pr._ac_factorize = linalg.Refactorizer(pr.method)
    # the multipliers that are unknowns: the points within CANDIDATE x travel of the indenter at the
    # start or carrying a traction (the others stay open: lambda = 0), more if one closes
    g0 = gap(pr.ind, xp, pr.z_top, d, with_curvature=False)[0]
    cand = (g0 < CANDIDATE * abs(d)) | (np.abs(lam).sum(axis=0) > 0)

    def evaluate(x, lam, tangent=True):
        r, _, _, K = pr._residual(x, d, None, tangent=tangent, contact=False)
        if pr._min_J <= 0 or not np.all(np.isfinite(r)):
            return None
        cd = conditions(pr.ind, at_points(x[uo]), lam, a, pr.z_top, d, mu, eps, c is None)
        if not pts.free.all():            # lambda_c = 0 where a symmetry plane fixes the component
            fr = pts.free
            cd.C = np.where(fr, cd.C, lam)
            cd.Cx = np.where(fr[:, None], cd.Cx, 0.0)
            cd.Cl = np.where(fr[:, None], cd.Cl, np.eye(dim)[:, :, None])
        ru = r - pts.B @ lam.T.ravel()
        E = -(pts.W[sel] / eps) * cd.C[:, sel]
        return ru, E.T.ravel(), cd, K

    def select(cand):
        sel = np.flatnonzero(cand)
        cols = (dim * sel[:, None] + np.arange(dim)).ravel()
        return sel, pts.Bc[:, cols].tocsr(), np.append(pr.red.is_u, np.zeros(len(cols), bool))

    sel, Bs, is_u = select(cand)
    state = evaluate(x, lam)
    if state is None:
        raise PressError("inversion", f"the semi-smooth Newton starts from inverted silicone at travel {d:.4g} m",
                         pr.res, crush_where(pr, x))
    merits, D, last = [], None, None          # last: (branches, solver) of the last factorization

    def jacobian(K, cd):
        return sp.bmat([[K, -Bs], [-(1 / eps) * _block_diag(cd.Cx[..., sel]) @ Bs.T,
                                   -(1 / eps) * _block_diag(cd.Cl[..., sel] * pts.W[sel])]], format="csr")

    def split(dz):
        dl = np.zeros_like(lam)
        dl[:, sel] = dz[n_y:, 0].reshape(len(sel), dim).T
        return P @ dz[:n_y, 0], dl

    n_y = P.shape[1]
    pts_zero = at_points(np.zeros(len(x[uo])))
    for it in range(max(o.max_iter, 40)):
        ru, E, cd, K = state
        if D is None:
            D = linalg.scaling(jacobian(K, cd), is_u)
        Du = D[:n_y]
        rel = np.linalg.norm(Du * ru) / max(np.linalg.norm(Du * (pts.B @ lam.T.ravel())), 1e-300)
        cmax = float(np.abs(cd.C[:, sel]).max(initial=0.0)) / eps
        F = np.concatenate([ru, E])
        merit = np.linalg.norm(D * F)
        pr.trace.append((d, it, rel, int(cd.closed.sum()), "semismooth", cmax, int(cd.stick.sum()), len(sel)))
        if rel < (tol_u if tol is None else min(tol, tol_u)) and cmax <= tol_c:
            if not (cd.closed & ~cand).any():
                return x, _state(pr, x, lam, d, cd, pts), it
            cand = cand | cd.closed                    # a point outside the candidates entered the indenter
            sel, Bs, is_u = select(cand)
            state, merits, D, last = evaluate(x, lam), [], None, None
            continue
        if len(merits) >= STALL_STEPS and merit > STALL_CUT * merits[-STALL_STEPS]:
            raise PressError("stagnation", f"the semi-smooth Newton stagnates at travel {d:.4g} m: {STALL_STEPS} "
                             f"steps cut the residual from {merits[-STALL_STEPS]:.2e} only to {merit:.2e}", pr.res,
                             f"{int(cd.closed.sum())} points closed, {int(cd.stick.sum())} sticking; relative "
                             f"residual {rel:.2e}, largest gap or slip residual {cmax:.3g} m")
        merits.append(merit)
        branches = (cd.closed[sel].tobytes(), cd.stick[sel].tobytes())
        if o.chord and last is not None and last[0] == branches:
            # a chord step: the last factorization (the same branches), kept if it cuts the merit by CHORD_CUT
            dx, dl = split(last[1](-F, rtol=1e-10)[0])
            trial = evaluate(x + dx, lam + dl, tangent=False)
            if trial is not None and np.linalg.norm(D * np.concatenate(trial[:2])) < CHORD_CUT * merit:
                pr.stats["chord_steps"] += 1
                pr.trace[-1] += ("chord",)
                x, lam, state = x + dx, lam + dl, trial
                continue
        if K is None:
            ru, E, cd, K = state = evaluate(x, lam)
        t0 = time.process_time()
        J = jacobian(K, cd)
        solver = fac(J, is_u, D=D)
        last = (branches, solver)
        pr.stats["factorizations"] += 1
        pr.stats["factorize_s"] += time.process_time() - t0
        t0 = time.process_time()
        dz, lres = solver(-F, rtol=1e-10)
        if float(np.max(lres)) > 1e-6:         # perturbed pivots: GMRES preconditioned by the factors
            dz, lres = _krylov(J, D, solver, -F, dz)
        pr.stats["solve_s"] += time.process_time() - t0
        if float(np.max(lres)) > INEXACT:      # an inexact Newton step up to INEXACT (the line search judges it)
            raise PressError("stagnation", f"the semi-smooth Newton's scaled linear solve has a relative residual "
                             f"{float(np.max(lres)):.1e} (> {INEXACT:g}) at travel {d:.4g} m", pr.res)
        dx, dl = split(dz)
        # a trust region on the contact points: no Newton step moves one by more than STEP_CAP x the travel
        move = float(np.abs(at_points(dx[uo]) - pts_zero).max(initial=0.0))
        alpha = min(1.0, STEP_CAP * abs(d) / max(move, 1e-300))
        while True:
            trial = evaluate(x + alpha * dx, lam + alpha * dl, tangent=False)
            if trial is not None:
                m_new = np.linalg.norm(D * np.concatenate(trial[:2]))
                if m_new <= (1 - 1e-4 * alpha) * merit or alpha <= MIN_STEP:
                    break
            elif alpha <= MIN_STEP:
                raise PressError("inversion", f"the semi-smooth Newton inverts silicone elements at travel "
                                 f"{d:.4g} m", pr.res, crush_where(pr, x + alpha * dx))
            alpha /= 2
        pr.trace[-1] += (alpha,)
        x, lam, state = x + alpha * dx, lam + alpha * dl, trial
    raise PressError("iterations", f"the semi-smooth Newton did not converge at travel {d:.4g} m in {it + 1} "
                     "iterations", pr.res, f"relative residual {rel:.2e}, largest gap or slip residual {cmax:.3g} m")


def _krylov(J, D, solver, b, z0, rtol=1e-10, restart=30, maxiter=2):
    """(z, [relative residual]) of J z = b on the scaled system D J D y = D b (z = D y) by
    GMRES from z0, preconditioned by the factorization `solver` (one solve, no refinement):
    where PARDISO perturbed small pivots of the saddle point (measured on Q1/P0 hexahedra,
    frictionless: refinement stalled at 1.5e-5), its factors still precondition well."""
    from scipy.sparse.linalg import LinearOperator, gmres
    n = len(D)
    As = sp.diags(D) @ J @ sp.diags(D)
    bs = D * b
    M = LinearOperator((n, n), matvec=lambda v: solver(np.asarray(v).ravel() / D, rtol=1.0)[0][:, 0] / D)
    y, _ = gmres(As, bs, x0=z0[:, 0] / D, rtol=rtol, atol=0.0, restart=restart, maxiter=maxiter, M=M)
    res = np.linalg.norm(bs - As @ y) / max(np.linalg.norm(bs), 1e-300)
    return (D * y)[:, None], np.array([res])


def _state(pr, x, lam, d, cd, pts):
    """The converged ContactState: the press's augmented-Lagrangian state with lambda as its
    multipliers (its tractions equal lambda to the tolerance)."""
    surf, dim = pr.surf, pr.surf.X.shape[0]
    u = x[pr.sy.offsets["u"]]
    xc = surf.X + np.einsum("fqic,fi->cfq", surf.phi, u[surf.dofs])
    _, n, _ = gap(pr.ind, xc, pr.z_top, d, with_curvature=False)
    lc = lam[:, pts.merge].reshape((dim,) + surf.shape)
    lN = (n * lc).sum(axis=0) * cd.closed[pts.merge].reshape(surf.shape)
    c = pr._stick
    if c is not None:
        c = Coulomb(c.mu, c.a0, lc - n * (n * lc).sum(axis=0), c.slip)
    return surf.state(u, pr.ind, d, lN, pr.eps, stick=c)
