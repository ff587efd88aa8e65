"""The iterative solver (fem.linalg): equal to the direct one where both run, and a
failing preconditioner is an error, never a quiet answer."""

import numpy as np
import pytest

from taxel.analyses import problem
from taxel.fem import linalg
from taxel.fem.assembly import assemble
from taxel.fem.assembly import elimination
from taxel.fem.static import solve_linear
from taxel.scene import load


# a coarse 3D taxel (2 888 unknowns): Krylov against direct in about a second; the 2 mm mesh
# (GMRES tens of seconds) is the slow test below
COARSE = {"mesh.size": "3 mm", "mesh.piezo_size": "1.5 mm", "mesh.piezo_layers": 1}


@pytest.fixture(scope="module")
def system():
    return assemble(problem(load("thesis-pzt-single-3d").replace(**COARSE)))


def test_krylov_equals_direct_on_a_3d_taxel(system):
    _krylov_equals_direct(system)


@pytest.mark.slow
def test_krylov_equals_direct_on_the_3d_taxel_at_2_mm():
    _krylov_equals_direct(assemble(problem(load("thesis-pzt-single-3d").replace(**{"mesh.size": "2 mm"}))))


def _krylov_equals_direct(system):
    direct = solve_linear(system, "superlu")
    it = solve_linear(system, "krylov")
    assert it.solver == "krylov" and it.residual <= 1e-10
    for k, e in direct.electrodes.items():
        assert abs(it.electrodes[k].voltage - e.voltage) <= 1e-8 * abs(direct.voltages()["taxel_0_0"])
        assert abs(it.electrodes[k].charge - e.charge) <= 1e-8 * abs(e.short_circuit_charge) + 1e-30
        if e.capacitance is not None:
            assert abs(it.electrodes[k].capacitance - e.capacitance) <= 1e-8 * e.capacitance
    assert np.abs(it.fields.u - direct.fields.u).max() <= 1e-8 * np.abs(direct.fields.u).max()


def _reduced(sy):
    red = elimination(sy)
    return (red.P.T @ sy.A @ red.P).tocsc(), red


@pytest.mark.parametrize("options", [{"schur_scale": 1e-7, "maxiter": 300}, {"maxiter": 5}])
def test_a_failing_preconditioner_is_reported(system, options):
    """A Schur block scaled 1e7 too small, or too few iterations: KrylovError naming
    the residual reached, not a returned vector."""
    A, red = _reduced(system)
    solve = linalg.krylov_solver(A, linalg.krylov_blocks(system, red), **options)
    with pytest.raises(linalg.KrylovError, match="relative residual"):
        solve(red.P.T @ system.b)


def test_auto_picks_krylov_only_for_static_solves_above_the_threshold():
    assert linalg.resolve("auto", linalg.AUTO_KRYLOV_ABOVE + 1, iterative=True, dim=3) == "krylov"
    assert linalg.resolve("auto", linalg.AUTO_KRYLOV_ABOVE + 1, dim=3) != "krylov"
    assert linalg.resolve("auto", 1000, iterative=True, dim=2) == "superlu"
    with pytest.raises(ValueError, match="static linear problems only"):
        linalg.factorize(np.eye(3), "krylov")
