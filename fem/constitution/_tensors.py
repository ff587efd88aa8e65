"""Tensor algebra of the linear piezoelectric constants: the strain-charge and
stress-charge forms, rotation to the global frame, and the exact reductions to the
2D models (plane strain, plane stress, axisymmetric).

Voigt order 11, 22, 33, 23, 13, 12 (IEEE 176); engineering shear strains; SI units.
Conventions of the frames: fem.constitution._materials.
"""

from __future__ import annotations

import math

import numpy as np

# Voigt index pairs, IEEE order.
_VOIGT = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]


# --------------------------------------------------------------------------------------
# form conversions, rotation
# --------------------------------------------------------------------------------------

def strain_to_stress_charge(s, d, eps_T):
    """(s^E, d, eps^T) -> (c^E, e, eps^S): c = s^-1, e = d c, eps^S = eps^T - d c d^T."""
    c = np.linalg.inv(s)
    e = d @ c
    return symmetric(c), e, symmetric(eps_T - d @ c @ d.T)


def stress_to_strain_charge(c, e, eps_S):
    """(c^E, e, eps^S) -> (s^E, d, eps^T): s = c^-1, d = e s, eps^T = eps^S + d c d^T."""
    s = np.linalg.inv(c)
    d = e @ s
    return symmetric(s), d, symmetric(eps_S + d @ c @ d.T)


def symmetric(a):
    """The symmetric part of a matrix."""
    return 0.5 * (a + a.T)


def poling_rotation(direction) -> np.ndarray:
    """Rotation R (columns: local axes in global) taking local 3 to `direction`.

    Local 1 stays as close to global x as possible, so a film's drawing direction
    (local 1) lies along x for poling +z or -z.
    """
    n = np.asarray(direction, float)
    n = n / np.linalg.norm(n)
    a1 = np.array([1.0, 0, 0]) if abs(n[0]) < 0.9 else np.array([0, 1.0, 0])
    a1 = a1 - n * (a1 @ n)
    a1 /= np.linalg.norm(a1)
    return np.column_stack([a1, np.cross(n, a1), n])


def _to_tensor4(c):
    t = np.empty((3, 3, 3, 3))
    for I, (i, j) in enumerate(_VOIGT):
        for J, (k, l) in enumerate(_VOIGT):
            t[i, j, k, l] = t[j, i, k, l] = t[i, j, l, k] = t[j, i, l, k] = c[I, J]
    return t


def _to_tensor3(e):
    t = np.empty((3, 3, 3))
    for J, (i, j) in enumerate(_VOIGT):
        t[:, i, j] = t[:, j, i] = e[:, J]
    return t


def rotate(c, e, eps, R):
    """Tensors given in the frame of R's columns, expressed in the global frame.

    c'_ijkl = R_ia R_jb R_kc R_ld c_abcd, e'_kij = R_ka R_ib R_jc e_abc, eps' = R eps R^T.
    Voigt components of c and e equal tensor components (stress-like indices), so
    the rotation is exact without Bond-matrix factors.
    """
    c4 = np.einsum("ia,jb,kc,ld,abcd->ijkl", R, R, R, R, _to_tensor4(c))
    e3 = np.einsum("ka,ib,jc,abc->kij", R, R, R, _to_tensor3(e))
    idx = np.array(_VOIGT)
    c_v = c4[idx[:, 0][:, None], idx[:, 1][:, None], idx[:, 0][None, :], idx[:, 1][None, :]]
    e_v = e3[:, idx[:, 0], idx[:, 1]]
    return symmetric(c_v), e_v, symmetric(R @ eps @ R.T)


# --------------------------------------------------------------------------------------
# reductions to 2D
# --------------------------------------------------------------------------------------

# Voigt rows kept by each model (x-z cross-section; axisymmetric r, theta, z).
PLANE_STRAIN_IDX = ([0, 2, 4], [0, 2])     # S: xx, zz, 2xz;  E: x, z
AXISYM_IDX = ([0, 1, 2, 4], [0, 2])        # S: rr, tt, zz, 2rz;  E: r, z


def plane_strain_tensors(c, e, eps):
    """Plane strain in x-z: S_yy = S_yz = S_xy = 0, E_y = 0.

    With those strains and field zero, T = c S - e^T E keeps only the columns of
    the kept components, so the reduced stress-charge tensors are exact
    sub-matrices: c[[xx,zz,xz]][:, same], e[[x,z]][:, same], eps[[x,z]][:, [x,z]].
    """
    s, f = PLANE_STRAIN_IDX
    return c[np.ix_(s, s)], e[np.ix_(f, s)], eps[np.ix_(f, f)]


def plane_stress_tensors(c, e, eps):
    """Plane stress in x-z: T_yy = T_yz = T_xy = 0 and E_y = 0 (thin in y, no field across it).

    In strain-charge form S = s T + d^T E, D = d T + eps^T E the out-of-plane
    stresses are zero, so the in-plane strains and charges depend only on the kept
    stresses and fields: the reduced strain-charge tensors are exact sub-matrices
    of (s, d, eps^T). Converting them back gives the reduced stress-charge tensors.
    """
    s, d, eps_T = stress_to_strain_charge(c, e, eps)
    k, f = PLANE_STRAIN_IDX
    return strain_to_stress_charge(s[np.ix_(k, k)], d[np.ix_(f, k)], eps_T[np.ix_(f, f)])


def axisymmetric_tensors(c, e, eps):
    """Axisymmetric (r, theta, z): torsion-free, S_rt = S_tz = 0, E_t = 0.

    Exact for a material transversely isotropic about z (then the tensors are the
    same in every meridian plane): sub-matrices of the stress-charge form for
    rr, tt, zz, rz and E_r, E_z. Raises for materials that are not.
    """
    R = np.array([[math.cos(0.7), -math.sin(0.7), 0], [math.sin(0.7), math.cos(0.7), 0], [0, 0, 1]])
    cr, er, epsr = rotate(c, e, eps, R)
    # 1e-3: tables round s66 = 2 (s11 - s12) (PZT-5H: 42.6 vs 42.56 pm^2/N)
    if not (np.allclose(cr, c, rtol=0, atol=1e-3 * np.abs(c).max())
            and np.allclose(er, e, rtol=0, atol=1e-3 * max(np.abs(e).max(), 1e-30))):
        raise ValueError("material is not transversely isotropic about the z axis "
                         "(an axisymmetric model needs that); use a 3D or plane model")
    s, f = AXISYM_IDX
    return c[np.ix_(s, s)], e[np.ix_(f, s)], eps[np.ix_(f, f)]


MODEL_TENSORS = {
    "3d": lambda c, e, eps: (c, e, eps),
    "plane_strain": plane_strain_tensors,
    "plane_stress": plane_stress_tensors,
    "axisymmetric": axisymmetric_tensors,
}
