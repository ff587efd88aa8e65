"""The semi-smooth Newton solve of one press equilibrium (fem.contact.Press), at fixed
travel d and multipliers lambda:

    r(x) = A_lin x + R_yeoh(x) + R_c(x; d, lambda) = 0

The contact active set is re-evaluated at every iterate (the tangent consistent,
fem.contact); when a set comes back (`Options.fix_cycling`) Newton finishes on it,
a smooth problem. Each step is a scaled direct solve with the press's factorizer
(fem.linalg.Refactorizer: one PARDISO analysis for the whole press, the symmetric-
indefinite mode on the tangent's upper triangle), then a backtracking line search on
the scaled residual (and J > 0 in the Yeoh silicone).

Convergence: |D r| / |D R_c| < tol, or round-off (the active set unchanged and a
full step changing x by less than 1e-9 relative, with |D r| / |D R_c| < 1e-6: large
graded meshes floor near 1e-8).

Stops, as PressError with its cause (fem.contact.StopCause) and what was measured:
a non-finite state ("non-finite"); the penalty too high, the scaled solve's relative
residual above 1e-6 ("penalty"); elements inverted at every line-search step ("inversion":
where, and the last converged state's smallest J); the active set cycling between two
sets ("cycling"); Newton stagnating ("stagnation": STALL_STEPS steps on one active set
that cut the residual by less than STALL_CUT in all, the line search taking short steps:
a kink the iterates cannot cross, or an unstable state; measured on the 3D press at sizes
/ 0.707, a trial 41 % beyond the last state sat at 0.027 for 20 iterations,
benchmarks/press_3d.py), so that force control bisects at once; and the iteration limit
("iterations").
"""

from __future__ import annotations

import time

import numpy as np

from taxel.fem import hyperelastic
from taxel.fem import linalg
from ._geometry import lateral_distance
from ._records import PressError

STALL_STEPS = 5      # Newton steps on one active set ...
STALL_CUT = 0.5      # ... that cut the residual by less than this factor: stagnation
CHORD_CUT = 0.25     # a chord step (the last factorization) is kept if it cuts the residual by this
SOLVE_RTOL = 1e-10   # a Newton step's linear solve: refinement stops here (1e-13 elsewhere)
TAU0 = 1e-4          # continuation: the smallest pseudo-time shift tried (relative to diag K_uu) ...
TAU_TRIES = 12       # ... raised 4x at a time, at most this often per step
PTC_STEPS = 400      # continuation steps at one travel before it gives up
GROW = 4.0           # ... each step may raise the residual by this factor (leaving a saddle), no more
PATIENCE = 300       # ... and abandoned (a shorter travel step) if the residual is not below its start by then
#                      (the flow from a saddle first climbs: 20 gave up on the 3D press at 0.4 N, 300 took it to 0.69 N)
NEAR = 1e-1          # ... entered where Newton inverts elements only from this close to equilibrium


def newton(pr, x, d, lam, tol=None):
    """(x, contact state, iterations) at equilibrium for travel d and multipliers lam,
    from x; `tol` the scaled relative residual (default Options.tol)."""
    o, P = pr.o, pr.red.P
    tol = o.tol if tol is None else tol
    seen, norms, frozen, fixed, step_rel = [], [], None, None, 1.0
    dx = np.zeros_like(x)           # the last full Newton step (a stagnation message measures it)
    trial, D = None, None          # the line search's accepted residual (r, ref, st) at x; the last scaling
    for it in range(o.max_iter):
        r, ref, st, K = trial + (None,) if trial is not None else pr._residual(x, d, lam, frozen=frozen, fixed=fixed)
        key = st.active.tobytes()
        if o.fix_cycling and fixed is None and o.active_set_update and key in seen[:-1] and key != seen[-1]:
            fixed = st.active.copy()          # the set came back: finish on it (smooth), Uzawa decides
            r, ref, st, K = pr._residual(x, d, lam, fixed=fixed)
        if not o.active_set_update and frozen is None:
            frozen = st.active.copy()
            r, ref, st, K = pr._residual(x, d, lam, frozen=frozen)
        if K is not None and (not np.all(np.isfinite(K.data)) or not np.all(np.isfinite(r))):
            raise PressError("non-finite", f"Newton reached a non-finite state at travel {d:.4g} m", pr.res)
        if K is not None:
            D = linalg.scaling(K, pr.red.is_u)
        # the scaled norm first (after a line search with the last step's scaling): a converged
        # iterate gets no tangent and no factorization
        nr, norm = _scaled_norm(D, r, ref)
        floor = (len(seen) >= 1 and key == seen[-1] and step_rel < 1e-9 and norm < 1e-6)
        if norm < tol or floor:            # floor: a full step with the same active set changed x
            return x, _true_state(pr, x, st, d, lam, fixed), it
        ckey = (key, pr.eps, None if pr._stick is None else pr._stick.key(), fixed is None, frozen is None)
        if o.chord and pr.solver is not None and pr._chord_key == ckey:
            # a chord step: the last factorization (same active set, stick set and penalty), kept if it
            # cuts the residual by CHORD_CUT; else Newton's tangent at this iterate
            t0 = time.process_time()
            dy, _ = pr.solver(-r, rtol=SOLVE_RTOL)
            pr.stats["solve_s"] += time.process_time() - t0
            x_c = x + P @ dy[:, 0]
            tr = pr._residual(x_c, d, lam, tangent=False, frozen=frozen, fixed=fixed)[:3]
            if pr._min_J > 0 and np.all(np.isfinite(tr[0])) and np.linalg.norm(D * tr[0]) < CHORD_CUT * nr:
                pr.stats["chord_steps"] += 1
                seen.append(key)
                norms.append(norm)
                pr.trace.append((d, it, norm, int(st.active.sum()), "chord"))
                step_rel = np.linalg.norm(x_c - x) / max(np.linalg.norm(x), 1e-300)
                x, trial = x_c, tr
                continue
        if K is None:
            r, ref, st, K = pr._residual(x, d, lam, frozen=frozen, fixed=fixed)
            if not np.all(np.isfinite(K.data)) or not np.all(np.isfinite(r)):
                raise PressError("non-finite", f"Newton reached a non-finite state at travel {d:.4g} m", pr.res)
            D = linalg.scaling(K, pr.red.is_u)
            nr, norm = _scaled_norm(D, r, ref)
        if (len(seen) >= STALL_STEPS and len(set(seen[-STALL_STEPS:] + [key])) == 1
                and norm > STALL_CUT * norms[-STALL_STEPS]):
            stall = PressError("stagnation", f"Newton stagnates at travel {d:.4g} m: {STALL_STEPS} steps on "
                                 f"one active set cut the residual from {norms[-STALL_STEPS]:.2e} only to {norm:.2e}",
                                 pr.res, f"line search steps down to 1/64{_stability(pr)}; {_where(pr, st, x, dx)}")
            if not (o.continuation and o.active_set_update):
                raise stall
            x, st, k = continuation(pr, x, d, lam, tol, stall)
            return x, st, it + k
        solver = pr.refactor(K, D, ckey)
        seen.append(key)
        norms.append(norm)
        pr.trace.append((d, it, norm, int(st.active.sum())))
        t0 = time.process_time()
        dy, lres = solver(-r, rtol=SOLVE_RTOL)
        pr.stats["solve_s"] += time.process_time() - t0
        if float(np.max(lres)) > 1e-6:
            raise PressError("penalty", f"penalty too high: the scaled linear solve's relative residual is "
                               f"{float(np.max(lres)):.1e} (> 1e-6, ill-conditioned) with penalty "
                               f"{pr.eps:.3g} Pa/m; lower it", pr.res)
        dx = P @ dy[:, 0]
        alpha = 1.0
        while True:
            x_new = x + alpha * dx
            trial = pr._residual(x_new, d, lam, tangent=False, frozen=frozen, fixed=fixed)[:3]
            r_new = trial[0]
            if pr._min_J > 0:
                if (not o.line_search or alpha <= 1 / 64
                        or np.linalg.norm(D * r_new) < (1 - 1e-4 * alpha) * np.linalg.norm(D * r)):
                    break
            elif not np.all(np.isfinite(r_new)) or alpha <= 1 / 64:
                inverts = PressError("inversion", f"Newton inverts silicone elements at travel {d:.4g} m",
                                       pr.res, crush_where(pr, x_new))
                if not (o.continuation and o.active_set_update) or norm > NEAR:     # far from equilibrium: a shorter travel step
                    raise inverts
                x, st, k = continuation(pr, x, d, lam, tol, inverts)
                return x, st, it + k
            alpha /= 2
        pr.trace[-1] += (alpha,)
        step_rel = alpha * np.linalg.norm(dx) / max(np.linalg.norm(x), 1e-300)
        x = x_new
    last = seen[-6:]
    if len(set(last)) <= 2 and len(set(last)) < len(last) and last[-1] != last[-2]:
        raise PressError("cycling", f"the contact active set cycles between two sets at travel {d:.4g} m: "
                           "keep the active-set update in the tangent, or take smaller travel steps", pr.res,
                           f"{o.max_iter} Newton iterations, residual {norm:.2e}")
    raise PressError("iterations", f"Newton did not converge at travel {d:.4g} m in {o.max_iter} iterations",
                       pr.res, f"residual {norm:.2e}")


def continuation(pr, x, d, lam, tol, stall: PressError):
    r"""Pseudo-transient continuation (Kelley and Keyes 1998, SIAM J. Numer. Anal. 35:508)
    from a stagnating Newton iterate to a stable equilibrium at the same travel: steps

        (K + tau M) dx = -r,   M = diag(K_uu) on the displacements (0 on pressures and potentials),

    i.e. implicit Euler steps of the gradient flow M du/dt = -r_u with the pressures and
    potentials kept in equilibrium, pseudo-time step 1/tau. Each step's tau is the smallest
    of tau_k x 4^j (at least TAU0 once raised) that makes the shifted tangent's inertia that
    of a stable state (as many negative eigenvalues as there are pressure and potential
    unknowns: the condensed displacement stiffness positive definite; PARDISO's
    symmetric-indefinite factorization reports it), keeps J > 0 in the silicone and raises
    the residual by at most GROW; tau then shrinks with the residual (switched evolution
    relaxation, tau <- tau min(1, |r_k| / |r_k-1|), halved after a step its first tau took),
    so the last steps are Newton's. At an unstable state (a frictionless punch's rim, where the material squeezed
    out loses stability: measured on the 3D press at 0.3 N, one negative eigenvalue at the
    stalled iterate) the flow leaves the saddle that Newton was drawn to and settles on the
    stable branch. Its fixed points are the equilibria r = 0: the shift leaves no error.
    The contact active set is re-evaluated at every step (the stable state may touch the
    punch elsewhere), whatever set Newton had fixed; continuation needs the active-set
    update (Options.active_set_update), so no set is frozen. Where it gives up, the stop is
    `stall`'s (what made Newton enter it), with what continuation measured added."""
    P, is_u = pr.red.P, pr.red.is_u
    def stop(measured=""):
        return PressError(stall.cause, stall.summary, pr.res, "; ".join(m for m in (stall.detail, measured) if m))
    if pr._inertia is None:                       # no PARDISO: no inertia to tell a stable state by
        raise stall
    tau, prev, shrink = TAU0, None, 1.0
    for k in range(PTC_STEPS):
        r, ref, st, K = pr._residual(x, d, lam)
        if not np.all(np.isfinite(K.data)) or not np.all(np.isfinite(r)):
            raise PressError("non-finite", f"continuation reached a non-finite state at travel {d:.4g} m", pr.res)
        D = linalg.scaling(K, is_u)
        nr, norm = _scaled_norm(D, r, ref)
        pr.trace.append((d, k, norm, int(st.active.sum()), "continuation", tau))
        if norm < tol:
            pr.stats["continuation_steps"] = pr.stats.get("continuation_steps", 0) + k
            return x, _true_state(pr, x, st, d, lam, None), k
        if k == 0:
            entry = norm
        elif k == PATIENCE and norm >= entry:
            raise stop(f"pseudo-transient continuation left the residual at {norm:.2e} after {k} steps, "
                       f"from {entry:.2e}")
        if prev is not None:                      # SER; halved after a step taken at its first tau
            tau *= min(1.0, norm / prev) * shrink
        prev, shrink = norm, 0.5
        m = np.where(is_u, np.abs(K.diagonal()), 0.0)
        for _ in range(TAU_TRIES):
            Kt = K.copy()
            Kt.setdiag(K.diagonal() + tau * m)
            solver = pr.refactor(Kt, D, factorizer=pr._inertia)
            if solver.inertia is None:           # a nonsymmetric (sticking) tangent: no inertia
                raise stall
            if solver.inertia[1] > _stable_negatives(pr):
                tau, shrink = max(4 * tau, TAU0), 1.0     # still unstable: a shorter pseudo-time step
                continue
            dy, _ = solver(-r, rtol=SOLVE_RTOL)
            x_new = x + P @ dy[:, 0]
            r_new = pr._residual(x_new, d, lam, tangent=False)[0]
            if (pr._min_J > 0 and np.all(np.isfinite(r_new))
                    and np.linalg.norm(D * r_new) <= GROW * max(nr, 1e-3 * np.linalg.norm(D * ref))):
                break
            tau, shrink = max(4 * tau, TAU0), 1.0         # inverted or far off: a shorter pseudo-time step
        else:
            raise stop("pseudo-transient continuation found no step keeping the silicone uninverted and "
                       f"the tangent stable (tau up to {tau:.1e})")
        x = x_new
    raise stop(f"pseudo-transient continuation did not settle in {PTC_STEPS} steps, residual {norm:.2e}")


def _scaled_norm(D, r, ref):
    """(|D r|, |D r| / |D R_c|): the residual's scaled norm, absolute and relative to the contact part."""
    nr = np.linalg.norm(D * r)
    return nr, (nr / max(np.linalg.norm(D * ref), 1e-300) if nr > 0 else 0.0)


def _true_state(pr, x, st, d, lam, fixed):
    """The converged contact state: with a fixed active set or without dn/dx, re-evaluated
    (the true, non-negative pressure, with dn/dx)."""
    if fixed is None and st.H is not None:
        return st
    return pr.surf.state(x[pr.sy.offsets["u"]], pr.ind, d, lam, pr.eps, stick=pr._stick)


def _stable_negatives(pr) -> int:
    """The negative eigenvalues of a stable state's tangent: one per pressure and potential
    unknown (the condensed displacement stiffness positive definite)."""
    return int((~pr.red.is_u).sum())


def _stability(pr) -> str:
    """The stalled tangent's stability, where the factorization reports its inertia."""
    inertia = getattr(pr.solver, "inertia", None)
    if inertia is None:
        return ""
    extra = inertia[1] - _stable_negatives(pr)
    return (f"; the state is unstable: {extra} negative eigenvalue{'s' if extra > 1 else ''} of the "
            "condensed displacement stiffness" if extra > 0 else "; the state is stable: a kink in the contact zone")


def crush_where(pr, x_step) -> str:
    """Where Newton's last line-search step inverts the silicone (its smallest J and that point's
    reference position from the indenter's axis and below the top surface), and the smallest
    J of the last converged state (fem.hyperelastic.smallest_jacobian)."""
    sy = pr.sy
    if not sy.yeoh:
        return ""

    def smallest(x):
        u = x[sy.offsets["u"]]
        return min((hyperelastic.smallest_jacobian(sy.ubases[r], u, sy.kin) for r in sy.yeoh), key=lambda t: t[0])
    J, X = smallest(x_step)
    last = f"the last converged state, at travel {pr.d:.4g} m, has J down to {smallest(pr.x)[0]:.2f}"
    if not np.isfinite(J):
        return f"its last line-search step leaves a non-finite state; {last}"
    r = float(lateral_distance(X, pr.ind.centre))
    return (f"its last line-search step leaves J {J:.2g} at {1e3 * r:.3g} mm from the indenter's axis, "
            f"{1e3 * (pr.z_top - X[-1]):.2g} mm below the top surface; {last}")


def _where(pr, st, x, dx) -> str:
    """What the stagnating iterate shows: its contact points on the punch's rounded edge (the
    gap's normal turns there), how far the last full Newton step would slide a contact point
    along the indenter (against the edge radius), and the smallest J of the Yeoh silicone."""
    ind = pr.ind
    r = lateral_distance(st.x, ind.centre)
    act = st.active
    rim = int((act & (r > ind.core)).sum()) if ind.rho > 0 else 0
    u = pr.sy.offsets["u"]
    move = np.einsum("fqic,fi->cfq", pr.surf.phi, dx[u][pr.surf.dofs])
    slide = move - (move * st.n).sum(axis=0) * st.n
    slide = float(np.sqrt((slide ** 2).sum(axis=0))[act].max(initial=0.0))
    part = "the rounded edge" if ind.shape == "flat" else f"the {ind.shape}"
    return (f"{rim} of {int(act.sum())} contact points on {part}; the last full Newton step "
            f"slides a contact point by {1e3 * slide:.3g} mm (edge radius {1e3 * ind.rho:.3g} mm)"
            + (f"; smallest J in the silicone {pr._min_J:.2f}" if pr.sy.yeoh else ""))

