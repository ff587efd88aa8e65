"""Tables for the report pages: every number in an engineering unit (mV, pC, pF,
kPa, %), rows sorted by the parameters, the full-precision CSV beside the page.

A table is a plain dict the page template draws: {"cols": [...], "rows": [[cell,
...], ...], "marks": [row class or "", ...], "csv": href or None, "raw": the
unformatted rows}. Every row is shown (the page scrolls a long table); every table
gets a CSV beside the page (`write_csvs`: its own full-precision file when it has
one, else its rows as given). The column's unit comes from its name (the CSV's SI
column names: voltage_*, short_circuit_charge_*, max_strain, ..., or a unit in parentheses:
"gap (mm)"). Conventions: crosstalk in %, lengths to 0.01 mm, 3 significant figures.
"""

from __future__ import annotations

import re

from taxel.units import engineering, magnitude

# column name pattern -> (shown name, how to print an SI number)
_COLUMNS = [
    (r"^pressed_voltage$", "V pressed taxel (signed)", lambda v: eng(v, "V")),
    (r"^voltage_(.+)$", "V {0}", lambda v: eng(v, "V")),
    (r"^short_circuit_charge_(.+)$", "Q {0}", lambda v: eng(v, "C")),
    (r"^capacitance.*", "capacitance", lambda v: eng(v, "F")),
    (r"^max_strain$", "largest silicone strain", lambda v: percent(v)),
    (r"^crosstalk_bound$", "crosstalk bound", lambda v: percent(v)),
    (r"^(.*) moved$", "{0} moved (%)", lambda v: f"{100 * v:+.3g}"),      # a relative change
    (r"^(.*crosstalk.*)$", "{0}", lambda v: percent(v)),
    (r"^(.*)\(mm\)$", "{0}(mm)", lambda v: f"{v:.2f}"),
    (r"^(.*)\(V/N\)$", "{0}", lambda v: eng(v, "V/N")),
    (r"^sensitivity(_V_per_N)?$", "sensitivity", lambda v: eng(v, "V/N")),
    (r"^(predicted sensitivity)$", "{0}", lambda v: eng(v, "V/N")),
    (r"^seconds$", "solve time", lambda v: f"{v:.2f} s"),
]


def eng(value: float | None, unit: str, digits: int = 3) -> str:
    """A number with an SI prefix, 3 significant figures, micro as µ: eng(2.33e-4, "N") -> "233 µN"."""
    return re.sub(r"^(\S+) u", r"\1 µ", engineering(value, unit, digits))


def percent(ratio: float) -> str:
    """A ratio in %, 3 significant digits, never with an exponent (0.00289 %)."""
    import numpy as np
    p = 100 * ratio
    text = f"{p:.3g}"
    if "e" in text:
        text = np.format_float_positional(p, precision=3, unique=False, fractional=False, trim="-")
    return f"{text} %"


def column(name: str):
    """(shown name, formatter) of a column; plain 4-digit numbers when no unit is known."""
    for pattern, shown, fmt in _COLUMNS:
        m = re.match(pattern, name)
        if m:
            name = shown.format(*m.groups())
            return (name.replace("taxel_", "taxel ") if "taxel_" in name else name.replace("_", " ")).strip(), fmt
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
    return f"{x:.3g}"                       # no unit known (a ratio, a residual): 3 significant figures


def table(rows: list[dict], cols: list[str] | None = None, sort_by: list[str] = (), csv: str | None = None,
          order: dict[str, list] | None = None, mark=None, title: str = "") -> dict:
    """A table for the page template: named columns in units, sorted by `sort_by`
    (numerically by each value's magnitude, so "0.5 mm" < "2 mm"; names such as
    materials in the order `order` gives them, else as first met), every row.
    `mark(row)` gives a row's class ("reference", "dominated", "out-of-range" or "")."""
    cols = cols or (list(rows[0]) if rows else [])
    if sort_by:
        first = {k: {v: i for i, v in reversed(list(enumerate(list((order or {}).get(k) or [])
                                                            + [r.get(k) for r in rows])))} for k in sort_by}
        rows = sorted(rows, key=lambda r: tuple(_sort_key(r.get(k), first[k]) for k in sort_by))
    shown = [column(c) for c in cols]
    body = [[cell(r.get(c), fmt) for c, (_, fmt) in zip(cols, shown)] for r in rows]
    return {"cols": [name for name, _ in shown], "rows": body, "csv": csv, "title": title,
            "marks": [mark(r) if mark else "" for r in rows], "raw": [[r.get(c) for c in cols] for r in rows],
            "raw_cols": list(cols)}


def write_csvs(sections: list[dict], out, stem: str) -> None:
    """Give every table of the page's sections a CSV beside the page: the rows as
    given to `table` (SI numbers where the caller had them), for a table without its
    own full-precision file."""
    import csv as _csv
    n = 0
    for sec in sections:
        for b in sec["blocks"]:
            t = b.get("table") if b.get("type") == "table" else None
            if t is None or t.get("csv") or not t.get("rows"):
                continue
            n += 1
            slug = re.sub(r"[^a-z0-9]+", "-", (t.get("title") or sec["title"]).lower()).strip("-")
            name = f"{stem}-{slug}-{n}.csv"
            with open(out / name, "w", newline="", encoding="utf-8") as fh:
                w = _csv.writer(fh)
                w.writerow(t["raw_cols"])
                w.writerows(t["raw"])
            t["csv"] = name


def _sort_key(v, first):
    m = magnitude(v) if isinstance(v, str) else v
    if isinstance(m, (int, float)):
        return (0, float(m))
    return (1, float(first.get(v, 0)))
