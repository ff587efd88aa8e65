"""Units: the one pint registry, reading quantities typed by a person, and printing them.

Inside the code every number is SI. At a boundary where a person types a number
(a TOML scene, a study, a rig file) it is a string with its unit ("0.5 mm",
"10 kPa"); `to_si` reads it. Called from Python, a plain number is taken as SI
(`si_numbers=True`); in a file it is refused, because "1" next to a thickness is
more often a millimetre than a metre.
"""

from __future__ import annotations

import math
from functools import cache
from typing import TYPE_CHECKING

if TYPE_CHECKING:                   # pint is imported on first use (registry), not at import
    import pint

# the unit a message suggests for each SI base unit
HINT = {"m": "mm", "N": "N", "Pa": "kPa", "V": "V", "Hz": "Hz", "s": "ms", "ohm": "MOhm", "F": "pF",
        "V/N": "V/N", "A": "A"}


class UnitError(ValueError):
    """A value that is not the quantity asked for; the message says what to write."""


@cache
def registry() -> pint.UnitRegistry:
    """The one registry. Its parsed unit definitions are cached by pint in the user's
    cache folder (0.03 s instead of 0.18 s to build, benchmarks/cli_startup.py); where
    that folder cannot be used the registry is built without it."""
    import sys
    if "dask" not in sys.modules and "pint" not in sys.modules:
        # pint looks for dask at import (for dask arrays, which no quantity here holds): 0.07 s of a
        # 2D solve's start. Hidden for that import only; `import dask` works as before afterwards.
        sys.modules["dask"] = None
        try:
            import pint
        finally:
            del sys.modules["dask"]
    import pint                     # imported on first use: 0.2 s, not needed by `taxel --help`
    try:
        return pint.UnitRegistry(cache_folder=":auto:")
    except Exception:               # no writable cache folder (read-only home): build it afresh
        return pint.UnitRegistry()


# the longest quantity text read: pint's tokenizer takes time growing with the square of a
# number's length (16k digits: 7-11 s), so a longer text is refused before it is parsed
MAX_TEXT = 100


def quantity(text: str) -> pint.Quantity:
    """A pint quantity from a string ("Ohm" and "ohm" both read as ohms; "34 degC", an
    offset unit pint cannot multiply, as the number in that unit); UnitError for a text
    longer than MAX_TEXT characters (no quantity needs it), before it is parsed."""
    text = str(text)
    if len(text) > MAX_TEXT:
        raise UnitError(f"a quantity of {len(text)} characters ({text[:20]!r}...): at most {MAX_TEXT}; "
                        "write e.g. \"1 mm\"")
    text = text.replace("Ohm", "ohm")
    try:
        return registry().Quantity(text)
    except Exception as exc:
        number, _, unit = text.strip().partition(" ")
        try:
            return registry().Quantity(float(number), unit.strip())
        except Exception:
            raise exc from None


def to_si(value, unit: str, what: str, *, si_numbers: bool = False, positive: bool = False,
          nonnegative: bool = False) -> float:
    """The SI magnitude of `value` in `unit`, checked; raises UnitError (one line).

    value: a string with a unit ("0.5 mm"), or, with `si_numbers`, a number in SI.
    Zero needs no unit.
    """
    hint = HINT.get(unit, unit)
    if isinstance(value, bool):
        raise UnitError(f"expected a {what} such as \"1 {hint}\", got {value!r}")
    if isinstance(value, (int, float)):
        if value != 0 and not si_numbers:
            raise UnitError(f"missing unit: write it as a string, e.g. \"{value} {hint}\"")
        return _check(float(value), value, positive, nonnegative)
    if not isinstance(value, str):
        raise UnitError(f"expected a {what} such as \"1 {hint}\"")
    try:
        q = quantity(value)
    except UnitError:
        raise
    except Exception:
        raise UnitError(f"cannot read {value!r} as a {what}; write e.g. \"1 {hint}\"") from None
    if isinstance(q, (int, float)) or q.dimensionless:
        raise UnitError(f"missing unit in {value!r}; write e.g. \"{value} {hint}\"")
    import pint
    try:
        x = float(q.to(unit).magnitude)
    except pint.DimensionalityError:
        raise UnitError(f"unit mismatch: {value!r} is not a {what}") from None
    return _check(x, value, positive, nonnegative)


def _check(x: float, value, positive: bool, nonnegative: bool) -> float:
    if not math.isfinite(x):
        raise UnitError(f"must be a finite number, got {value!r}")
    if positive and not x > 0:
        raise UnitError(f"must be positive, got {value!r}")
    if nonnegative and x < 0:
        raise UnitError(f"must not be negative, got {value!r}")
    return x


def in_unit(value, unit: str | None = None) -> tuple[float, str]:
    """(magnitude, unit) of a value in `unit`, or in its own unit when `unit` is
    None ("" for a plain number). Raises UnitError (one line) for text that is not
    a quantity, a unit that does not convert, a number where a unit is expected,
    or a value that is not finite."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if unit not in (None, ""):
            raise UnitError(f"{value!r} has no unit but {unit} is expected; write e.g. \"{value} {unit}\"")
        x, unit = float(value), ""
    else:
        try:
            q = quantity(value)
        except UnitError:
            raise
        except Exception:
            raise UnitError(f"cannot read {value!r} as a quantity") from None
        if unit is None:
            unit = f"{q.units:~}" if hasattr(q, "units") else ""
        try:
            x = float(q.to(unit).magnitude) if unit else float(q)
        except Exception:
            raise UnitError(f"unit mismatch: {value!r} is not in {unit or 'plain numbers'}") from None
    if not math.isfinite(x):
        raise UnitError(f"{value!r} is not a finite number")
    return x, unit


def magnitude(value):
    """The SI number in a value such as "0.5 mm", a number as is, anything else unchanged."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    try:
        return float(quantity(value).to_base_units().magnitude)
    except Exception:
        return value


def engineering(value: float | None, unit: str, digits: int = 4) -> str:
    """A number with an SI prefix: engineering(2.97e-9, 'C') -> '2.97 nC'."""
    if value is None:
        return "-"
    if value == 0 or not math.isfinite(value):
        return f"{value:g} {unit}"
    value = float(f"{value:.{digits}g}")
    exp = max(-15, min(9, 3 * math.floor(math.log10(abs(value)) / 3)))
    prefix = {-15: "f", -12: "p", -9: "n", -6: "u", -3: "m", 0: "", 3: "k", 6: "M", 9: "G"}[exp]
    return f"{value / 10 ** exp:.{digits}g} {prefix}{unit}"
