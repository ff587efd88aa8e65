"""Static linear piezoelectric solve of a scene: assemble, constrain, scale, solve, report.

Unknowns: displacement u everywhere (P2, or P1 + bubble with order 1), one P1
pressure per solid region (mixed u-p, see fem.forms), and the electric
potential phi only in the piezo bodies (P2 or P1). The weak form is in
fem.forms.

Electrodes. One electrode is the reference (phi = 0: the common bottom
"ground" of an array, the first grounded electrode of a plate). Every other
electrode is *active*: its potential DOFs collapse into one unknown V_k whose
equation is the electrode's charge balance (the sum of its rows), right-hand
side -Q_k. One factorization of that matrix then gives, by back-substitution:

    x_f        load, all active electrodes open (Q = 0): open-circuit voltages V_f
    X_k        unit charge on electrode k:        column k of C^-1
    C          the capacitance matrix (clamped by the scene's supports, free elsewhere)
    Q_sc = -C V_f   short-circuit charges (what a charge amplifier integrates)

and the state the scene asks for (each electrode open, grounded or at a
voltage) follows from the n x n relation V = V_f + C^-1 Q without another
factorization.

Scaling. Stiffnesses span 1e4 Pa (silicone) to 1e11 Pa (PZT) and the
dielectric block is ~1e-8: the matrix is scaled symmetrically, A_s = D A D, with
unit displacement diagonals and unit approximate Schur-complement diagonals for
pressure and potential (see `_scaling`), then factorized; iterative refinement
reuses the factors, and the relative residual |A_s y - b_s| / |b_s| is reported
(tests also check equilibrium of the reactions and agreement between solvers).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementTetMini, ElementTetP1, ElementTetP2, ElementTriMini, ElementTriP1, \
    ElementTriP2, ElementVector, FacetBasis, asm

from fem import forms, linsolve, materials
from meshing.build import TaggedMesh, build
from meshing.layout import layout
from studies.scene import Scene, SceneError, electrode_state, user_materials


@dataclass
class ElectrodeResult:
    name: str
    state: str                    # open | ground | reference | "<V> V"
    voltage: float                # V, under the scene's electrode states
    charge: float                 # C, under the scene's electrode states
    short_circuit_charge: float   # C, this and every other active electrode grounded
    capacitance: float | None     # F, self capacitance with the others grounded; None for the reference


@dataclass
class Solution:
    scene: Scene
    electrodes: dict[str, ElectrodeResult]
    applied_force: float          # N, total downward load
    reaction: np.ndarray          # N, total support reaction (x, [y,] z); axisymmetric: (0, z)
    max_silicone_strain: float    # largest |principal strain| of element-mean strains in solids with Yeoh data
    unknowns: int
    solver: str
    residual: float               # relative residual |A x - b| / |b| of the scaled system
    times: dict[str, float]
    mesh: TaggedMesh
    fields: dict = field(repr=False, default_factory=dict)
    newton: object = None         # fem.newton.NewtonResult for a hyperelastic solve
    model_note: str = ""          # which silicone model was used and why ("auto")

    def voltages(self):
        return {k: e.voltage for k, e in self.electrodes.items() if e.state != "reference"}

    def record(self) -> dict:
        """One JSON-ready record of the numbers a user asks for (SI units)."""
        return {
            "scene": self.scene.name, "model": self.scene.model.type,
            "electrodes": {k: {"state": e.state, "voltage_V": e.voltage, "charge_C": e.charge,
                               "short_circuit_charge_C": e.short_circuit_charge,
                               "capacitance_F": e.capacitance} for k, e in self.electrodes.items()},
            "applied_force_N": self.applied_force, "reaction_N": self.reaction.tolist(),
            "max_silicone_strain": self.max_silicone_strain, "unknowns": self.unknowns,
            "solver": self.solver, "relative_residual": self.residual,
            "times_s": self.times, "silicone": self.scene.model.silicone, "model_note": self.model_note,
            "newton": None if self.newton is None else {
                "load_factors": self.newton.load_factors, "iterations": self.newton.iterations,
                "cutbacks": self.newton.cutbacks, "message": self.newton.message},
        }


# Linear silicone's taxel-voltage error per unit of its own largest silicone strain:
# the worst ratio measured over the thesis PZT and PVDF taxels, 0.05 to 0.45 N
# (benchmarks/silicone_model_error.py: 0.223 least squares, 0.257 worst).
LINEAR_ERROR_PER_STRAIN = 0.257


def solve(scene: Scene, solver: str = "auto", tagged_mesh: TaggedMesh | None = None,
          scale: bool = True, newton: dict | None = None) -> Solution:
    """Solve a scene (meshing it unless `tagged_mesh` is given). With a Yeoh
    silicone, `newton` passes options to fem.newton.newton (tol, max_iter,
    first_step, stepping, line_search).

    model.silicone = "auto" solves the linear model, estimates its voltage error
    as LINEAR_ERROR_PER_STRAIN x its largest silicone strain, keeps it when the
    estimate is within model.tolerance and otherwise solves Yeoh; the choice and
    the estimate are in `Solution.model_note`.
    """
    if scene.model.silicone == "auto":
        return _solve_auto(scene, solver, tagged_mesh, scale, newton)
    t0 = time.perf_counter()
    user = user_materials(scene)
    tm = tagged_mesh or build(layout(scene), user)
    t1 = time.perf_counter()
    hyper = scene.model.silicone == "yeoh"
    system = assemble(scene, tm, user, hyperelastic=hyper)
    t2 = time.perf_counter()
    if hyper:
        from fem.newton import solve_yeoh
        sol = solve_yeoh(system, solver, **(newton or {}))
    else:
        sol = _solve(system, solver, scale)
    t3 = time.perf_counter()
    sol.times = {"mesh": t1 - t0, "assemble": t2 - t1, "solve": t3 - t2, "total": t3 - t0}
    return sol


def _solve_auto(scene, solver, tagged_mesh, scale, newton):
    from fem.newton import NewtonError

    def as_(model):
        return scene.model_copy(update={"model": scene.model.model_copy(update={"silicone": model})})
    lin = solve(as_("linear"), solver, tagged_mesh, scale)
    est, tol = LINEAR_ERROR_PER_STRAIN * lin.max_silicone_strain, scene.model.tolerance
    if est <= tol:
        lin.model_note = (f"auto: linear silicone (largest strain {100 * lin.max_silicone_strain:.1f} %, "
                          f"estimated voltage error {100 * est:.2g} % <= {100 * tol:g} %)")
        return lin
    try:
        hyper = solve(as_("yeoh"), solver, lin.mesh, scale, newton)
    except NewtonError as exc:
        lin.model_note = (f"auto: Yeoh silicone needed (linear error about {100 * est:.2g} %) but {exc}; "
                          f"returning the LINEAR result")
        return lin
    hyper.model_note = f"auto: Yeoh silicone (the linear model would err by about {100 * est:.2g} %)"
    return hyper


# --------------------------------------------------------------------------------------
# assembly
# --------------------------------------------------------------------------------------

@dataclass
class System:
    scene: Scene
    tm: TaggedMesh
    A: sp.csr_matrix              # full (unconstrained) matrix
    b: np.ndarray                 # full load vector
    offsets: dict                 # block -> slice in the full vector
    ubases: dict                  # region -> restricted displacement basis
    pbases: dict                  # solid region -> restricted pressure basis
    phibases: dict                # piezo region -> restricted potential basis
    constitutive: dict            # region -> ("piezo", c, e, eps) or ("solid", mu, lam, beta, kappa)
    fixed_u: np.ndarray           # constrained displacement DOFs (value 0)
    fixed_by_support: dict        # support name -> DOFs
    electrode_dofs: dict          # electrode -> global phi DOFs (offset applied)
    states: dict                  # electrode -> "reference" | "open" | volts (float)
    applied_force: float
    yeoh: dict = field(default_factory=dict)   # solid region -> (C10, C20, C30), K  (hyperelastic)
    soft: set = field(default_factory=set)     # solid regions with Yeoh data (the silicone), solved or not
    parts: dict = field(default_factory=dict)  # A split by kind (see assemble), for loss factors
    preload: np.ndarray | None = None          # static state a dynamic model is linearised about


def _elements(dim, order, mixed):
    tri = dim == 2
    if order == 2:
        eu = ElementTriP2() if tri else ElementTetP2()
        return ElementVector(eu), ElementTriP1() if tri else ElementTetP1(), eu
    p1 = ElementTriP1() if tri else ElementTetP1()
    eu = (ElementTriMini() if tri else ElementTetMini()) if mixed else p1
    return ElementVector(eu), p1, p1


def assemble(scene: Scene, tm: TaggedMesh, user: dict | None = None, hyperelastic: bool = False) -> System:
    """The full linear system; with `hyperelastic`, solid regions with Yeoh data are
    left out of A (fem.newton adds their state-dependent residual and tangent)."""
    model, lay, mesh = scene.model.type, tm.layout, tm.mesh
    depth, dim = lay.depth, mesh.dim()
    mixed = scene.mesh.formulation == "mixed"
    eu, ep, ephi = _elements(dim, scene.mesh.order, mixed)
    q = 4

    ubases, pbases, phibases, constitutive, yeoh, soft = {}, {}, {}, {}, {}, set()
    for region, (mname, poling) in tm.materials.items():
        mat = materials.get(mname, user)
        elems = tm.regions[region]
        ubases[region] = Basis(mesh, eu, elements=elems, intorder=q)
        if isinstance(mat, materials.Piezo):
            try:
                c, e, eps = materials.reduced(mat.poled([0, 0, poling]), model)
            except ValueError as exc:
                raise SceneError(f"{mname}: {exc}") from None
            constitutive[region] = ("piezo", c, e, eps)
            phibases[region] = Basis(mesh, ephi, elements=elems, intorder=q)
        else:
            mu, lam = mat.mu, mat.lam
            beta, kappa = 1 / 3, mat.K            # deviatoric split (see fem.forms)
            if model == "plane_stress":
                lam = 2 * lam * mu / (lam + 2 * mu)
                beta, kappa = 0.0, lam
            constitutive[region] = ("solid", mu, lam, beta, kappa)
            if mixed and kappa != 0:      # kappa = 0 (plane stress, nu = 0): p = 0, nothing to constrain
                pbases[region] = Basis(mesh, ep, elements=elems, intorder=q)
            if mat.yeoh is not None:
                soft.add(region)
                if hyperelastic:
                    yeoh[region] = (mat.yeoh, mat.K)

    Nu = next(iter(ubases.values())).N
    Np1 = mesh.nvertices if pbases else 0
    Nphi = next(iter(phibases.values())).N if phibases else 0
    offsets = {"u": slice(0, Nu)}
    n = Nu
    for region in pbases:
        offsets[("p", region)] = slice(n, n + Np1)
        n += Np1
    offsets["phi"] = slice(n, n + Nphi)
    n += Nphi

    # blocks by kind, so that dynamics can give each its own loss factor:
    # "elastic:<region>" piezo stiffness, "coupling", "dielectric:<region>",
    # "shear:<region>" / "volumetric:<region>" silicone, "constraint" (the u-p coupling)
    blocks: dict[str, list] = {}

    def add(kind, *triples):
        blocks.setdefault(kind, []).extend(triples)
    for region, law in constitutive.items():
        ub = ubases[region]
        if law[0] == "piezo":
            _, c, e, eps = law
            add(f"elastic:{region}", ("u", "u", asm(forms.elastic(c, model, depth), ub)))
            Kup = asm(forms.piezo_coupling(e, model, depth), phibases[region], ub)
            add("coupling", ("u", "phi", Kup), ("phi", "u", Kup.T))
            add(f"dielectric:{region}", ("phi", "phi", -asm(forms.dielectric(eps, model, depth), phibases[region])))
        elif region in yeoh:
            continue
        else:
            _, mu, lam, beta, kappa = law
            if region in pbases:
                pk = ("p", region)
                B = asm(forms.pressure_divergence(model, depth), pbases[region], ub)
                add(f"shear:{region}", ("u", "u", asm(forms.deviatoric_shear(mu, beta, model, depth), ub)))
                add("constraint", ("u", pk, B), (pk, "u", B.T))
                add(f"volumetric:{region}", (pk, pk, -asm(forms.pressure_mass(kappa, model, depth), pbases[region])))
            else:
                c = materials.reduced(materials.get(tm.materials[region][0], user), model)[0]
                add(f"shear:{region}", ("u", "u", asm(forms.elastic(c, model, depth), ub)))
    parts = {kind: place(triples, offsets, n) for kind, triples in blocks.items()}
    A = sum(parts.values()) if parts else sp.csr_matrix((n, n))

    b, force = _load(scene, tm, eu, depth, n)
    fixed_by_support = _supports(scene, tm, ubases)
    fixed_u = np.unique(np.concatenate(list(fixed_by_support.values()) or [np.zeros(0, int)]))
    electrode_dofs, states = _electrodes(scene, tm, phibases, offsets["phi"].start)
    return System(scene, tm, A, b, offsets, ubases, pbases, phibases, constitutive, fixed_u,
                  fixed_by_support, electrode_dofs, states, force, yeoh, soft, parts)


def place(blocks, offsets, n) -> sp.csr_matrix:
    """An n x n matrix from (row block, column block, matrix) triples."""
    coo = [sp.coo_matrix(M) for *_, M in blocks]
    if not coo:
        return sp.csr_matrix((n, n))
    rows = np.concatenate([m.row + offsets[r].start for (r, _, _), m in zip(blocks, coo)])
    cols = np.concatenate([m.col + offsets[c].start for (_, c, _), m in zip(blocks, coo)])
    vals = np.concatenate([m.data for m in coo])
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))


def _load(scene: Scene, tm: TaggedMesh, eu, depth, n):
    """Full load vector (downward pressure on the "load" facets) and the total force (N)."""
    lay, model, ld = tm.layout, scene.model.type, scene.load
    dim = tm.mesh.dim()
    fb = FacetBasis(tm.mesh, eu, facets=tm.facets["load"], intorder=4)
    patch = lay.load

    def shape(x):
        if patch is None or lay.load_profile == "flat":
            return np.ones_like(x[0])
        if dim == 3:
            rho = np.hypot(x[0] - patch.x, x[1] - patch.y)
        else:
            rho = np.abs(x[0] - patch.x)
        return np.sqrt(np.clip(1 - (rho / patch.half) ** 2, 0, None))

    unit = forms.resultant(shape, model, depth).assemble(fb)
    if ld.kind == "pressure":
        p0, force = ld.pressure, ld.pressure * unit
    else:
        p0, force = ld.force / unit, ld.force
    b = np.zeros(n)
    b[:fb.N] = asm(forms.surface_pressure(lambda x: p0 * shape(x), model, depth, dim), fb)
    return b, force


def _supports(scene: Scene, tm: TaggedMesh, ubases) -> dict[str, np.ndarray]:
    """Constrained displacement DOFs (all homogeneous) by support."""
    lay, model, sup = tm.layout, scene.model.type, scene.supports
    dim = tm.mesh.dim()
    ub = next(iter(ubases.values()))
    comps = [f"u^{i + 1}" for i in range(dim)]
    vertical = comps[-1]
    out = {}

    def dofs(name, which=None):
        if name not in tm.facets:
            return np.zeros(0, int)
        d = ub.get_dofs(tm.facets[name])
        return d.all() if which is None else d.all(which)

    if sup.bottom == "bonded":
        out["bottom"] = dofs("bottom")
    elif sup.bottom == "rollers":
        out["bottom"] = dofs("bottom", [vertical])
        bottom_nodes = np.unique(tm.mesh.facets[:, tm.facets["bottom"]])
        centre = np.array([lay.plan.x, lay.plan.y][: dim - 1])
        if model != "axisymmetric":     # pin the in-plane rigid motion
            out["pin"] = _pins(tm, ub, bottom_nodes, centre)
    if sup.edges == "clamped":
        out["edges"] = dofs("edges")
    elif sup.edges == "rollers":
        if dim == 3 and lay.plan.shape == "disk":
            raise SceneError("supports.edges = 'rollers' needs a rectangular plan in 3d; "
                             "use 'clamped' or a rectangle")
        fac = tm.facets["edges"]
        if dim == 2:
            out["edges"] = ub.get_dofs(fac).all(["u^1"])
        else:
            mid = tm.mesh.p[:, tm.mesh.facets[:, fac]].mean(axis=1)
            on_x = np.abs(np.abs(mid[0]) - lay.plan.half) < 1e-9 * lay.plan.half
            out["edges"] = np.concatenate([ub.get_dofs(fac[on_x]).all(["u^1"]),
                                           ub.get_dofs(fac[~on_x]).all(["u^2"])])
    elif sup.edges == "simply_supported":       # hinged along the mid-plane line
        d = dofs("edges")
        out["edges"] = d[np.abs(ub.doflocs[dim - 1, d] - lay.midplane) < 1e-9 * lay.height]
    if model == "axisymmetric":
        out["axis"] = dofs("axis", ["u^1"])
    return out


def _pins(tm: TaggedMesh, ub, nodes, centre):
    """In-plane rigid-motion pins on the bottom: u_x (and u_y) at node k, and in 3D
    u_y at a node k2 on the same y line (so a free lateral expansion comes with no
    rigid rotation: harmless in a linear model, not strain-free in finite strain).
    k is the node nearest the centre among those with a partner on their y line."""
    dim = tm.mesh.dim()
    p = tm.mesh.p[: dim - 1, nodes]
    if dim == 2:
        k = nodes[np.argmin(np.abs(p[0] - centre[0]))]
        return np.array([ub.nodal_dofs[0, k]])
    tol = 1e-9 * max(np.ptp(p[0]), np.ptp(p[1]))
    y = np.round(p[1] / tol)
    _, inverse, counts = np.unique(y, return_inverse=True, return_counts=True)
    paired = counts[inverse] > 1
    cand = np.flatnonzero(paired) if paired.any() else np.arange(len(nodes))
    i = cand[np.argmin(np.linalg.norm(p[:, cand] - centre[:, None], axis=0))]
    same = np.flatnonzero(y == y[i]) if paired.any() else np.arange(len(nodes))
    j = same[np.argmax(np.abs(p[0, same] - p[0, i]))]
    return np.array([ub.nodal_dofs[0, nodes[i]], ub.nodal_dofs[1, nodes[i]], ub.nodal_dofs[1, nodes[j]]])


def _electrodes(scene: Scene, tm: TaggedMesh, phibases, offset):
    """Global phi DOFs of each electrode, and each one's state (one is the reference)."""
    names = [e.name for e in tm.layout.electrodes]
    for key in scene.electrodes:
        if key not in names and key != "taxels":
            raise SceneError(f"electrodes.{key}: no such electrode; this scene has: {', '.join(names)}")
    states = {}
    for name in names:
        s = "ground" if name in ("ground", "bottom") else "open"
        if name.startswith("taxel_") and "taxels" in scene.electrodes:
            s = electrode_state(scene.electrodes["taxels"])
        if name in scene.electrodes:
            s = electrode_state(scene.electrodes[name])
        states[name] = s
    if names and "ground" not in states.values():
        raise SceneError("electrodes: none is grounded, so the potential has no reference; "
                         "set one electrode to 'ground'")
    if names:
        states[next(k for k, s in states.items() if s == "ground")] = "reference"
    dofs = {}
    for name in names:
        d = [pb.get_dofs(tm.facets[name]).all() for pb in phibases.values() if name in tm.facets]
        dofs[name] = np.unique(np.concatenate(d)) + offset if d else np.zeros(0, int)
    return dofs, states


# --------------------------------------------------------------------------------------
# constrained solve
# --------------------------------------------------------------------------------------

@dataclass
class Reduction:
    """The constrained, collapsed unknowns: x_full = P y. Columns: free DOFs, then
    one potential per active electrode (whose equation is its charge balance)."""

    P: sp.csr_matrix
    nf: int
    active: list[str]
    ref: list[str]
    is_u: np.ndarray          # reduced unknowns that are displacements

    @property
    def n(self):
        return self.nf + len(self.active)

    def unit_charges(self):
        """Right-hand sides for Q_k = 1 C on each active electrode (rhs -Q)."""
        B = np.zeros((self.n, len(self.active)))
        B[self.nf + np.arange(len(self.active)), np.arange(len(self.active))] = -1.0
        return B


def reduction(sy: System, eliminate_grounded: bool = False) -> Reduction:
    """Drop fixed displacements, unused pressure/potential DOFs and the reference
    electrode (and, if asked, every grounded electrode); collapse active electrodes."""
    n = sy.A.shape[0]
    used = np.zeros(n, bool)
    used[sy.offsets["u"]] = True
    for region, pb in sy.pbases.items():
        used[sy.offsets[("p", region)].start + np.unique(pb.element_dofs)] = True
    phi0 = sy.offsets["phi"].start
    for pb in sy.phibases.values():
        used[phi0 + np.unique(pb.element_dofs)] = True
    used[sy.fixed_u] = False
    grounded = ("reference", "ground") if eliminate_grounded else ("reference",)
    ref = [k for k, s in sy.states.items() if s in grounded]
    active = [k for k, s in sy.states.items() if s not in grounded]
    for k in ref + active:
        used[sy.electrode_dofs[k]] = False
    free = np.flatnonzero(used)
    nf = len(free)
    col = np.full(n, -1)
    col[free] = np.arange(nf)
    for i, k in enumerate(active):
        col[sy.electrode_dofs[k]] = nf + i
    rows = np.flatnonzero(col >= 0)
    P = sp.csr_matrix((np.ones(len(rows)), (rows, col[rows])), shape=(n, nf + len(active)))
    return Reduction(P, nf, active, ref, np.append(free < sy.offsets["u"].stop, np.zeros(len(active), bool)))


def scaled_solver(A: sp.spmatrix, red: Reduction, method: str, scale: bool = True):
    """Factorize D A D once; return solve(B) -> (X, relative residuals), with
    iterative refinement reusing the factors."""
    D = _scaling(A, red.is_u) if scale else np.ones(red.n)
    As = (sp.diags(D) @ A @ sp.diags(D)).tocsc()
    factor = linsolve.factorize(As, method)

    def solve_(B):
        B = np.asarray(B).reshape(red.n, -1)
        Bs = D[:, None] * B
        Y = factor(Bs).reshape(Bs.shape)
        for _ in range(3):
            R = Bs - As @ Y
            norm_b = np.linalg.norm(Bs, axis=0)
            res = np.linalg.norm(R, axis=0) / np.where(norm_b > 0, norm_b, 1.0)    # zero rhs: zero error
            if res.max() < 1e-13:
                break
            Y = Y + factor(R).reshape(Bs.shape)
        X = D[:, None] * Y
        if not np.all(np.isfinite(X)):
            raise RuntimeError("linear solve produced non-finite values: the system is singular "
                               "(check the supports and that every piezo body touches a grounded electrode)")
        return X, res
    solve_.D = D
    return solve_


def _solve(sy: System, method: str, scale: bool) -> Solution:
    red = reduction(sy)
    nf, na = red.nf, len(red.active)
    A = (red.P.T @ sy.A @ red.P).tocsc()
    X, res = scaled_solver(A, red, method, scale)(np.column_stack([red.P.T @ sy.b, red.unit_charges()]))

    # open-circuit voltages, capacitance matrix, and the state the scene asks for
    Vf, Cinv = X[nf:, 0], X[nf:, 1:]
    fixedV = [i for i, k in enumerate(red.active) if sy.states[k] != "open"]
    Q = np.zeros(na)
    if fixedV:
        Vset = np.array([0.0 if sy.states[red.active[i]] == "ground" else sy.states[red.active[i]]
                         for i in fixedV])
        Q[fixedV] = np.linalg.solve(Cinv[np.ix_(fixedV, fixedV)], Vset - Vf[fixedV])
    x = red.P @ (X[:, 0] + X[:, 1:] @ Q)
    r = sy.A @ x - sy.b
    return results(sy, red, x, r, Cinv, linsolve.resolve(method, red.n), float(res.max()))


def results(sy: System, red: Reduction, x, r, Cinv, solver: str, residual: float) -> Solution:
    """Per-electrode numbers, reactions and fields from a solved state.

    x: full solution; r: full residual (A x - b: reactions at supports, charges at
    electrodes); Cinv: inverse capacitance matrix of the active electrodes.
    """
    na = len(red.active)
    C = np.linalg.inv(Cinv) if na else np.zeros((0, 0))
    V = np.array([x[sy.electrode_dofs[k][0]] for k in red.active])
    electrodes = {}
    for i, k in enumerate(red.active):
        st = sy.states[k]
        q = 0.0 if st == "open" else float(-r[sy.electrode_dofs[k]].sum())    # open: Q = 0 exactly
        qsc = float(q - (C @ V)[i])                # Q = Q_sc + C V
        electrodes[k] = ElectrodeResult(k, st if isinstance(st, str) else f"{st:g} V", float(V[i]), q,
                                        qsc, float(C[i, i]))
    for k in red.ref:                          # grounded: the charge is the residual of its rows
        q = float(-r[sy.electrode_dofs[k]].sum())
        electrodes[k] = ElectrodeResult(k, sy.states[k], 0.0, q, q, None)
    if len(red.ref) == 1 and red.active:       # charge is conserved: the one grounded electrode
        ref = electrodes[red.ref[0]]           # carries minus the others' (exactly, not to round-off)
        ref.charge = -sum(electrodes[k].charge for k in red.active)
        ref.short_circuit_charge = -sum(electrodes[k].short_circuit_charge for k in red.active)
    dim = sy.tm.mesh.dim()
    ub = next(iter(sy.ubases.values()))
    reaction = np.array([r[np.intersect1d(sy.fixed_u, _component_dofs(ub, c))].sum() for c in range(dim)])
    if sy.scene.model.type == "axisymmetric":
        reaction[0] = 0.0           # radial support forces cancel around the circle
    fields = _fields(sy, x)
    return Solution(sy.scene, electrodes, sy.applied_force, reaction, fields.pop("max_silicone_strain"),
                    red.n, solver, residual, {}, sy.tm, fields)


def _scaling(A, is_u):
    """Symmetric diagonal scaling D (A_s = D A D) for the coupled saddle-point system.

    Displacement rows: D_i = 1/sqrt(A_ii), so K_uu gets a unit diagonal.
    Pressure and potential rows: D_i = 1/sqrt(s_i), s_i = |A_ii| + sum_j A_ij^2 / A_jj
    over displacement columns j: the diagonal of the Schur complement
    |A_qq| + B K_uu^-1 B^T with K_uu replaced by its diagonal. Scaling by row
    maxima instead leaves that Schur complement at ~1e-16 for a steel plate or a
    PZT patch (coupling entries dominate the rows) and loses every digit.
    """
    diag = np.abs(A.diagonal())    # |.|: a hyperelastic tangent may lose definiteness mid-Newton
    is_u = np.append(is_u, np.zeros(A.shape[0] - len(is_u), bool))      # electrode unknowns
    s = diag.astype(float)
    if (~is_u).any():
        Aqu = A[~is_u][:, is_u]
        s[~is_u] += np.asarray(abs(Aqu).power(2) @ (1.0 / np.maximum(diag[is_u], 1e-300))).ravel()
    if not (s > 0).all():
        raise RuntimeError("the system has an empty row: a region without stiffness or an unconnected unknown")
    return 1.0 / np.sqrt(s)


def _component_dofs(ub, c):
    """All displacement DOFs of component c (nodal, edge or facet, interior)."""
    out = [ub.nodal_dofs[c]]
    if ub.facet_dofs.size and ub.mesh.dim() == 2:
        out.append(ub.facet_dofs[c])
    if ub.edge_dofs.size and ub.mesh.dim() == 3:
        out.append(ub.edge_dofs[c])
    if ub.interior_dofs.size:
        out.append(ub.interior_dofs[c])
    return np.concatenate(out)


def _fields(sy: System, x) -> dict:
    """Vertex values of u and phi, element-mean strain and stress, and the largest
    |principal strain| of the element-mean strains in the silicone (element means
    rather than point values: the strain is singular at taxel and load corners,
    so a point maximum grows without bound under refinement)."""
    model, mesh = sy.scene.model.type, sy.tm.mesh
    dim = mesh.dim()
    u = x[sy.offsets["u"]]
    phi = x[sy.offsets["phi"]]
    ub0 = next(iter(sy.ubases.values()))
    nS = {"3d": 6, "axisymmetric": 4}.get(model, 3)
    strain_cell = np.zeros((mesh.nelements, nS))
    stress_cell = np.zeros((mesh.nelements, nS))
    max_strain = 0.0
    for region, law in sy.constitutive.items():
        ub = sy.ubases[region]
        elems = sy.tm.regions[region]
        S = forms.strain(ub.interpolate(u), np.asarray(ub.global_coordinates()), model)      # (nS, ne, nq)
        if law[0] == "piezo":
            _, c, e, eps = law
            g = sy.phibases[region].interpolate(phi).grad
            T = np.einsum("ij,j...->i...", c, S) + np.einsum("ki,k...->i...", e, g)
        else:
            _, mu, lam, beta, kappa = law
            wts = np.array(forms.shear_weights(model))
            tr = forms.divergence(S, model)
            if region in sy.pbases:
                p = np.asarray(sy.pbases[region].interpolate(x[sy.offsets[("p", region)]]))
            else:
                p, beta = lam * tr, 0.0
            normal = np.zeros(nS)
            normal[: (3 if model in ("3d", "axisymmetric") else 2)] = 1
            T = 2 * mu * (wts[:, None, None] * S - beta * normal[:, None, None] * tr) + normal[:, None, None] * p
        strain_cell[elems] = S.mean(axis=2).T
        if law[0] == "solid" and region in sy.soft:
            max_strain = max(max_strain, _max_principal(strain_cell[elems].T, model, mu, lam))
        stress_cell[elems] = T.mean(axis=2).T
    vertex_u = u[ub0.nodal_dofs].T
    phi_vertex = np.zeros(mesh.nvertices)
    for pb in sy.phibases.values():
        phi_vertex[pb.nodal_dofs[0]] = phi[pb.nodal_dofs[0]]
    return {"u": vertex_u, "phi": phi_vertex, "strain": strain_cell, "stress": stress_cell,
            "max_silicone_strain": float(max_strain), "x": x}       # x: the full solution vector


def _max_principal(S, model, mu, lam):
    """max |principal strain| of Voigt strains S (nS, ...)."""
    if model == "3d":
        E = np.array([[S[0], S[5] / 2, S[4] / 2], [S[5] / 2, S[1], S[3] / 2], [S[4] / 2, S[3] / 2, S[2]]])
        extra = None
    else:
        xx, zz, xz = (S[0], S[2], S[3]) if model == "axisymmetric" else (S[0], S[1], S[2])
        E = np.array([[xx, xz / 2], [xz / 2, zz]])
        extra = {"axisymmetric": S[1] if model == "axisymmetric" else None,
                 "plane_stress": -lam / (lam + 2 * mu) * (xx + zz)}.get(model)
    ev = np.linalg.eigvalsh(np.moveaxis(E, (0, 1), (-2, -1)))
    m = np.abs(ev).max()
    return float(max(m, np.abs(extra).max()) if extra is not None else m)
