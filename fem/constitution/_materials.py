"""Material library: piezoelectric tensors, isotropic solids, and their 2D reductions.

Conventions
-----------
Axes: 3 is the poling (thickness) direction of a piezo in its own frame, 1 and 2 in
plane. Voigt order 11, 22, 33, 23, 13, 12 (IEEE 176); engineering shear strains.
SI units everywhere: Pa, C/m^2, F/m, m^2/N, C/N, kg/m^3.

Two equivalent constitutive forms (IEEE 176):

    strain-charge:  S = s^E T + d^T E,      D = d T + eps^T E
    stress-charge:  T = c^E S - e^T E,      D = e S + eps^S E

    c^E = (s^E)^-1,  e = d c^E,  eps^S = eps^T - d c^E d^T      (and back).

Global frame of a scene: x, y in the plane of the sensor, z up (thickness). 2D
cross-sections are the x-z plane; the mesh's second coordinate is z. Axisymmetric
models use (r, z) with the theta direction as the 3D y axis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cache
from pathlib import Path

import numpy as np

EPS0 = 8.8541878128e-12  # F/m, CODATA 2018

# Marechal et al. (2021) uniaxial test of Ecoflex 00-30, the data behind the Yeoh sets (fem/data/SOURCES.md)
ECOFLEX_UNIAXIAL_CSV = Path(__file__).parent.parent / "data" / "ecoflex-00-30-uniaxial.csv"

# Voigt index pairs, IEEE order.
_VOIGT = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]


@dataclass(frozen=True)
class Piezo:
    """A linear piezoelectric in stress-charge form, in the global frame.

    c: (6, 6) Pa, e: (3, 6) C/m^2, eps: (3, 3) F/m (clamped, eps^S), rho kg/m^3.
    """

    name: str
    c: np.ndarray
    e: np.ndarray
    eps: np.ndarray
    rho: float
    source: str = ""
    Qm: float | None = None           # mechanical quality factor (used by dynamics)
    tan_delta: float | None = None    # dielectric loss tangent

    kind = "piezo"

    @classmethod
    def from_strain_charge(cls, name, s, d, eps_T, rho, **kw) -> "Piezo":
        c, e, eps_S = strain_to_stress_charge(s, d, eps_T)
        return cls(name, c, e, eps_S, rho, **kw)

    def strain_charge(self):
        """(s^E, d, eps^T) of this material."""
        return stress_to_strain_charge(self.c, self.e, self.eps)

    def poled(self, direction) -> "Piezo":
        """This material with its poling axis (local 3) along `direction` (global)."""
        return replace(self, **dict(zip(("c", "e", "eps"),
                                        rotate(self.c, self.e, self.eps, poling_rotation(direction)))))

    @property
    def d33(self):
        return self.strain_charge()[1][2, 2]

    @property
    def g33(self):
        s, d, eps_T = self.strain_charge()
        return d[2, 2] / eps_T[2, 2]


@dataclass(frozen=True)
class Solid:
    """An isotropic linear-elastic solid (here: the silicone), shear and bulk moduli.

    mu and K in Pa. For the nearly incompressible silicone K is a modelling
    parameter (no sourced value exists): the solver's mixed u-p formulation is
    robust for any K/mu, including very large ones.
    """

    name: str
    mu: float
    K: float
    rho: float
    eps_r: float = 1.0
    source: str = ""
    yeoh: tuple[float, float, float] | None = None   # C10, C20, C30 in Pa

    kind = "solid"

    @property
    def lam(self):
        return self.K - 2.0 * self.mu / 3.0

    @property
    def E(self):
        return 9.0 * self.K * self.mu / (3.0 * self.K + self.mu)

    @property
    def nu(self):
        return (3.0 * self.K - 2.0 * self.mu) / (2.0 * (3.0 * self.K + self.mu))

    @classmethod
    def from_E_nu(cls, name, E, nu, rho, **kw) -> "Solid":
        return cls(name, mu=E / (2 * (1 + nu)), K=E / (3 * (1 - 2 * nu)), rho=rho, **kw)

    def stiffness(self) -> np.ndarray:
        """6x6 Voigt stiffness: c = lam 1x1 + mu diag(2, 2, 2, 1, 1, 1)."""
        c = np.zeros((6, 6))
        c[:3, :3] = self.lam
        c += self.mu * np.diag([2.0, 2, 2, 1, 1, 1])
        return c


# --------------------------------------------------------------------------------------
# form conversions, rotation
# --------------------------------------------------------------------------------------

def strain_to_stress_charge(s, d, eps_T):
    """(s^E, d, eps^T) -> (c^E, e, eps^S): c = s^-1, e = d c, eps^S = eps^T - d c d^T."""
    c = np.linalg.inv(s)
    e = d @ c
    return _sym(c), e, _sym(eps_T - d @ c @ d.T)


def stress_to_strain_charge(c, e, eps_S):
    """(c^E, e, eps^S) -> (s^E, d, eps^T): s = c^-1, d = e s, eps^T = eps^S + d c d^T."""
    s = np.linalg.inv(c)
    d = e @ s
    return _sym(s), d, _sym(eps_S + d @ c @ d.T)


def _sym(a):
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
    return _sym(c_v), e_v, _sym(R @ eps @ R.T)


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


def model_tensors(material, model: str):
    """(c, e, eps) of `material` for `model`; a Solid has e = 0 and eps = eps_r eps0."""
    if isinstance(material, Piezo):
        return MODEL_TENSORS[model](material.c, material.e, material.eps)
    c = material.stiffness()
    return MODEL_TENSORS[model](c, np.zeros((3, 6)), material.eps_r * EPS0 * np.eye(3))


# --------------------------------------------------------------------------------------
# the library
# --------------------------------------------------------------------------------------

def _pzt5h() -> Piezo:
    """Generic PZT-5H, strain-charge set of Erturk and Inman, Piezoelectric Energy
    Harvesting (2011), App. E, Table E.1 (docs/materials.md)."""
    p = 1e-12
    s = _transversely_isotropic_compliance(16.5 * p, -4.78 * p, -8.45 * p, 20.7 * p, 43.5 * p, 42.6 * p)
    d = _pz_d(d31=-274e-12, d33=593e-12, d15=741e-12)
    eps_T = np.diag([3130, 3130, 3400]) * EPS0
    return Piezo.from_strain_charge("PZT-5H", s, d, eps_T, rho=7500.0,
                                    source="Erturk & Inman 2011, App. E, Table E.1",
                                    Qm=65.0, tan_delta=0.02)


def _psi5h4e() -> Piezo:
    """PSI-5H4E (Piezo Systems datasheet; the thesis's PZT).

    The datasheet gives d33 = 650, d31 = -320 pC/N, K3^T = 3800, Y3^E = 5.0e10 and
    Y1^E = 6.2e10 Pa, rho = 7800, Qm = 32, but no full matrix. We build one that
    reproduces those numbers exactly:
      s11 = 1/Y1, s33 = 1/Y3 (the datasheet's Young moduli);
      Poisson ratios nu12 = -s12/s11 = 0.290 and nu13 = -s13/s33 = 0.408 from
      generic PZT-5H (Erturk & Inman), so s12 = -0.290 s11, s13 = -0.408 s33;
      s44 = s55 = 52.4 pm^2/N and d15 = 1000 pC/N from the later sheet of the same
      family (CTS 3203HD-like, docs/materials.md); s66 = 2 (s11 - s12);
      eps11^T = 3130 * 3800/3400 eps0 (generic ratio eps11/eps33, scaled);
      eps33^T = 3800 eps0.
    Checks (tests): g33 = d33/eps33^T = 19.3e-3 Vm/N (sheet 19.0e-3), k31 = 0.43
    (sheet 0.44), k33 = 0.79 (sheet 0.75), positive definite.
    """
    p = 1e-12
    s11, s33 = 1 / 6.2e10, 1 / 5.0e10
    nu12, nu13 = 4.78 / 16.5, 8.45 / 20.7
    s = _transversely_isotropic_compliance(s11, -nu12 * s11, -nu13 * s33, s33, 52.4 * p)
    d = _pz_d(d31=-320e-12, d33=650e-12, d15=1000e-12)
    eps_T = np.diag([3130 * 3800 / 3400, 3130 * 3800 / 3400, 3800]) * EPS0
    return Piezo.from_strain_charge("PSI-5H4E", s, d, eps_T, rho=7800.0,
                                    source="Piezo Systems PSI-5H4E datasheet; full matrix built "
                                           "from its transversely isotropic constants",
                                    Qm=32.0, tan_delta=0.02)


def _pvdf() -> Piezo:
    """PVDF film, TE/Measurement Specialties Piezo Film Sensors Technical Manual, Table 1.

    d31 = +23, d33 = -33 pC/N; eps_r = 12 (the manual's 12-13; 12 reproduces its
    g31 = 216e-3 Vm/N); rho = 1780; tan delta 0.02. Not in the table, assumed here:
    d32 = 3 pC/N (uniaxially drawn film, drawing direction = local 1), d15 = d24 = 0,
    isotropic elasticity with E = 3 GPa (the middle of the manual's 2-4 GPa) and
    nu = 0.34 (typical semicrystalline polymer). Thesis Table 2.1 swaps d31/d33 and
    the g signs (docs/materials.md errata); these are the manual's values.
    """
    E, nu = 3.0e9, 0.34
    s = np.zeros((6, 6))
    s[:3, :3] = -nu / E
    np.fill_diagonal(s[:3, :3], 1 / E)
    s[3:, 3:] = np.eye(3) * 2 * (1 + nu) / E
    d = np.zeros((3, 6))
    d[2, 0], d[2, 1], d[2, 2] = 23e-12, 3e-12, -33e-12
    return Piezo.from_strain_charge("PVDF", s, d, np.eye(3) * 12.0 * EPS0, rho=1780.0,
                                    source="TE Piezo Film Sensors Technical Manual, Table 1; "
                                           "d32, E, nu assumed",
                                    Qm=10.0, tan_delta=0.02)


# Incompressible Yeoh least-squares fits to the Marechal et al. uniaxial test of Ecoflex
# 00-30 (Soft Robotics Materials Database; nominal stress vs engineering strain), by
# the strain range fitted; docs/materials.md, reproduced by fem.constitution (tests/test_yeoh_fit.py).
ECOFLEX_YEOH = {
    "fit50": (6.70e3, 1.93e3, -1.07e3),
    "fit100": (7.18e3, 0.619e3, -0.114e3),
    "fit300": (7.83e3, 0.103e3, -0.0008e3),
}


def _ecoflex0030(fit="fit300") -> Solid:
    """Ecoflex 00-30 (Smooth-On) with one of the published Yeoh sets.

    The default "Ecoflex-00-30" uses the fit to 300 % strain: it is the only set
    whose energy stays stable (dP/dlambda > 0) in uniaxial, equibiaxial and pure
    shear from stretch 0.5 to 4; the 50 % set, closer at small strain, loses
    stability in equibiaxial tension at 36 % strain and the 100 % set at 72 %
    (fem.constitution.stability_limit), strains a 1 N press reaches. Linear model:
    mu = 2 C10 (the small-strain limit of the same energy). K = 1000 mu
    (nu = 0.4995) is a modelling choice: no sourced bulk modulus exists.
    rho = 1070 kg/m^3, eps_r = 2.8 (docs/materials.md).
    """
    C = ECOFLEX_YEOH[fit]
    name = "Ecoflex-00-30" if fit == "fit300" else f"Ecoflex-00-30-{fit}"
    return Solid(name, mu=2 * C[0], K=1000 * 2 * C[0], rho=1070.0, eps_r=2.8,
                 source=f"Marechal et al., Soft Robotics Materials Database (Yeoh {fit}); K = 1000 mu assumed",
                 yeoh=C)


def _transversely_isotropic_compliance(s11, s12, s13, s33, s44, s66=None):
    """s^E of a hexagonal (6mm) material; s66 = 2 (s11 - s12) unless a table gives it."""
    s = np.zeros((6, 6))
    s[0, 0] = s[1, 1] = s11
    s[0, 1] = s[1, 0] = s12
    s[0, 2] = s[2, 0] = s[1, 2] = s[2, 1] = s13
    s[2, 2] = s33
    s[3, 3] = s[4, 4] = s44
    s[5, 5] = 2 * (s11 - s12) if s66 is None else s66
    return s


def _pz_d(d31, d33, d15):
    d = np.zeros((3, 6))
    d[2, 0] = d[2, 1] = d31
    d[2, 2] = d33
    d[0, 4] = d[1, 3] = d15
    return d


@cache
def library() -> dict:
    mats = [_psi5h4e(), _pzt5h(), _pvdf(), *(_ecoflex0030(f) for f in ECOFLEX_YEOH)]
    return {m.name.lower(): m for m in mats}


ALIASES = {"pzt": "psi-5h4e", "ecoflex": "ecoflex-00-30", "silicone": "ecoflex-00-30"}


def get(name: str, user: dict | None = None):
    """A material by name (case-insensitive), from `user` materials first, then the library."""
    key = name.lower()
    if user and key in {k.lower() for k in user}:
        return {k.lower(): v for k, v in user.items()}[key]
    key = ALIASES.get(key, key)
    lib = library()
    if key not in lib:
        known = ", ".join(m.name for m in lib.values())
        raise KeyError(f"unknown material '{name}'; known: {known} (or define it under [materials])")
    return lib[key]


def check_piezo(m: Piezo):
    """Raise unless c and eps^S are symmetric positive definite (a stable material)."""
    for what, a, shape in (("c", m.c, (6, 6)), ("eps", m.eps, (3, 3))):
        if a.shape != shape:
            raise ValueError(f"material '{m.name}': {what} has shape {a.shape}")
        if np.linalg.eigvalsh(_sym(a)).min() <= 0:
            raise ValueError(f"material '{m.name}': {what} is not positive definite; check the table's Voigt order")
    if m.e.shape != (3, 6):
        raise ValueError(f"material '{m.name}': e has shape {m.e.shape}, expected (3, 6)")
