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

from dataclasses import dataclass, replace
from functools import cache
from pathlib import Path

import numpy as np

from ._tensors import (MODEL_TENSORS, poling_rotation, rotate, strain_to_stress_charge, stress_to_strain_charge,
                       symmetric)

EPS0 = 8.8541878128e-12  # F/m, CODATA 2018

# Marechal et al. (2021) uniaxial test of Ecoflex 00-30, the data behind the Yeoh sets (fem/data/SOURCES.md)
ECOFLEX_UNIAXIAL_CSV = Path(__file__).parent.parent / "data" / "ecoflex-00-30-uniaxial.csv"

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
    # heat (fem.thermal): W/(m K), J/(kg K); the pyroelectric coefficient p3 along the poling
    # axis (local 3) at constant stress, C/(m^2 K); where each comes from
    conductivity: float | None = None
    specific_heat: float | None = None
    pyro: float = 0.0
    thermal_source: str = ""
    # temperature coefficients, 1/K, linear about room temperature: of eps33^T and of the
    # d constants (d31, d33 together); None where no datasheet gives one (the warm touch
    # then says "no drift data", never zero); where each comes from
    permittivity_tc: float | None = None
    d_tc: float | None = None
    drift_source: str = ""

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
    conductivity: float | None = None      # W/(m K) (fem.thermal)
    specific_heat: float | None = None     # J/(kg K)
    thermal_source: str = ""

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


def model_tensors(material, model: str):
    """(c, e, eps) of `material` for `model`; a Solid has e = 0 and eps = eps_r eps0."""
    if isinstance(material, Piezo):
        return MODEL_TENSORS[model](material.c, material.e, material.eps)
    c = material.stiffness()
    return MODEL_TENSORS[model](c, np.zeros((3, 6)), material.eps_r * EPS0 * np.eye(3))


# --------------------------------------------------------------------------------------
# the library
# --------------------------------------------------------------------------------------

# Heat (docs/materials.md, "Heat and pyroelectricity"). PZT: CTS "Materials Technical Data (Typical
# Values)", the PZT-5H column (3203HD: K3 3800, d33 650, d31 -320, the PSI-5H4E numbers): specific heat
# 420 J/(kg K), thermal conductivity 1.2 W/(m K). Neither that sheet nor PSI-5H4E's gives a pyroelectric
# coefficient: Piezo Systems' technical note's "for PZT piezoceramic ~ 400e-6 C/(m^2 K)", negative (the
# polarization falls on heating). The same values for the generic PZT-5H. Silicone: no sourced value for
# Ecoflex 00-30; a measured thin silicone rubber sheet, 0.237 W/(m K) (Thermtest, guarded heat-flow
# meter, ASTM E1530, 26 C), and 1250 J/(kg K), the middle of silicone rubbers' 1.0-1.5 kJ/(kg K) (assumed).
# Temperature drift (docs/materials.md, "Temperature drift"): no sheet gives PSI-5H4E's or PZT-5H's;
# PI Ceramic's "Piezo Material Data" gives TK eps33 = 5e-3/K (-20 to +125 C) for PIC153, its PZT-5H-class
# soft ceramic (eps33 4200, d33 600 pC/N, Tc 185 C): taken for both. No d31/d33 coefficient found.
PZT_THERMAL = dict(conductivity=1.2, specific_heat=420.0, pyro=-400e-6,
                   thermal_source="k, c: CTS Materials Technical Data, PZT-5H (3203HD); p3: Piezo Systems "
                                  "technical note, typical PZT (-400e-6)",
                   permittivity_tc=5e-3,
                   drift_source="eps33: PI Ceramic Piezo Material Data, PIC153 (PZT-5H class), TK eps33 5e-3/K, "
                                "-20 to +125 C; d: no sourced coefficient")
SILICONE_THERMAL = dict(conductivity=0.237, specific_heat=1250.0,
                        thermal_source="k: Thermtest, thin silicone rubber sheet (not Ecoflex); c: assumed 1250")


def _pzt5h() -> Piezo:
    """Generic PZT-5H, strain-charge set of Erturk and Inman, Piezoelectric Energy
    Harvesting (2011), App. E, Table E.1 (docs/materials.md)."""
    p = 1e-12
    s = _transversely_isotropic_compliance(16.5 * p, -4.78 * p, -8.45 * p, 20.7 * p, 43.5 * p, 42.6 * p)
    d = _pz_d(d31=-274e-12, d33=593e-12, d15=741e-12)
    eps_T = np.diag([3130, 3130, 3400]) * EPS0
    return Piezo.from_strain_charge("PZT-5H", s, d, eps_T, rho=7500.0,
                                    source="Erturk & Inman 2011, App. E, Table E.1",
                                    Qm=65.0, tan_delta=0.02, **PZT_THERMAL)


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
                                    Qm=32.0, tan_delta=0.02, **PZT_THERMAL)


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
                                    Qm=10.0, tan_delta=0.02, conductivity=0.19, specific_heat=1200.0, pyro=-30e-6,
                                    thermal_source="p3: TE Piezo Film Sensors Technical Manual, Table 1 (30e-6, sign: "
                                                   "polarization falls on heating); k, c: PVDF resin, typical (assumed)",
                                    drift_source="none: the TE manual shows d33, g31 and the permittivity against "
                                                 "temperature as curves (Figures 24, 25b) and gives no coefficient")


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
    return Solid(name, mu=2 * C[0], K=1000 * 2 * C[0], rho=1070.0, eps_r=2.8, **SILICONE_THERMAL,
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
        if np.linalg.eigvalsh(symmetric(a)).min() <= 0:
            raise ValueError(f"material '{m.name}': {what} is not positive definite; check the table's Voigt order")
    if m.e.shape != (3, 6):
        raise ValueError(f"material '{m.name}': e has shape {m.e.shape}, expected (3, 6)")
