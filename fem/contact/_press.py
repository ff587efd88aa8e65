"""Pressing with a rigid indenter: displacement and force control of the
contact problem (fem.contact), monolithic with the piezo and the (linear or Yeoh)
silicone.

Equilibrium at a travel d (reduced unknowns of fem.assembly.elimination, grounded
electrodes eliminated, open electrodes one potential each with zero net charge):

    r(x) = A_lin x + R_yeoh(x) + R_c(x; d, lambda) = 0

solved by semi-smooth Newton (fem.contact: the contact active set
re-evaluated at every iterate, tangent A_lin + K_yeoh + K_c consistent and
symmetric, fem.contact), backtracking line search on the scaled residual (and J > 0
in the Yeoh silicone). Convergence: |D r| / |D R_c| < min(tol, 1e-3 gap_tol) (1e-6:
the 3D press's V/F moves by 1e-6 relative against 1e-9, benchmarks/press_3d.py). Around it the Uzawa
loop updates lambda <- t_N until max |t_N - lambda| / eps (the penetration, or the
gap where a pressure still acts) is below `gap_tol` x travel (augmented Lagrangian;
method = "penalty" does one Newton solve with lambda = 0 and reports the
penetration it leaves). While the multipliers still move, Newton stops at
min(uzawa_tol, gap_tol) (inexact Uzawa); once they have converged, one more pass
takes it to the full tolerance on them.
Contact points: fem.contact (its `_geometry` docstring).

Frictionless and Coulomb contact can be solved by the semi-smooth Newton on the Alart-Curnier
conditions with the tractions as unknowns (fem.contact._alart_curnier; Options.solver
"semismooth", and with "auto" a load step the Uzawa path below (the default) stops in): no Uzawa
loop, no penetration left.
When an active set comes back within one Newton solve (`fix_cycling`, default),
Newton finishes on it (a smooth problem) and the Uzawa loop decides. Sticking
contact (Indenter.friction): points that came into contact in a converged step
are tied to the indenter there (fem.contact.Stick), their vector multipliers
updated by the same Uzawa loop. Coulomb friction (Indenter.friction a number mu):
the return mapping of fem.contact.Coulomb at every iterate, its tangential
multipliers updated by the same Uzawa loop, every point re-anchored after each
converged step.

Each new travel starts from the tangent prediction x + (d - d0) dx/dd, with
K dx/dd = -dr/dd from the factorized tangent of the last converged state
(shortened while it would invert elements). Load control (fem.contact): displacement control: travel
increments from the last converged state (halved on failure, grown by 1.5 after
an easy step). Force control: Newton on F(d) = F_target with the path's own
stiffness dF/dd = dF/dd|_x + dF/dx . dx/dd (at most twice the last step), regula
falsi with the Illinois rule once bracketed, a failed trial bisected towards the
last converged travel. Every converged state is a point of the force-travel /
voltage-force curve. The Yeoh and contact terms are vectorised element arrays
(fem.hyperelastic, Surface.element_*) scattered into a reduced CSR pattern built once
(fem.assembly); Options(assembly="skfem") keeps the scikit-fem path for comparison.

Failures are raised as PressError with its cause (fem.contact.StopCause) and what
it measured: Newton not converging,
Newton stagnating on one active set (fem.contact), the active set cycling
(the last iterates alternate between two sets), the augmented
Lagrangian not reaching the penetration tolerance (the penalty is doubled, up
to 64 x, when an update does not cut the error by 4), a penalty too low
(penetration above tolerance with method = "penalty"), a penalty too high (the
scaled linear solve loses accuracy: relative residual above 1e-6).
"""

from __future__ import annotations

import logging
import time

import numpy as np

from . import _alart_curnier as alart_curnier
from . import _newton as contact_newton
from taxel.fem import linalg, static
from . import _loadpath as loadpath
from taxel.fem.assembly import Indenter, Pattern, System, elimination
from ._friction import Coulomb
from ._geometry import Stick, Surface
from taxel.fem.hyperelastic import scatter, yeoh_regions
from ._records import PressError, PressResult, Options, PressPoint
from taxel.fem.static import Solution
from ._solution import final_solution, residual_skfem

__all__ = ["PressError", "PressResult", "Options", "Press", "PressPoint"]


class Press:
    """One system pressed by one indenter; `travel(d)` and `force(F)` move it."""

    def __init__(self, sy: System, ind: Indenter, method="auto", opts: Options | None = None):
        self.sy, self.ind = sy, ind
        self.o = opts or Options()
        tm = sy.tm
        self.red = elimination(sy, eliminate_grounded=True)
        self.method = linalg.resolve(method, self.red.n, dim=tm.mesh.dim())   # PARDISO for 3D sizes
        p = tm.mesh.p
        top = tm.facets["top"]
        self.z_top = float(p[-1, np.unique(tm.mesh.facets[:, top])].max())
        self.height = self.z_top - float(p[-1].min())
        ub = next(iter(sy.ubases.values()))
        rule = self.o.rule if self.o.rule != "auto" else "nodal" if tm.mesh.dim() == 3 else "gauss"
        self.surf = Surface(tm.mesh, ub.elem, top, sy.kin, self.z_top, self.o.intorder, rule)
        if self.o.penalty is None:
            mu = max(lw.mu for r, lw in sy.laws.items() if r in sy.soft)
            h = float(np.min(np.linalg.norm(np.diff(p[:, tm.mesh.facets[:, top]], axis=1), axis=0)))
            self.eps = self.o.penalty_factor * mu / h
        else:
            self.eps = self.o.penalty
        self.x = np.zeros(sy.A.shape[0])
        self.lam = np.zeros(self.surf.shape)
        self.d = 0.0
        self.prev = None                 # (travel, x) of the state before the last converged one
        self.res = PressResult(ind, self.eps, self.o.method)
        self.G = static.symmetry_order(sy)      # a half or quarter model (fem.static): forces and areas x G
        self.solver = None
        # the tangents share one pattern (fem.assembly): PARDISO's analysis once, a numeric
        # factorization per Newton step (Options.reuse_analysis)
        self._factorize = (linalg.Refactorizer(self.method) if self.o.reuse_analysis and self.o.assembly != "skfem"
                           else lambda K, is_u, D=None: linalg.scaled_solver(K, is_u, self.method, D=D))
        self._pat, self._min_J = None, 1.0
        # continuation's factorizer (fem.contact), PARDISO for its inertia: the press's own in 3D
        self._inertia = (self._factorize if self.method == "pardiso" and isinstance(self._factorize, linalg.Refactorizer)
                         else linalg.Refactorizer("pardiso") if linalg.available("pardiso") else None)
        # sticking contact: the tied points (fem.contact.Stick); Coulomb friction: its state (fem.contact.Coulomb)
        self.stick: Stick | Coulomb | None = None
        self._stick: Stick | Coulomb | None = None    # the one in use by the solve under way
        self.v, self.slope = None, None  # dx/dd and dF/dd at the last converged state
        self.stats = dict(factorizations=0, residuals=0, tangents=0, factorize_s=0.0, assemble_s=0.0, solve_s=0.0,
                          chord_steps=0)
        self.res.stats = self.stats      # the same dict: the result carries the work it cost
        self._chord_key = None           # what the last factorization was made for (fem.contact)
        self.trace = []                  # (travel, iteration, scaled residual, active points) per Newton step
        self._fallback = False           # Options.solver "auto": this step by the semi-smooth Newton

    # ------------------------------------------------------------ one equilibrium
    def _pattern(self) -> Pattern:
        """The reduced matrix's pattern: the linear part, every Yeoh element block, every
        contact facet block (fem.assembly), built on first use."""
        if self._pat is None:
            blocks = {}
            for k, reg in yeoh_regions(self.sy).items():
                U, Q = reg.udofs, reg.pdofs
                blocks[f"uu:{k}"] = (U[:, :, None] + 0 * U[:, None, :], U[:, None, :] + 0 * U[:, :, None])
                blocks[f"up:{k}"] = (U[:, :, None] + 0 * Q[:, None, :], Q[:, None, :] + 0 * U[:, :, None])
                blocks[f"pu:{k}"] = (Q[:, None, :] + 0 * U[:, :, None], U[:, :, None] + 0 * Q[:, None, :])
                blocks[f"pp:{k}"] = (Q[:, :, None] + 0 * Q[:, None, :], Q[:, None, :] + 0 * Q[:, :, None])
            S = self.surf.dofs + self.sy.offsets["u"].start
            blocks["contact"] = (S[:, :, None] + 0 * S[:, None, :], S[:, None, :] + 0 * S[:, :, None])
            self._pat = Pattern(self.red.P, self.sy.A, blocks)
        return self._pat

    def _residual(self, x, d, lam, tangent=True, frozen=None, fixed=None, contact=True):
        """(reduced residual, reduced contact residual, contact state, reduced tangent or None);
        the smallest J of the Yeoh silicone in self._min_J. contact=False: without the contact
        terms (residual, None, None, tangent; fem.contact's semi-smooth Newton adds its own)."""
        t0 = time.process_time()          # CPU time: the machine is shared
        try:
            return self._residual_any(x, d, lam, tangent, frozen, fixed, contact)
        finally:
            self.stats["residuals"] += 1
            self.stats["tangents"] += bool(tangent)
            self.stats["assemble_s"] += time.process_time() - t0

    def _residual_any(self, x, d, lam, tangent=True, frozen=None, fixed=None, contact=True):
        if self.o.assembly == "skfem":
            return self._residual_skfem(x, d, lam, tangent, frozen, fixed)
        sy, pat = self.sy, self._pattern()
        n = len(x)
        r_full = sy.A @ x
        vals, self._min_J = {}, 1.0
        for k, reg in yeoh_regions(sy).items():
            t = reg.terms(x, tangent)
            self._min_J = min(self._min_J, t.min_J)
            r_full += np.bincount(reg.udofs.ravel(), t.r_u.ravel(), minlength=n)
            r_full += np.bincount(reg.pdofs.ravel(), t.r_p.ravel(), minlength=n)
            if tangent:
                vals.update({f"uu:{k}": t.K_uu, f"up:{k}": t.K_up, f"pu:{k}": t.K_up, f"pp:{k}": t.K_pp})
        if not contact:
            return pat.reduce(r_full), None, None, pat.matrix(vals) if tangent else None
        u = x[sy.offsets["u"]]
        st = self.surf.state(u, self.ind, d, lam, self.eps, with_curvature=tangent, fixed=fixed, stick=self._stick)
        S = self.surf.dofs.ravel() + sy.offsets["u"].start
        rc_full = np.bincount(S, self.surf.element_residual(st).ravel(), minlength=n)
        r, ref = pat.reduce(r_full + rc_full), pat.reduce(rc_full)
        if not tangent:
            return r, ref, st, None
        vals["contact"] = self.surf.element_tangent(st, self.eps, frozen)
        return r, ref, st, pat.matrix(vals)

    def _residual_skfem(self, x, d, lam, tangent=True, frozen=None, fixed=None):
        """`_residual` through scikit-fem's forms (fem.contact's residual_skfem)."""
        return residual_skfem(self, x, d, lam, tangent, frozen, fixed)

    def _newton(self, x, d, lam, tol=None):
        """Newton at travel d, multipliers lam (fem.contact): the semi-smooth Newton on the
        Alart-Curnier equations (frictionless and Coulomb, Options.solver "semismooth"), else
        the penalty Newton inside the Uzawa loop."""
        if self._semismooth():
            return alart_curnier.newton(self, x, d, lam, tol)
        return contact_newton.newton(self, x, d, lam, tol)

    def _semismooth(self, fallback=False) -> bool:
        """Whether the semi-smooth Newton solves this step (or, `fallback`, would solve a step the
        Uzawa path stopped in): Options.solver "semismooth", or "auto" after a stop."""
        o = self.o
        chosen = o.solver == "semismooth" or (o.solver == "auto" and (fallback or self._fallback))
        return chosen and self.ind.friction != "sticking" and o.method != "penalty" and o.assembly != "skfem"

    def solve_at(self, d):
        """Equilibrium at travel d from the last converged state; appends a PressPoint."""
        o = self.o
        x, lam, its = self.x.copy(), self.lam.copy(), 0
        self._stick = self._sticking()
        if o.predictor and self.v is None and not self.res.points:
            self.start_rates()
        if o.predictor and self.v is not None:     # the tangent prediction, shortened while it inverts elements
            for frac in (1.0, 0.5, 0.25, 0.0):
                if frac == 0.0 or self._residual(x + frac * (d - self.d) * self.v, d, lam, tangent=False) \
                        and self._min_J > 0:
                    break
            x = x + frac * (d - self.d) * self.v
        eps0, err_prev = self.eps, np.inf
        # Newton resolves the gap tolerance: a relative residual 1e-3 of it (Options.tol at most);
        # while the multipliers move, uzawa_tol (the gap tolerance at most)
        tol_n = min(o.tol, 1e-3 * o.gap_tol)
        loose = tol_n if o.uzawa_tol is None else max(tol_n, min(o.uzawa_tol, o.gap_tol))
        exact = o.method == "penalty" or loose <= tol_n
        for k in range(o.max_uzawa + 1):
            x, st, it = self._newton(x, d, lam, tol_n if exact else loose)
            its += it
            if self._semismooth():       # the multipliers are unknowns of the solve (fem.contact): no Uzawa pass
                lam = st.tn
                if st.tang is not None:
                    self._stick = Coulomb(self._stick.mu, self._stick.a0, st.tang.t.copy(), self._stick.slip)
                break
            tol = o.gap_tol * max(abs(d), 1e-12)
            err = float(np.abs(st.tn - lam).max()) / self.eps   # m: penetration, or gap under pressure
            if st.stuck is not None:                            # m: the stuck points' distance to their anchors
                err = max(err, float(np.abs(st.ts - self._stick.lam).max()) / self.eps)
            if st.tang is not None:                             # m: Coulomb, the tangential multipliers' move
                err = max(err, float(np.abs(st.tang.t - self._stick.lam).max()) / self.eps)
            if o.method == "penalty":
                if st.penetration > tol:
                    raise PressError("penalty", f"penalty too low: penetration {st.penetration:.3g} m is "
                                       f"{100 * st.penetration / max(abs(d), 1e-300):.2g} % of the travel "
                                       f"(tolerance {100 * o.gap_tol:g} %); raise the penalty "
                                       f"({self.eps:.3g} Pa/m) or use the augmented Lagrangian", self.res)
                break
            if err <= tol and not exact:   # the multipliers have converged: Newton to Options.tol on them
                exact = True
                continue
            if err <= tol:
                break
            if err > 0.25 * err_prev and self.eps < 64 * eps0:   # slow Uzawa: a stiffer augmentation
                self.eps *= 2
            err_prev = err
            lam = st.tn
            if st.stuck is not None:
                self._stick = Stick(self._stick.mask, self._stick.a0, st.ts.copy())
            if st.tang is not None:
                self._stick = Coulomb(self._stick.mu, self._stick.a0, st.tang.t.copy(), self._stick.slip)
        else:
            self.eps = eps0
            raise PressError("multipliers", f"augmented Lagrangian: the multipliers did not settle in "
                               f"{o.max_uzawa} updates at travel {d:.4g} m; raise the penalty", self.res,
                               f"largest penetration, or gap under pressure, {err:.3g} m against {tol:.3g} m; "
                               f"penetration {st.penetration:.3g} m")
        if o.predictor:                     # with the tangent's own penalty (before restoring it)
            self.v, self.slope = self._rates(x, st, d, lam)
        self.eps = eps0
        self.prev = (self.d, self.x)
        self.x, self.lam, self.d = x, st.tn.copy(), d
        if isinstance(self._stick, Coulomb):  # every point re-anchored where it is, t_T kept (fem.contact.Coulomb)
            a0 = st.x.copy()
            a0[-1] += d
            self.stick = Coulomb(self._stick.mu, a0, st.tang.t.copy(), st.slip.copy())
        elif self._stick is not None:        # points that came into contact in this step stick where they are
            new = st.normal_active & ~self._stick.mask
            a0, lam_s = self._stick.a0.copy(), (self._stick.lam if st.ts is None else st.ts).copy()
            a0[:, new] = st.x[:, new]
            a0[-1, new] += d
            lam_s[:, new] = (st.tn * st.n)[:, new]
            self.lam = np.where(new, 0.0, self.lam)
            self.stick = Stick(self._stick.mask | new, a0, lam_s)
        self._stick = None
        self.res.state = st
        V = {k: float(x[self.sy.electrodes.dofs[k][0]]) for k in self.red.active}
        pt = PressPoint(d, self.G * st.force, V, self.G * st.area, st.half_width(self.ind.centre),
                        st.penetration, its, k, st.max_pressure)
        self.res.points.append(pt)
        logging.getLogger(__name__).info("press step %d: travel %.4g mm, force %.4g N, %d Newton iterations",
                                         len(self.res.points), 1e3 * d, pt.force, its)
        return pt

    def _rates(self, x, st, d, lam):
        """(dx/dd, dF/dd) along the equilibrium path at a converged state, with the
        tangent factorized at Newton's last step (self.solver; within a step of it): K dx/dd = -dr/dd, and dF/dd =
        dF/dd|_x + dF/dx . dx/dd (the force-travel stiffness; fem.contact.travel_derivatives)."""
        n, u0 = len(x), self.sy.offsets["u"].start
        S = self.surf.dofs.ravel() + u0
        dr, dF_dd, dF_du = self.surf.travel_derivatives(st, self.eps)
        if self.solver is None:                  # converged without a Newton step: factorize here
            self.refactor(self._residual(x, d, lam)[3])
        rhs = self.red.P.T @ np.bincount(S, dr.ravel(), minlength=n)
        dy, _ = self.solver(-rhs)
        v = self.red.P @ dy[:, 0]
        return v, self.G * (dF_dd + float(dF_du.ravel() @ v[S]))

    def refactor(self, K, D=None, key=None, factorizer=None):
        """Factorize the tangent K (row scaling D, or the solver's own) as the press's
        solver, made for `key` (the chord steps' active set, stick set and penalty;
        fem.contact), by `factorizer` (default the press's own), counted in the stats."""
        t0 = time.process_time()
        self.solver = (factorizer or self._factorize)(K, self.red.is_u, D=D)
        self._chord_key = key
        self.stats["factorizations"] += 1
        self.stats["factorize_s"] += time.process_time() - t0
        return self.solver

    def node_penetration(self) -> float:
        """m, the deepest node of the top facets inside the indenter at the current state,
        whatever contact points pressed it (a check of the rule: points between nodes leave
        the nodes free, fem.contact)."""
        nodes = Surface(self.sy.tm.mesh, self.surf.fb.elem, self.sy.tm.facets["top"], self.sy.kin, self.z_top,
                        rule="nodal")
        st = nodes.state(self.x[self.sy.offsets["u"]], self.ind, self.d, np.zeros(nodes.shape), self.eps)
        return st.penetration

    def start_rates(self):
        """dx/dd and dF/dd at the unpressed state (one factorization): the first travel's
        prediction, and force control's first trial (fem.contact.force)."""
        self._stick = self._sticking()
        _, _, st, K = self._residual(self.x, self.d, self.lam)
        self.refactor(K)
        self.v, self.slope = self._rates(self.x, st, self.d, self.lam)
        return self.slope

    def _sticking(self) -> Stick | Coulomb | None:
        """The stick set for the next solve: with a sticking indenter, at the first solve
        the points touching it at the current travel (the flat of a punch at zero travel);
        with a Coulomb coefficient, the friction state (every point anchored where it is)."""
        mu = self.ind.coulomb
        if mu is not None:
            if self.stick is None:
                x = self.surf.state(self.x[self.sy.offsets["u"]], self.ind, self.d, self.lam, self.eps, False).x
                a0 = x.copy()
                a0[-1] += self.d
                self.stick = Coulomb(mu, a0, np.zeros_like(x), np.zeros(x.shape[1:]))
            return self.stick.copy()
        if self.ind.friction != "sticking":
            return None
        if self.stick is None:
            st = self.surf.state(self.x[self.sy.offsets["u"]], self.ind, self.d, self.lam, self.eps, False)
            mask = st.g <= 1e-9 * self.height
            a0 = st.x.copy()
            a0[-1] += self.d
            self.stick = Stick(mask, a0, np.zeros_like(st.x))
        return Stick(self.stick.mask.copy(), self.stick.a0, self.stick.lam.copy())

    def attempt(self, d):
        """solve_at, restoring the state on failure; with Options.solver "auto", a step the
        Uzawa path stops in is solved again by the semi-smooth Newton (fem.contact)."""
        saved = self.snapshot()
        try:
            return self.solve_at(d)
        except PressError as exc:
            self.restore(saved)
            self.res.failed_trials += 1
            if self._fallback or not self._semismooth(fallback=True) or exc.cause == "penalty":
                raise
        self._fallback = True
        try:
            return self.attempt(d)
        finally:
            self._fallback = False

    def snapshot(self) -> tuple:
        """The converged state (restore() returns to it): a failed or rejected trial leaves no trace
        (its penalty too: a trial that stopped after doubling it kept the doubled one before)."""
        return (self.x, self.lam, self.d, self.prev, self.v, self.slope, self.stick, len(self.res.points),
                self.res.state, self.eps)

    def restore(self, saved: tuple) -> None:
        """Back to a snapshot(): the states converged since are dropped from the path."""
        self.x, self.lam, self.d, self.prev, self.v, self.slope, self.stick, n, self.res.state, self.eps = saved
        del self.res.points[n:]
        self._stick = None

    # ------------------------------------------------------------ load control (fem.contact)
    def travel(self, d_target, first=0.25, min_frac=1e-3):
        """Displacement control to travel d_target (fem.contact.travel)."""
        return loadpath.travel(self, d_target, first, min_frac)

    def force(self, F_target, max_trials=40):
        """Force control to F_target from the last converged state (fem.contact.force)."""
        return loadpath.force(self, F_target, max_trials)

    def solution(self) -> Solution:
        """The Solution of the final state (fem.contact's final_solution)."""
        return final_solution(self)

    def contact_tangent(self):
        """K_c of the final state as a full-size CSR matrix."""
        S = self.surf.dofs + self.sy.offsets["u"].start
        return scatter(S, S, self.surf.element_tangent(self.res.state, self.eps), self.sy.A.shape[0])

