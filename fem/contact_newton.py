"""The semi-smooth Newton solve of one press equilibrium (fem.press.Press), at fixed
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

Stops, as ContactError naming the cause: a non-finite state; the penalty too high (the
scaled solve's relative residual above 1e-6); elements inverted at every line-search
step; the active set cycling between two sets; Newton stagnating (STALL_STEPS steps
on one active set that cut the residual by less than STALL_CUT in all, the line
search taking short steps: a kink the iterates cannot cross; measured on the 3D
press at sizes / 0.707, a trial 41 % beyond the last state sat at 0.027 for 20
iterations, benchmarks/press_3d.py), so that force control bisects at once; and the
iteration limit.
"""

from __future__ import annotations

import time

import numpy as np

from taxel.fem import linalg
from taxel.fem.press_result import ContactError

STALL_STEPS = 5      # Newton steps on one active set ...
STALL_CUT = 0.5      # ... that cut the residual by less than this factor: stagnation
CHORD_CUT = 0.25     # a chord step (the last factorization) is kept if it cuts the residual by this
SOLVE_RTOL = 1e-10   # a Newton step's linear solve: refinement stops here (1e-13 elsewhere)


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
            raise ContactError(f"Newton reached a non-finite state at travel {d:.4g} m", pr.res)
        if K is not None:
            D = linalg.scaling(K, pr.red.is_u)
        # the scaled norm first (after a line search with the last step's scaling): a converged
        # iterate gets no tangent and no factorization
        nr = np.linalg.norm(D * r)
        norm = nr / max(np.linalg.norm(D * ref), 1e-300) if nr > 0 else 0.0
        floor = (len(seen) >= 1 and key == seen[-1] and step_rel < 1e-9 and norm < 1e-6)
        if norm < tol or floor:            # floor: a full step with the same active set changed x
            if fixed is not None or st.H is None:   # the true (non-negative) pressure, with dn/dx
                st = pr.surf.state(x[pr.sy.offsets["u"]], pr.ind, d, lam, pr.eps, stick=pr._stick)
            return x, st, it
        ckey = (key, pr.eps, None if pr._stick is None else pr._stick.mask.tobytes(), fixed is None, frozen is None)
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
                raise ContactError(f"Newton reached a non-finite state at travel {d:.4g} m", pr.res)
            D = linalg.scaling(K, pr.red.is_u)
            nr = np.linalg.norm(D * r)
            norm = nr / max(np.linalg.norm(D * ref), 1e-300) if nr > 0 else 0.0
        if (len(seen) >= STALL_STEPS and len(set(seen[-STALL_STEPS:] + [key])) == 1
                and norm > STALL_CUT * norms[-STALL_STEPS]):
            raise ContactError(f"Newton stagnates at travel {d:.4g} m: {STALL_STEPS} steps on one active set "
                               f"cut the residual from {norms[-STALL_STEPS]:.2e} only to {norm:.2e} (line "
                               f"search steps down to 1/64: a kink in the contact zone; {_where(pr, st, x, dx)})", pr.res)
        solver = pr.refactor(K, D, ckey)
        seen.append(key)
        norms.append(norm)
        pr.trace.append((d, it, norm, int(st.active.sum())))
        t0 = time.process_time()
        dy, lres = solver(-r, rtol=SOLVE_RTOL)
        pr.stats["solve_s"] += time.process_time() - t0
        if float(np.max(lres)) > 1e-6:
            raise ContactError(f"penalty too high: the scaled linear solve's relative residual is "
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
                raise ContactError(f"Newton inverts silicone elements at travel {d:.4g} m", pr.res)
            alpha /= 2
        pr.trace[-1] += (alpha,)
        step_rel = alpha * np.linalg.norm(dx) / max(np.linalg.norm(x), 1e-300)
        x = x_new
    last = seen[-6:]
    if len(set(last)) <= 2 and len(set(last)) < len(last) and last[-1] != last[-2]:
        raise ContactError(f"the contact active set cycles between two sets at travel {d:.4g} m "
                           f"({o.max_iter} Newton iterations, residual {norm:.2e}): keep the active-set "
                           "update in the tangent, or take smaller travel steps", pr.res)
    raise ContactError(f"Newton did not converge at travel {d:.4g} m in {o.max_iter} iterations "
                       f"(residual {norm:.2e})", pr.res)


def _where(pr, st, x, dx) -> str:
    """What the stagnating iterate shows: its contact points on the punch's rounded edge (the
    gap's normal turns there), how far the last full Newton step would slide a contact point
    along the indenter (against the edge radius), and the smallest J of the Yeoh silicone."""
    ind = pr.ind
    nl = st.x.shape[0] - 1
    c = np.asarray(ind.centre[:nl], float).reshape((nl,) + (1,) * (st.x.ndim - 1))
    r = np.sqrt(((st.x[:nl] - c) ** 2).sum(axis=0))
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
