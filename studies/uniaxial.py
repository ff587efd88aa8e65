"""Reading a uniaxial tensile test (CSV) for `taxel material fit-yeoh`.

Delimiter ';', tab or ','; a decimal comma is accepted. The engineering (nominal)
strain and stress columns are found by their headers; the stress unit is read
from its header (MPa, kPa, N/mm^2, psi, Pa). Rows that are not two finite numbers
are counted and reported, never dropped silently.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

# Stress units recognised in a column header, and their factor to Pa.
_STRESS_UNITS = [(r"gpa", 1e9), (r"mpa", 1e6), (r"n\s*/\s*mm\s*(\^?\s*2|²)", 1e6), (r"kpa", 1e3),
                 (r"psi", 6894.757293168361), (r"pa", 1.0)]


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
    A data row that is not two finite numbers is an error naming its line (never
    dropped silently); blank lines are skipped.

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
    for n, line in enumerate(lines[k + 1:], start=k + 2):
        if not line.strip():
            continue
        c = _split(line)
        row = (_number(c[i]) if i < len(c) else math.nan, _number(c[j]) if j < len(c) else math.nan)
        if not all(math.isfinite(v) and abs(v) < 1e12 for v in row):
            raise ValueError(f"{path}: line {n} is not a strain and a stress ({line.strip()[:40]!r}); "
                             "fix or delete that row")
        rows.append(row)
    data = np.array(rows, float).reshape(-1, 2)
    if len(data) < 4:
        raise ValueError(f"{path}: only {len(data)} numeric rows under '{cells[i]}' and '{cells[j]}' "
                         f"(at least 4 are needed)")
    return data[:, 0] * strain_scale, data[:, 1] * factor


