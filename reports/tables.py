"""Tables for the report pages: every number in an engineering unit (mV, pC, pF,
kPa, %), rows sorted by the parameters, the full-precision CSV beside the page.

A table is a plain dict the page template draws: {"cols": [...], "rows": [[cell,
...], ...], "more": n, "csv": href or None}. The column's unit comes from its
name (the CSV's SI column names: voltage_*, charge_*, max_strain, ...).
"""

from __future__ import annotations

import re

from taxel.units import engineering, magnitude

# column name pattern -> (shown name, how to print an SI number)
_COLUMNS = [
    (r"^(pressed_voltage|voltage_pressed)$", "pressed |V|", lambda v: engineering(v, "V")),
    (r"^voltage_(.+)$", "V {0}", lambda v: engineering(v, "V")),
    (r"^charge_(.+)$", "Q {0}", lambda v: engineering(v, "C")),
    (r"^capacitance.*", "capacitance", lambda v: engineering(v, "F")),
    (r"^max_strain$", "largest silicone strain", lambda v: percent(v)),
    (r"^crosstalk_bound$", "crosstalk bound", lambda v: percent(v)),
    (r"^crosstalk$", "crosstalk", lambda v: percent(v)),
    (r"^sensitivity(_V_per_N)?$", "sensitivity", lambda v: engineering(v, "V/N")),
    (r"^seconds$", "solve time", lambda v: f"{v:.2f} s"),
]


def percent(ratio: float) -> str:
    """A ratio in %, 3 significant digits, never with an exponent."""
    p = 100 * ratio
    return f"{p:.3g} %" if abs(p) >= 0.01 or p == 0 else f"< 0.01 %"


def column(name: str):
    """(shown name, formatter) of a column; plain 4-digit numbers when no unit is known."""
    for pattern, shown, fmt in _COLUMNS:
        m = re.match(pattern, name)
        if m:
            return shown.format(*m.groups()).replace("taxel_", "taxel "), fmt
    return name.replace("_", " "), None


def cell(value, fmt=None) -> str:
    """One cell: None blank, numbers (also numeric strings from a CSV) through the
    column's unit, otherwise 4 significant digits without an exponent when it fits."""
    if value is None or value == "":
        return ""
    if isinstance(value, bool):
        return str(value)
    try:
        x = float(value)
    except (TypeError, ValueError):
        return str(value)
    if fmt is not None:
        return fmt(x)
    if x.is_integer() and abs(x) < 1e15:   # counts: unknowns, evaluations
        return str(int(x))
    return f"{x:.4g}"                       # no unit known (a ratio, a residual): as is


def table(rows: list[dict], cols: list[str] | None = None, sort_by: list[str] = (), limit: int = 60,
          csv: str | None = None, order: dict[str, list] | None = None) -> dict:
    """A table for the page template: named columns in units, sorted by `sort_by`
    (numerically by each value's magnitude, so "0.5 mm" < "2 mm"; names such as
    materials in the order `order` gives them, else as first met), at most `limit` rows."""
    cols = cols or (list(rows[0]) if rows else [])
    if sort_by:
        first = {k: {v: i for i, v in reversed(list(enumerate(list((order or {}).get(k) or [])
                                                            + [r.get(k) for r in rows])))} for k in sort_by}
        rows = sorted(rows, key=lambda r: tuple(_sort_key(r.get(k), first[k]) for k in sort_by))
    shown = [column(c) for c in cols]
    body = [[cell(r.get(c), fmt) for c, (_, fmt) in zip(cols, shown)] for r in rows[:limit]]
    return {"cols": [name for name, _ in shown], "rows": body, "more": max(0, len(rows) - limit), "csv": csv}


def _sort_key(v, first):
    m = magnitude(v) if isinstance(v, str) else v
    if isinstance(m, (int, float)):
        return (0, float(m))
    return (1, float(first.get(v, 0)))
