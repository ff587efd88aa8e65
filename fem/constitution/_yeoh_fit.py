"""Incompressible Yeoh fit to a uniaxial tensile test, and its stability range.

The law and its homogeneous modes are in fem.constitution (the same law the solver
uses). Uniaxial nominal stress P = 2 (lam - lam^-2) W'(lam^2 + 2/lam); with lam = 1 + engineering strain, P is linear in (C10, C20, C30), so the fit is a
linear least-squares problem on the engineering (nominal) stress. This is how the
published Ecoflex 00-30 sets in docs/materials.md were obtained: engineering strain and
engineering stress of the Marechal et al. test, points with 0 < strain <= fit_strain
(tests/test_yeoh_fit.py reproduces them to their last printed digit).

Units: strain is a fraction (0.5 = 50 %), stresses and coefficients in Pa.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ._yeoh import MODES, instability_reason, is_stable, nominal_stress

COMPRESSION_STRETCH = 0.5     # default lower end of the stability check (50 % compression)


def uniaxial_stress(strain, C10, C20, C30):
    """Uniaxial nominal stress at engineering strain: P = 2 (lam - lam^-2) W'(I1), lam = 1 + strain."""
    return nominal_stress("uniaxial", 1.0 + np.asarray(strain, float), C10, C20, C30)


def yeoh_basis(strain) -> np.ndarray:
    """Columns dP/dC10, dP/dC20, dP/dC30 of the uniaxial nominal stress (P is linear in C).

    With lam = 1 + strain, I1 = lam^2 + 2/lam, g = 2 (lam - lam^-2):
    P = g C10 + 2 g (I1 - 3) C20 + 3 g (I1 - 3)^2 C30.
    """
    lam = 1.0 + np.asarray(strain, float)
    x = lam**2 + 2.0 / lam - 3.0
    g = 2.0 * (lam - lam**-2)
    return np.column_stack([g, 2.0 * g * x, 3.0 * g * x * x])


# --------------------------------------------------------------------------------------
# the fit
# --------------------------------------------------------------------------------------

@dataclass(frozen=True)
class YeohFit:
    """Least-squares Yeoh coefficients (Pa) and the quality of the fit on its points.

    r2 = 1 - SS_res / SS_tot, rms_Pa = sqrt(SS_res / n_points), both over the points
    used (0 < strain <= fit_strain).
    """

    C10: float
    C20: float
    C30: float
    r2: float
    fit_strain: float
    n_points: int
    rms_Pa: float

    @property
    def C(self) -> tuple[float, float, float]:
        return self.C10, self.C20, self.C30

    def stress(self, strain):
        """Fitted uniaxial nominal stress at engineering strain, Pa."""
        return uniaxial_stress(strain, *self.C)

    def record(self) -> dict:
        return asdict(self)


def fit_yeoh(strain, stress, fit_strain: float) -> YeohFit:
    """Fit C10, C20, C30 to uniaxial (engineering strain, nominal stress Pa) data.

    Minimises sum (P(strain_i; C) - stress_i)^2 over the points with
    0 < strain_i <= fit_strain, with numpy.linalg.lstsq on the basis of yeoh_basis
    (P is linear in C, so this is the exact least-squares optimum).
    """
    fit_strain = float(fit_strain)
    if not math.isfinite(fit_strain) or fit_strain <= 0:
        raise ValueError(f"the fit strain must be a positive fraction (0.5 = 50 %), got {fit_strain:g}")
    strain = np.asarray(strain, float)
    stress = np.asarray(stress, float)
    _check_tension(strain, stress, fit_strain)
    ok = np.isfinite(strain) & np.isfinite(stress) & (strain > 0) & (strain <= fit_strain)
    n = int(ok.sum())
    if n < 4:
        raise ValueError(f"only {n} data points with 0 < strain <= {fit_strain:g} "
                         f"(at least 4 are needed for 3 coefficients): raise the max strain")
    e, P = strain[ok], stress[ok]
    if len(np.unique(e)) < 4:
        raise ValueError(f"only {len(np.unique(e))} distinct strain values with 0 < strain <= {fit_strain:g}; "
                         "three coefficients need a test that spans strains (at least 4 distinct values)")
    A = yeoh_basis(e)
    # column scaling keeps lstsq well conditioned at large strain ((I1-3)^2 grows fast)
    scale = np.linalg.norm(A, axis=0)
    scale[scale == 0] = 1.0
    c, *_ = np.linalg.lstsq(A / scale, P, rcond=None)
    c = c / scale
    res = P - A @ c
    ss_res = float(res @ res)
    ss_tot = float(((P - P.mean()) ** 2).sum())
    r2 = 1.0 - ss_res / ss_tot if ss_tot > 0 else (1.0 if ss_res == 0 else -math.inf)
    return YeohFit(float(c[0]), float(c[1]), float(c[2]), r2, fit_strain, n, math.sqrt(ss_res / n))


# --------------------------------------------------------------------------------------
# stability
# --------------------------------------------------------------------------------------

def _check_tension(strain: np.ndarray, stress: np.ndarray, fit_strain: float) -> None:
    """Refuse data that is not one uniaxial tension test: a stretch 1 + strain <= 0,
    compression (strain < 0) mixed with tension (strain > 0), no tension at all, or a
    compressive stress at every tensile strain (a sign convention flipped). One line each."""
    finite = np.isfinite(strain) & np.isfinite(stress)
    e, P = strain[finite], stress[finite]
    if np.any(e <= -1):
        raise ValueError(f"strain {e[e <= -1][0]:g} is a stretch 1 + strain <= 0, which no material reaches; "
                         "give engineering strain as a fraction (0.5 = 50 %), positive in tension")
    neg, pos = int(np.sum(e < 0)), int(np.sum(e > 0))
    if neg and pos:
        raise ValueError(f"the data mixes {neg} compressive (negative) and {pos} tensile (positive) strains; "
                         "fit-yeoh fits one uniaxial tension test: keep the tension rows (strain > 0) only")
    if neg and not pos:
        raise ValueError("every strain is negative (compression); fit-yeoh fits uniaxial tension: give the "
                         "tension test, strain positive")
    inside = (e > 0) & (e <= fit_strain)
    if np.any(inside) and np.all(P[inside] < 0):
        raise ValueError("every stress at a positive strain is negative; in tension both are positive: check "
                         "the sign convention of the stress column")


def _first_loss(mode, C, lam_from, lam_to, n=4000):
    """First stretch from lam_from towards lam_to where is_stable fails, or None.

    A uniform scan of n steps, then bisection of the first unstable step to 1e-12.
    """
    lams = np.linspace(lam_from, lam_to, n + 1)
    stable = is_stable(mode, lams, *C)
    if stable.all():
        return None
    k = int(np.argmin(stable))
    if k == 0:
        return float(lam_from)
    a, b = lams[k - 1], lams[k]              # stable at a, unstable at b
    for _ in range(100):
        m = 0.5 * (a + b)
        if bool(is_stable(mode, m, *C)):
            a = m
        else:
            b = m
        if abs(b - a) < 1e-12:
            break
    return float(b)


def stability_limit(fit, lam_range=(0.5, 3.0)) -> dict[str, dict[str, float | None]]:
    """First stretch where the fitted law loses stability, per mode and direction.

    fit: a YeohFit or (C10, C20, C30) in Pa. lam_range = (lam_min, lam_max) with
    lam_min <= 1 <= lam_max. Returns {mode: {"tension": lam or None,
    "compression": lam or None}} for the modes uniaxial, equibiaxial and pure shear:
    the stability (is_stable) is followed from lam = 1 up to lam_max ("tension") and
    down to lam_min ("compression"); None when it holds over the whole interval.
    """
    C = fit.C if isinstance(fit, YeohFit) else tuple(float(c) for c in fit)
    lo, hi = (float(v) for v in lam_range)
    if not (0 < lo <= 1.0 <= hi):
        raise ValueError(f"stretch range must satisfy 0 < lam_min <= 1 <= lam_max, got ({lo:g}, {hi:g})")
    out = {}
    for mode in MODES:
        out[mode] = {"tension": _first_loss(mode, C, 1.0, hi) if hi > 1 else None,
                     "compression": _first_loss(mode, C, 1.0, lo) if lo < 1 else None}
    return out


def stability_losses(fit, lam_range=(COMPRESSION_STRETCH, 3.0)) -> list[dict]:
    """stability_limit as records, nearest to lam = 1 first.

    Each: {"mode", "direction" ("tension"/"compression"), "stretch", "strain" (= stretch - 1),
    "reason" (the condition that fails just past the limit, see instability_reason)}.
    """
    C = fit.C if isinstance(fit, YeohFit) else tuple(float(c) for c in fit)
    out = []
    for mode, per in stability_limit(C, lam_range).items():
        for direction, lam in per.items():
            if lam is not None:
                probe = lam + (1e-9 if direction == "tension" else -1e-9)
                out.append({"mode": mode, "direction": direction, "stretch": lam, "strain": lam - 1.0,
                            "reason": instability_reason(mode, probe, *C)})
    out.sort(key=lambda r: abs(r["strain"]))
    return out
