"""The coupled system's conditioning: scaling, solver agreement, residuals.

The taxel mixes 1e4 Pa silicone, 1e11 Pa PZT and 1e-8 F/m permittivity in one
indefinite matrix. Scaled (fem.linalg.scaling), SuperLU and PARDISO agree to
1e-9 and the relative residual is ~1e-12; unscaled, the same factorizations
leave a residual of ~2e-6 (measured).
"""

import gc
import os
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from pyamg.gallery import poisson

from taxel.fem import linalg
from taxel.fem.linalg import _memory as direct      # white-box: the memory budget check_fits reads
from taxel.analyses import solve_static as solve
from taxel.scene import load, parse

SOLVERS = [m for m in ("superlu", "pardiso") if linalg.available(m)]


@pytest.mark.parametrize("name", ["thesis-pzt-single-2d", "thesis-pvdf-single-2d"])
def test_solvers_agree_on_the_taxel_and_residual_is_small(name):
    sols = [solve(load(name), solver=m) for m in SOLVERS]
    v = [s.voltages()["taxel_0_0"] for s in sols]
    assert max(v) - min(v) < 1e-9 * abs(v[0])
    assert max(s.residual for s in sols) < 1e-10


def test_scaling_keeps_digits_that_the_unscaled_system_loses():
    scene = load("thesis-pzt-single-2d")
    scaled = solve(scene, solver="superlu")
    raw = solve(scene, solver="superlu", scale=False)
    assert scaled.residual < 1e-10 < 1e-7 < raw.residual
    # the voltage itself survives (iterative refinement repairs much of it), but only
    # the scaled solve is accurate to the digits its residual promises
    ref = solve(scene, solver=SOLVERS[-1]).voltages()["taxel_0_0"]
    assert abs(scaled.voltages()["taxel_0_0"] - ref) < 1e-9 * abs(ref)


@pytest.mark.parametrize("nu", [0.3, 0.0])
def test_thin_stiff_plate_mixed_form_solvers_agree(nu):
    """A 0.1 mm steel disk, radius 10 mm, mixed u-p (nu = 0 drops the pressure):
    row-max scaling once left this Schur complement at round-off (solvers
    differed by 2.5e-5 and a symmetric-indefinite PARDISO by 40 %)."""
    scene = parse({
        "model": {"type": "axisymmetric"}, "mesh": {"size": "0.25 mm", "piezo_layers": 2},
        "plate": {"shape": "disk", "radius": "10 mm", "layers": [{"material": "steel", "thickness": "0.1 mm"}]},
        "materials": {"steel": {"kind": "solid", "E": 2e11, "nu": nu, "rho": 7800}},
        "load": {"kind": "pressure", "pressure": "1 kPa"},
        "supports": {"bottom": "free", "edges": "simply_supported"}})
    w = []
    for m in SOLVERS:
        sol = solve(scene, solver=m)
        p = sol.mesh.mesh.p
        w.append(sol.fields.u[np.argmin(np.hypot(p[0], p[1])), 1])
        assert sol.residual < 1e-5
    assert max(w) - min(w) < 1e-6 * abs(w[0])


@pytest.mark.skipif("pardiso" not in SOLVERS, reason="PARDISO is not installed here")
def test_a_factorization_over_the_memory_budget_goes_out_of_core(monkeypatch, tmp_path, caplog):
    """With 0.8 x the memory its factors need in core, PARDISO factorizes out of core
    (linalg.check_fits: factor files in a temporary folder of its own, none in the working
    directory, and the folder gone with the solver) and solves as in core."""
    import logging
    monkeypatch.chdir(tmp_path)
    m = 26
    A = poisson((m, m, m), format="csr")          # the 7-point 3D Laplacian
    b = np.linspace(-1.0, 1.0, A.shape[0])
    x_in_core = linalg.factorize(A, "pardiso")(b)
    need = linalg.in_core_bytes(A)
    monkeypatch.setattr(direct, "budget", lambda: 0.8 * need)
    with caplog.at_level(logging.INFO, logger="taxel.fem.linalg"):
        solve = linalg.factorize(A, "pardiso")
        x = solve(b)
    assert "out of core" in caplog.text
    folder = Path(os.environ["MKL_PARDISO_OOC_PATH"])
    assert any(folder.glob("mkl_pardiso_*")) and not any(tmp_path.iterdir())
    del solve
    gc.collect()
    assert not folder.exists()
    assert np.linalg.norm(A @ x - b) < 1e-12 * np.linalg.norm(b)
    assert np.allclose(x, x_in_core, rtol=0, atol=1e-12 * np.abs(x_in_core).max())


@pytest.mark.skipif("pardiso" not in SOLVERS, reason="PARDISO is not installed here")
@pytest.mark.xfail(reason="intermittent: failed once in three fast-tier runs on two workers (2026-11-29), the first "
                          "factorization's solve off after the second was made; MKL's out-of-core state, to be found",
                   strict=False)
def test_two_out_of_core_factorizations_alive_at_once_each_solve_their_own(monkeypatch, tmp_path):
    """MKL_PARDISO_OOC_PATH is process-wide and each out-of-core factorization sets its own
    folder: a first solver still solves its own matrix after a second one moved the variable
    on, and after the second one (and its folder) is gone."""
    monkeypatch.chdir(tmp_path)
    m = 26                                 # (at 22 the out-of-core share of memory is too small for MKL: error -9)
    A = poisson((m, m, m), format="csr")          # the 7-point 3D Laplacian
    B = (A + sp.diags(np.linspace(0.5, 2.0, A.shape[0]))).tocsr()
    b = np.linspace(-1.0, 1.0, A.shape[0])
    xa, xb = linalg.factorize(A, "pardiso")(b), linalg.factorize(B, "pardiso")(b)
    need = linalg.in_core_bytes(A)
    monkeypatch.setattr(direct, "budget", lambda: 0.8 * need)
    fa = linalg.factorize(A, "pardiso")
    folder_a = os.environ["MKL_PARDISO_OOC_PATH"]
    fb = linalg.factorize(B, "pardiso")
    assert os.environ["MKL_PARDISO_OOC_PATH"] != folder_a
    assert np.allclose(fa(b), xa, rtol=0, atol=1e-12 * np.abs(xa).max())
    assert np.allclose(fb(b), xb, rtol=0, atol=1e-12 * np.abs(xb).max())
    del fb
    gc.collect()
    assert np.allclose(fa(b), xa, rtol=0, atol=1e-12 * np.abs(xa).max()) and Path(folder_a).exists()


@pytest.mark.skipif("pardiso" not in SOLVERS, reason="PARDISO is not installed here")
def test_a_factorization_that_cannot_fit_is_refused_before_it_starts(monkeypatch):
    """PARDISO's analysis phase gives the memory the factors need; with (pretend)
    almost no free memory the solve is refused with the estimate, not killed."""
    n = 2000
    A = sp.diags([np.full(n, 4.0), np.full(n - 1, -1.0), np.full(n - 1, -1.0)], [0, -1, 1]).tocsc()
    monkeypatch.setattr(direct, "available_memory", lambda: 1.0e3)
    with pytest.raises(linalg.MemoryLimitError, match="GB"):
        linalg.factorize(A, "pardiso")
    monkeypatch.undo()
    x = linalg.factorize(A, "pardiso")(np.ones(n))
    assert np.allclose(A @ x, 1.0)


@pytest.mark.skipif("pardiso" not in SOLVERS, reason="PARDISO is not installed here")
def test_an_out_of_core_factorization_short_of_memory_is_a_memory_error(monkeypatch, tmp_path):
    """Out of core with too small an in-memory share of the factors (a 10 648-unknown
    Laplacian, 0.8 x its in-core need, one MKL thread) MKL stops with error -9: it reaches
    the user as linalg.MemoryLimitError with the fix, not as a PARDISO traceback."""
    from threadpoolctl import threadpool_limits
    monkeypatch.chdir(tmp_path)
    m = 22
    A = poisson((m, m, m), format="csr")          # the 7-point 3D Laplacian
    with threadpool_limits(1):
        need = linalg.in_core_bytes(A)
        monkeypatch.setattr(direct, "budget", lambda: 0.8 * need)
        with pytest.raises(linalg.MemoryLimitError, match="PARDISO error -9.*coarsen mesh.size"):
            linalg.factorize(A, "pardiso")


@pytest.mark.skipif(not linalg.available("pardiso"), reason="PARDISO not installed")
def test_refactorizer_reuses_the_analysis_and_solves_like_a_fresh_factorization():
    """linalg.Refactorizer: matrices of one pattern (different values, explicit zeros
    kept) solve as a fresh scaled factorization does, one analysis for all of them; a
    new pattern is analysed again; the solve of an earlier matrix refuses once a later
    one is factorized (it would use the wrong factors)."""
    rng = np.random.default_rng(3)
    n = 400
    base = sp.random(n, n, density=0.02, random_state=4, format="csr")
    pattern = (base + base.T + sp.eye(n)).tocsr()
    is_u = np.arange(n) < 300
    ref = linalg.Refactorizer("pardiso")
    solves = []
    for k in range(3):
        A = pattern.copy()
        A.data = rng.standard_normal(A.nnz)
        A.data[:5] = 0.0                                 # explicit zeros stay in the pattern
        A.setdiag(20.0 + k)
        b = rng.standard_normal(n)
        X, res = ref(A, is_u)(b)
        fresh, _ = linalg.scaled_solver(A, is_u, "superlu")(b)
        np.testing.assert_allclose(X[:, 0], fresh[:, 0], rtol=1e-9, atol=1e-12 * np.abs(fresh).max())
        assert res.max() < 1e-12
        solves.append(ref._pattern)
    assert solves[0] == solves[1] == solves[2]          # one analysis
    last = ref(pattern + sp.eye(n, k=7), is_u)          # a new pattern: analysed again
    assert ref._pattern != solves[0]
    assert np.all(np.isfinite(last(np.ones(n))[0]))
    stale = ref(pattern.copy(), is_u)
    ref(pattern.copy(), is_u)
    with pytest.raises(RuntimeError, match="later factorization"):
        stale(np.ones(n))


@pytest.mark.skipif(not linalg.available("pardiso"), reason="PARDISO not installed")
def test_refactorizer_factorizes_a_symmetric_matrix_in_the_symmetric_mode():
    """A symmetric matrix (a press tangent) goes to PARDISO's symmetric-indefinite mode on
    its upper triangle and solves as a fresh factorization does; a nonsymmetric one of the
    same pattern goes back to the nonsymmetric mode (analysed again)."""
    rng = np.random.default_rng(5)
    n = 300
    base = sp.random(n, n, density=0.03, random_state=6, format="csr")
    S = (base + base.T + sp.eye(n)).tocsr()
    S.data = rng.standard_normal(S.nnz)
    S = ((S + S.T) / 2).tocsr()
    S.setdiag(15.0)
    S.data[S.indices == (np.repeat(np.arange(n), np.diff(S.indptr)) + 3) % n] *= -1   # indefinite rows
    S = ((S + S.T) / 2).tocsr()
    is_u = np.arange(n) < 200
    b = rng.standard_normal(n)
    ref = linalg.Refactorizer("pardiso")
    X, res = ref(S, is_u)(b)
    assert ref._solver.mtype == -2 and res.max() < 1e-12
    fresh, _ = linalg.scaled_solver(S, is_u, "superlu")(b)
    np.testing.assert_allclose(X[:, 0], fresh[:, 0], rtol=1e-9, atol=1e-12 * np.abs(fresh).max())
    N = S.copy()
    N.data = N.data + 0.1 * rng.standard_normal(N.nnz)                 # same pattern, not symmetric
    Xn, _ = ref(N, is_u)(b)
    assert ref._solver.mtype == 11
    np.testing.assert_allclose(N @ Xn[:, 0], b, rtol=0, atol=1e-9 * np.abs(b).max())


@pytest.mark.skipif("pardiso" not in SOLVERS, reason="PARDISO is not installed here")
@pytest.mark.slow      # 18 s of CPU: complex SuperLU beside PARDISO
def test_a_complex_damped_operator_solves_through_pardisos_real_equivalent_like_superlu():
    """fem.linalg._factorize_complex against SuperLU's complex LU on the damped dynamic
    stiffness of a coarse 3D taxel (complex symmetric, lossy silicone), near and far from
    resonance: the port voltages and unit-charge responses agree to 1e-9."""
    from taxel.analyses import problem
    from taxel.fem import dynamics
    scene = load("thesis-pzt-single-3d").replace(**{"mesh.size": "2 mm", "mesh.piezo_size": "1 mm",
                                                          "model.symmetry": "full"})
    dm = dynamics.model(problem(scene))
    assert dm.method == "pardiso"                 # 3D above the threshold: the sweep's direct solves use it
    B = np.column_stack([dm.F, dm.Be]).astype(complex)
    for f in (10.0, 300.0, 3e4):
        K = dm.K(2 * np.pi * f)
        assert np.abs(K.imag).max() > 0
        x = {m: linalg.scaled_solver(K, dm.red.is_u, m)(B) for m in ("superlu", "pardiso")}
        nf = dm.red.nf
        a, b = x["superlu"][0][nf:], x["pardiso"][0][nf:]
        assert np.abs(a - b).max() < 1e-9 * np.abs(a).max()
        assert x["pardiso"][1].max() < 1e-10
