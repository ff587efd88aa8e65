"""Incompressible Yeoh fit to a uniaxial tensile test, and its stability range.

Yeoh strain energy (incompressible), I1 = tr(C) the first invariant:

    W(I1) = C10 (I1 - 3) + C20 (I1 - 3)^2 + C30 (I1 - 3)^3
    W'(I1) = dW/dI1 = C10 + 2 C20 (I1 - 3) + 3 C30 (I1 - 3)^2
    W''(I1) = 2 C20 + 6 C30 (I1 - 3)

Homogeneous deformations, stretch lam along the loading direction, nominal (first
Piola-Kirchhoff, force per undeformed area) stress P:

    uniaxial:     I1 = lam^2 + 2/lam,        P = 2 (lam - lam^-2) W'(I1)
    equibiaxial:  I1 = 2 lam^2 + lam^-4,     P = 2 (lam - lam^-5) W'(I1)
    pure shear:   I1 = lam^2 + 1 + lam^-2,   P = 2 (lam - lam^-3) W'(I1)

With lam = 1 + engineering strain, P is linear in (C10, C20, C30), so the fit is a
linear least-squares problem on the engineering (nominal) stress. This is how the
published Ecoflex 00-30 sets in REFERENCE.md were obtained: engineering strain and
engineering stress of the Marechal et al. test, points with 0 < strain <= max_strain
(tests/test_yeoh_fit.py reproduces them to their last printed digit).

Units: strain is a fraction (0.5 = 50 %), stresses and coefficients in Pa.
"""

from __future__ import annotations

import math
import re
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

MODES = ("uniaxial", "equibiaxial", "pure shear")
COMPRESSION_STRETCH = 0.5     # default lower end of the stability check (50 % compression)

# Stress units recognised in a column header, and their factor to Pa.
_STRESS_UNITS = [(r"gpa", 1e9), (r"mpa", 1e6), (r"n\s*/\s*mm\s*(\^?\s*2|²)", 1e6), (r"kpa", 1e3),
                 (r"psi", 6894.757293168361), (r"pa", 1.0)]


# --------------------------------------------------------------------------------------
# reading a test file
# --------------------------------------------------------------------------------------

def _split(line: str) -> list[str]:
    """Cells of one CSV line; the delimiter is ';', tab or ',' (in that order of preference)."""
    for delim in (";", "\t", ","):
        if delim in line:
            return [c.strip().strip('"').strip() for c in line.split(delim)]
    return [line.strip().strip('"').strip()]


def _number(cell: str) -> float:
    """A float from a cell; a decimal comma ('0,5') is accepted; anything else is NaN."""
    s = cell.strip()
    if "," in s and "." not in s:
        s = s.replace(",", ".")
    try:
        return float(s)
    except ValueError:
        return math.nan


def _pick(cells: list[str], quantity: str) -> int | None:
    """Index of the engineering (nominal) `quantity` column ('strain' or 'stress').

    Preference: a header naming it 'engineering', 'eng.' or 'nominal'; else the only
    header containing the word that is not a true / Cauchy / log (Hencky) measure.
    """
    low = [c.lower() for c in cells]
    named = [i for i, c in enumerate(low) if quantity in c]
    eng = [i for i in named if re.search(r"\b(engineering|eng|nominal|1st\s*piola|pk1)\b", low[i])]
    if eng:
        return eng[0]
    plain = [i for i in named if not re.search(r"\b(true|cauchy|log|logarithmic|hencky)\b", low[i])]
    return plain[0] if plain else None


def _stress_factor(header: str) -> float:
    """Factor to Pa from the unit in a stress header ('Engineering Stress (MPa)' -> 1e6).

    No recognisable unit means Pa (as in a 'strain,stress_Pa' or 'strain,stress' file).
    """
    h = header.lower()
    for pattern, factor in _STRESS_UNITS:
        if re.search(r"(?<![a-z])" + pattern + r"(?![a-z])", h):
            return factor
    return 1.0


def read_uniaxial(path) -> tuple[np.ndarray, np.ndarray]:
    """(engineering strain, nominal stress in Pa) from a uniaxial test file.

    The header row is the first row with a strain column and a stress column (names
    matched case-insensitively); metadata rows before it are skipped. When the file
    has both true and engineering columns (e.g. 'True Strain', 'Engineering Strain'),
    the engineering ones are used. A plain 'strain,stress_Pa' file works too (comma,
    semicolon or tab separated). The stress unit comes from the header (GPa, MPa,
    N/mm^2, kPa, psi, Pa; none given: Pa); a strain header with '%' is read as percent.
    Rows where either value is not a finite number are dropped.

    Raises ValueError (one line naming the file) when the file cannot be read, the
    columns are not found, or fewer than 4 points remain.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text CSV file (cannot decode it as UTF-8)") from None
    except OSError as exc:
        raise ValueError(f"cannot read uniaxial test file {path}: {exc.strerror or exc}") from None

    lines = text.splitlines()
    header = None
    for k, line in enumerate(lines):
        cells = _split(line)
        if not any("strain" in c.lower() for c in cells) or not any("stress" in c.lower() for c in cells):
            continue
        i, j = _pick(cells, "strain"), _pick(cells, "stress")
        if i is None or j is None:
            missing = "strain" if i is None else "stress"
            found = ", ".join(f"'{c}'" for c in cells if missing in c.lower())
            raise ValueError(f"{path}: no engineering (nominal) {missing} column, only {found}: "
                             f"a Yeoh fit needs engineering strain and nominal stress")
        header = (k, cells, i, j)
        break
    if header is None:
        strain_only = None      # a strain header directly above numeric rows, if any
        for k, line in enumerate(lines[:-1]):
            cells = [c for c in _split(line) if "strain" in c.lower()]
            if cells and sum(math.isfinite(_number(c)) for c in _split(lines[k + 1])) >= 2:
                strain_only = cells[0]
                break
        what = (f"no stress column next to '{strain_only}'" if strain_only
                else "no header row with a strain column and a stress column")
        raise ValueError(f"{path}: {what} (expected e.g. 'Engineering Strain;Engineering Stress (MPa)' "
                         f"or 'strain,stress_Pa')")

    k, cells, i, j = header
    factor = _stress_factor(cells[j])
    strain_scale = 0.01 if ("%" in cells[i] or "percent" in cells[i].lower()) else 1.0
    rows = []
    for line in lines[k + 1:]:
        if not line.strip():
            continue
        c = _split(line)
        rows.append((_number(c[i]) if i < len(c) else math.nan, _number(c[j]) if j < len(c) else math.nan))
    data = np.array(rows, float).reshape(-1, 2)
    data = data[np.isfinite(data).all(axis=1)]
    if len(data) < 4:
        raise ValueError(f"{path}: only {len(data)} numeric rows under '{cells[i]}' and '{cells[j]}' "
                         f"(at least 4 are needed)")
    return data[:, 0] * strain_scale, data[:, 1] * factor


# --------------------------------------------------------------------------------------
# the Yeoh law in homogeneous deformations
# --------------------------------------------------------------------------------------

def dW(I1, C10, C20, C30):
    """W'(I1) = C10 + 2 C20 (I1 - 3) + 3 C30 (I1 - 3)^2."""
    x = np.asarray(I1, float) - 3.0
    return C10 + 2.0 * C20 * x + 3.0 * C30 * x * x


def d2W(I1, C10, C20, C30):
    """W''(I1) = 2 C20 + 6 C30 (I1 - 3)."""
    return 2.0 * C20 + 6.0 * C30 * (np.asarray(I1, float) - 3.0)


def _kinematics(mode: str, lam):
    """(I1, dI1/dlam, g, dg/dlam) of a mode, with P = 2 g(lam) W'(I1(lam))."""
    lam = np.asarray(lam, float)
    if mode == "uniaxial":
        return lam**2 + 2 / lam, 2 * lam - 2 / lam**2, lam - lam**-2, 1 + 2 * lam**-3
    if mode == "equibiaxial":
        return 2 * lam**2 + lam**-4, 4 * lam - 4 * lam**-5, lam - lam**-5, 1 + 5 * lam**-6
    if mode == "pure shear":
        return lam**2 + 1 + lam**-2, 2 * lam - 2 * lam**-3, lam - lam**-3, 1 + 3 * lam**-4
    raise ValueError(f"unknown deformation mode '{mode}'; known: {', '.join(MODES)}")


def nominal_stress(mode: str, lam, C10, C20, C30):
    """Nominal stress P(lam) of an incompressible Yeoh solid, Pa.

    uniaxial P = 2 (lam - lam^-2) W'(lam^2 + 2/lam); equibiaxial P = 2 (lam - lam^-5)
    W'(2 lam^2 + lam^-4); pure shear P = 2 (lam - lam^-3) W'(lam^2 + 1 + lam^-2).
    """
    I1, _, g, _ = _kinematics(mode, lam)
    return 2.0 * g * dW(I1, C10, C20, C30)


def tangent(mode: str, lam, C10, C20, C30):
    """dP/dlam = 2 (g' W'(I1) + g W''(I1) dI1/dlam), with P = 2 g(lam) W'(I1(lam))."""
    I1, dI1, g, dg = _kinematics(mode, lam)
    return 2.0 * (dg * dW(I1, C10, C20, C30) + g * d2W(I1, C10, C20, C30) * dI1)


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
    used (0 < strain <= max_strain).
    """

    C10: float
    C20: float
    C30: float
    r2: float
    max_strain: float
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


def fit_yeoh(strain, stress, max_strain: float) -> YeohFit:
    """Fit C10, C20, C30 to uniaxial (engineering strain, nominal stress Pa) data.

    Minimises sum (P(strain_i; C) - stress_i)^2 over the points with
    0 < strain_i <= max_strain, with numpy.linalg.lstsq on the basis of yeoh_basis
    (P is linear in C, so this is the exact least-squares optimum).
    """
    max_strain = float(max_strain)
    if not math.isfinite(max_strain) or max_strain <= 0:
        raise ValueError(f"max strain must be a positive fraction (0.5 = 50 %), got {max_strain:g}")
    strain = np.asarray(strain, float)
    stress = np.asarray(stress, float)
    ok = np.isfinite(strain) & np.isfinite(stress) & (strain > 0) & (strain <= max_strain)
    n = int(ok.sum())
    if n < 4:
        raise ValueError(f"only {n} data points with 0 < strain <= {max_strain:g} "
                         f"(at least 4 are needed for 3 coefficients): raise the max strain")
    e, P = strain[ok], stress[ok]
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
    return YeohFit(float(c[0]), float(c[1]), float(c[2]), r2, max_strain, n, math.sqrt(ss_res / n))


# --------------------------------------------------------------------------------------
# stability
# --------------------------------------------------------------------------------------

def is_stable(mode: str, lam, C10, C20, C30):
    """Drucker-like stability of the Yeoh law at stretch lam in a mode.

    Stable where W'(I1) > 0 (positive slope of the energy in I1, i.e. positive
    initial-shear-like stiffness 2 W') and the nominal stress rises with stretch,
    dP/dlam > 0. (W'' may be negative where both hold: convexity of W in I1 is
    sufficient, not necessary, for these homogeneous modes.)
    """
    I1, *_ = _kinematics(mode, lam)
    return (dW(I1, C10, C20, C30) > 0) & (tangent(mode, lam, C10, C20, C30) > 0)


def instability_reason(mode: str, lam, C10, C20, C30) -> str:
    """Which condition fails at lam: 'W\\'(I1) <= 0', 'dP/dlam <= 0', or '' if stable."""
    I1, *_ = _kinematics(mode, lam)
    if dW(I1, C10, C20, C30) <= 0:
        return "W'(I1) <= 0"
    if tangent(mode, lam, C10, C20, C30) <= 0:
        return "dP/dlam <= 0"
    return ""


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


def parse_strain(option: str, text) -> float:
    """A strain given as a fraction ('0.5') or a percentage ('50%', '50 %'); must be finite and > 0.

    Raises ValueError with one line naming `option` otherwise.
    """
    t = str(text).strip()
    pct = t.endswith("%")
    try:
        value = float(t.rstrip("%").strip()) / (100.0 if pct else 1.0)
    except ValueError:
        raise ValueError(f"{option} must be a number such as 0.5 or '50%', got '{text}'") from None
    if not (value > 0 and math.isfinite(value)):
        raise ValueError(f"{option} must be a positive strain (0.5 = 50 %), got '{text}'")
    return value


# --------------------------------------------------------------------------------------
# plot
# --------------------------------------------------------------------------------------

def plot_fit(strain, stress, fit: YeohFit, out, check_strain: float | None = None, title: str = ""):
    """PNG of the data, the fit over its range (solid) and beyond it (dashed).

    The fit range 0 < strain <= max_strain is shaded; the plot extends to
    max(3 max_strain, check_strain); where the uniaxial fit loses stability within
    it, a marker shows the point.
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    strain, stress = np.asarray(strain, float), np.asarray(stress, float)
    x_hi = max(3.0 * fit.max_strain, check_strain or 0.0)
    show = (strain >= 0) & (strain <= x_hi)
    order = np.argsort(strain[show])
    xs, ys = strain[show][order], stress[show][order]

    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    ax.axvspan(0, 100 * fit.max_strain, color="0.9", label=f"fit range (<= {100 * fit.max_strain:g} %)")
    ax.plot(100 * xs, ys / 1e3, ".", ms=4, color="k", label="test data")
    x_in = np.linspace(0, fit.max_strain, 200)
    x_out = np.linspace(fit.max_strain, x_hi, 400)
    lbl = (f"Yeoh: C10 {fit.C10 / 1e3:.3g}, C20 {fit.C20 / 1e3:.3g}, C30 {fit.C30 / 1e3:.3g} kPa"
           f" (R² {fit.r2:.4f})")
    ax.plot(100 * x_in, fit.stress(x_in) / 1e3, "-", color="C0", lw=2, label=lbl)
    ax.plot(100 * x_out, fit.stress(x_out) / 1e3, "--", color="C0", lw=1.5, label="fit, extrapolated")
    lost = stability_limit(fit, (0.5, 1.0 + x_hi))["uniaxial"]["tension"]
    if lost is not None:
        ax.plot(100 * (lost - 1), fit.stress(lost - 1) / 1e3, "x", color="C3", ms=10, mew=2,
                label=f"uniaxial stability lost ({100 * (lost - 1):.0f} %)")
    y_data = ys.max() if len(ys) else float(fit.stress(x_hi))
    ax.set_ylim(min(0.0, ys.min() / 1e3 if len(ys) else 0.0) - 0.05 * y_data / 1e3, 1.3 * y_data / 1e3)
    ax.set_xlim(0, 100 * x_hi)
    ax.set_xlabel("engineering strain (%)")
    ax.set_ylabel("nominal stress (kPa)")
    if title:
        ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
