"""User materials from a table of SI numbers (a scene's [materials.NAME]), checked.

    piezo, strain-charge:  {kind="piezo", s=6x6 (1/Pa), d=3x6 (C/N), eps_T=3x3 (relative), rho}
    piezo, stress-charge:  {kind="piezo", c=6x6 (Pa), e=3x6 (C/m^2), eps_S=3x3 (relative), rho}
    solid:                 {kind="solid", E, nu, rho[, eps_r]} or {kind="solid", mu, K, rho}
                           optional Yeoh: C10, C20, C30 (Pa); with only C10.. given, mu = 2 C10
    optional: Qm and tan_delta (piezo losses), eps_r (solid, relative permittivity)
    heat (fem.thermal; a warm touch needs them): conductivity (W/(m K)) and specific_heat
    (J/(kg K)), both positive; a piezo's pyro, its pyroelectric coefficient p3 (C/(m^2 K));
    a piezo's temperature drift (1/K, linear about room temperature): permittivity_tc of
    eps33^T, d_tc of its d constants (left out: "no drift data")

Physically impossible materials are refused (ValueError, one line naming the key):
a stiffness or permittivity that is not positive definite, E, mu, K, rho, eps_r
not positive, a Poisson ratio outside (-1, 0.5) for a compressible solid, and a
Yeoh law that is not stable (fem.constitution.is_stable) for stretches 0.7 to 1.5 in
uniaxial, equibiaxial and pure shear (C10 <= 0 fails at once).
"""

from __future__ import annotations

import math

import numpy as np

from . import _yeoh as yeoh
from ._materials import EPS0, Piezo, Solid, check_piezo

THERMAL_KEYS = {"conductivity", "specific_heat"}
KEYS = {"piezo": {"kind", "s", "d", "eps_T", "c", "e", "eps_S", "rho", "Qm", "tan_delta", "pyro",
                  "permittivity_tc", "d_tc", *THERMAL_KEYS},
        "solid": {"kind", "E", "nu", "mu", "K", "rho", "eps_r", "C10", "C20", "C30", *THERMAL_KEYS}}
SMALL_STRAIN_STRETCH = (0.7, 1.5)


def _number(rec, key, positive=False):
    v = rec[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ValueError(f"{key} = {v!r} is not a number (SI units, e.g. {key} = 1e5)")
    x = float(v)
    if not math.isfinite(x):
        raise ValueError(f"{key} = {v!r} is not finite")
    if positive and not x > 0:
        raise ValueError(f"{key} = {v!r} must be positive")
    return x


def _matrix(rec, key, shape):
    try:
        a = np.array(rec[key], dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{key} is not a {shape[0]} x {shape[1]} table of numbers") from None
    if a.shape != shape or not np.isfinite(a).all():
        raise ValueError(f"{key} has shape {a.shape}, expected a {shape[0]} x {shape[1]} table of finite numbers")
    return a


def from_record(name: str, rec: dict):
    """A checked user material from a table of SI numbers (see the module docstring)."""
    if not isinstance(rec, dict):
        raise ValueError(f"expected a table such as {{kind = \"solid\", E = 1e5, nu = 0.45, rho = 1070}}, got {rec!r}")
    kind = rec.get("kind")
    if kind not in KEYS:
        raise ValueError(f"kind must be 'piezo' or 'solid', got {kind!r}")
    unknown = sorted(set(rec) - KEYS[kind])
    if unknown:
        raise ValueError(f"unknown key '{unknown[0]}'; a {kind} takes {', '.join(sorted(KEYS[kind]))}")
    if "rho" not in rec:
        raise ValueError("rho (density, kg/m^3) is missing")
    rho = _number(rec, "rho", positive=True)
    extra = {k: _number(rec, k, positive=True) for k in ("Qm", *sorted(THERMAL_KEYS)) if k in rec}
    for k in ("pyro", "permittivity_tc", "d_tc"):
        if k in rec:
            extra[k] = _number(rec, k)
    if "permittivity_tc" in extra or "d_tc" in extra:
        extra["drift_source"] = "user"
    if "tan_delta" in rec:
        extra["tan_delta"] = _number(rec, "tan_delta")
        if not 0 <= extra["tan_delta"] < 1:
            raise ValueError(f"tan_delta = {rec['tan_delta']!r} must be in [0, 1)")
    return _piezo(name, rec, rho, extra) if kind == "piezo" else _solid(name, rec, rho, extra)


def _piezo(name, rec, rho, extra):
    if "s" in rec:
        missing = [k for k in ("s", "d", "eps_T") if k not in rec]
        if missing:
            raise ValueError(f"{missing[0]} is missing (strain-charge form: s, d, eps_T)")
        m = Piezo.from_strain_charge(name, _matrix(rec, "s", (6, 6)), _matrix(rec, "d", (3, 6)),
                                     _matrix(rec, "eps_T", (3, 3)) * EPS0, rho, source="user", **extra)
    else:
        missing = [k for k in ("c", "e", "eps_S") if k not in rec]
        if missing:
            raise ValueError(f"{missing[0]} is missing (stress-charge form: c, e, eps_S; or s, d, eps_T)")
        m = Piezo(name, _matrix(rec, "c", (6, 6)), _matrix(rec, "e", (3, 6)), _matrix(rec, "eps_S", (3, 3)) * EPS0,
                  rho, source="user", **extra)
    check_piezo(m)
    return m


def _solid(name, rec, rho, extra):
    eps_r = _number(rec, "eps_r", positive=True) if "eps_r" in rec else 1.0
    C = None
    if "C10" in rec:
        C = tuple(_number(rec, k) if k in rec else 0.0 for k in ("C10", "C20", "C30"))
        if not C[0] > 0:
            raise ValueError(f"C10 = {rec['C10']!r} must be positive (the initial shear modulus is 2 C10)")
        lam = np.linspace(*SMALL_STRAIN_STRETCH, 401)
        for mode in yeoh.MODES:
            bad = ~yeoh.is_stable(mode, lam, *C)
            if bad.any():
                raise ValueError(f"the Yeoh law (C10, C20, C30) = {C} Pa is unstable in {mode} at stretch "
                                 f"{lam[bad][np.argmin(abs(lam[bad] - 1))]:.3g}; refit it (taxel material fit-yeoh)")
    if "E" in rec:
        if "nu" not in rec:
            raise ValueError("nu (Poisson's ratio) is missing next to E")
        E, nu = _number(rec, "E", positive=True), _number(rec, "nu")
        if not -1 < nu < 0.5:
            raise ValueError(f"nu = {rec['nu']!r} must be in (-1, 0.5) for a compressible solid; for a nearly "
                             "incompressible one give mu and K (or C10 and K)")
        return Solid.from_E_nu(name, E, nu, rho, eps_r=eps_r, source="user", yeoh=C, **extra)
    if "K" not in rec:
        raise ValueError("K (bulk modulus, Pa) is missing; give E and nu, or mu (or C10) and K")
    K = _number(rec, "K", positive=True)
    if "mu" in rec:
        mu = _number(rec, "mu", positive=True)
    elif C is not None:
        mu = 2 * C[0]
    else:
        raise ValueError("mu (shear modulus, Pa) is missing; give mu and K, C10 and K, or E and nu")
    return Solid(name, mu, K, rho, eps_r=eps_r, source="user", yeoh=C, **extra)
