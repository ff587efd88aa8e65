"""Independent-code check of the Yeoh u-p solve against FELupe (see
benchmarks/felupe_compare.py for the set-up and the findings).

A bonded plane-strain block, 10 x 5 mm, 12 kPa dead load on the top (10 % top
compression at the centre, 25 % at the free corners). FELupe solves the same mesh
(P2 u, P1 p, P1 Jbar, NearlyIncompressible Yeoh, skfem's quadrature, consistent
nodal dead load) with its corrected P2 triangle gradient; both Newtons to 1e-12.
Measured: vertex displacements agree to ~1e-14 relative, nodal support reactions
to ~1e-15, the total reaction to round-off.
"""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

fe = pytest.importorskip("felupe")
pytest.importorskip("tensortrax")      # FELupe's automatic-differentiation hyperelastic models

_spec = importlib.util.spec_from_file_location(
    "felupe_compare", Path(__file__).resolve().parents[1] / "benchmarks" / "felupe_compare.py")
fc = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fc)


@pytest.fixture(scope="module")
def block():
    sc = fc.scene()
    return sc, fc.tagged_mesh(sc)


@pytest.fixture(scope="module")
def agreement(block):
    return fc.compare(*block)


def test_block_is_compressed_by_tens_of_percent(agreement):
    sol = agreement["sol"]
    m, u = sol.mesh.mesh, sol.fields.u
    top = np.isclose(m.p[1], fc.HEIGHT)
    uz = u[top, 1] / fc.HEIGHT
    assert sol.newton.converged
    assert uz.min() < -0.2 and uz.mean() < -0.12      # corners ~25 %, mean ~14 %


def test_vertex_displacements_agree_with_felupe(agreement):
    assert agreement["du"] < 1e-9            # measured ~1e-14
    assert agreement["du_all"] < 1e-9        # midside nodes too


def test_support_reactions_agree_with_felupe(agreement):
    assert agreement["dr"] < 1e-9            # nodal reactions on the bonded bottom
    R_ours, R_fe = agreement["R_ours"], agreement["R_fe"]
    assert R_fe[1] == pytest.approx(R_ours[1], rel=1e-9)
    assert R_ours[1] == pytest.approx(fc.PRESSURE * fc.WIDTH * fc.DEPTH, rel=1e-9)   # dead load: equilibrium
    assert abs(R_fe[0] - R_ours[0]) < 1e-9 * R_ours[1]


def test_corrected_p2_gradient_matches_felupe_shape_functions():
    el, fixed = fe.QuadraticTriangle(), fc.quadratic_triangle_fixed()
    h = 1e-6
    for rs in ([0.2, 0.3], [0.1, 0.7], [1 / 3, 1 / 3], [0.6, 0.05]):
        rs = np.array(rs)
        fd = np.array([(el.function(rs + h * e) - el.function(rs - h * e)) / (2 * h) for e in np.eye(2)]).T
        np.testing.assert_allclose(fixed.gradient(rs), fd, atol=1e-8)


@pytest.mark.xfail(reason="FELupe 11.3 QuadraticTriangle.gradient: d h5/ds coded as 4(1-2r-s), "
                          "not 4(1-r-2s); passes once FELupe fixes it", strict=False)
def test_stock_felupe_p2_gradient():
    el, h = fe.QuadraticTriangle(), 1e-6
    rs = np.array([0.2, 0.3])
    fd = np.array([(el.function(rs + h * e) - el.function(rs - h * e)) / (2 * h) for e in np.eye(2)]).T
    np.testing.assert_allclose(el.gradient(rs), fd, atol=1e-8)
