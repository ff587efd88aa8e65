"""The base of the four TOML schemas (scene, study, optimization, rig): one strict
pydantic model, typed quantities and safe names.

`Strict`: unknown keys are refused, models are frozen, defaults are validated.
A key renamed in a release is listed in the model's `renamed` ({old: new}): a
document that still uses the old key is read, with a DeprecationWarning naming
both, for one release.

Quantities: pydantic field types that read a string with a unit ("0.5 mm")
through taxel.units, or an SI number when the model is validated from Python
(context {"si_numbers": True}). Names: safe as file names.
"""

from __future__ import annotations

import math
import re
import warnings
from typing import Annotated, ClassVar

from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict, ValidationInfo, model_validator

from taxel import units


class Strict(BaseModel):
    """The strict base of every schema model (see the module docstring)."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)
    renamed: ClassVar[dict[str, str]] = {}

    @model_validator(mode="before")
    @classmethod
    def _renamed_keys(cls, data):
        if cls.renamed and isinstance(data, dict):
            for old, new in cls.renamed.items():
                if old in data:
                    if new in data:
                        raise ValueError(f"'{old}' and '{new}' are both given; '{old}' is the old name of "
                                         f"'{new}': keep '{new}' only")
                    warnings.warn(f"'{old}' is now called '{new}'; the old name is read for one release",
                                  DeprecationWarning, stacklevel=2)
                    data = {(new if k == old else k): v for k, v in data.items()}
        return data


def renamed_value(value: str, renamed: dict[str, str], key: str) -> str:
    """A value (such as an output name) under its current name, with a
    DeprecationWarning when an old one was given."""
    if value in renamed:
        warnings.warn(f"{key} = '{value}' is now called '{renamed[value]}'; the old name is read for one "
                      "release", DeprecationWarning, stacklevel=2)
        return renamed[value]
    return value


def _quantity(unit: str, what: str, positive=False, nonnegative=False, scale: tuple[float, float] | None = None):
    """A field read by units.to_si: a string with a unit in a file, or SI numbers
    when the scene is built from Python (validation context {"si_numbers": True}).
    `scale`: the range a nonzero magnitude must lie in (a tactile sensor's lengths)."""
    def parse(v, info: ValidationInfo):
        si_numbers = bool(info.context and info.context.get("si_numbers"))
        x = units.to_si(v, unit, what, si_numbers=si_numbers, positive=positive, nonnegative=nonnegative)
        if scale and x != 0 and not scale[0] <= abs(x) <= scale[1]:
            raise ValueError(f"{v!r} is outside {units.engineering(scale[0], unit)} to "
                             f"{units.engineering(scale[1], unit)}, the scale of a tactile sensor")
        return x
    parse.unit = unit
    return BeforeValidator(parse)


GEOMETRY = (1e-6, 1.0)      # m: every nonzero length of the geometry (a 9 um film to a 1 m skin)
Length = Annotated[float, _quantity("m", "length", positive=True, scale=GEOMETRY)]
MeshSize = Annotated[float, _quantity("m", "length", positive=True, scale=(1e-12, 1.0))]
Thickness = Annotated[float, _quantity("m", "length", nonnegative=True, scale=GEOMETRY)]
Force = Annotated[float, _quantity("N", "force")]
Pressure = Annotated[float, _quantity("Pa", "pressure")]
Coordinate = Annotated[float, _quantity("m", "length", scale=(0.0, 1.0))]
Frequency = Annotated[float, _quantity("Hz", "frequency", positive=True)]
Duration = Annotated[float, _quantity("s", "time", positive=True)]
Resistance = Annotated[float, _quantity("ohm", "resistance", positive=True)]
Capacitance = Annotated[float, _quantity("F", "capacitance", nonnegative=True)]


def electrode_name(row: int, col: int) -> str:
    """The electrode of the taxel at (row, col) of an array: "taxel_ROW_COL" (the
    key of a scene's [electrodes] table, of result records and of study columns)."""
    return f"taxel_{row}_{col}"


def electrode_position(name: str) -> tuple[int, int] | None:
    """(row, col) of a taxel electrode's name, or None for another electrode."""
    m = re.fullmatch(r"taxel_(\d+)_(\d+)", name)
    return (int(m.group(1)), int(m.group(2))) if m else None


NAME = re.compile(r"[A-Za-z0-9_+-][A-Za-z0-9._+-]{0,99}")


def _check_name(v: str) -> str:
    if not NAME.fullmatch(v):
        raise ValueError(f"{v!r} is not a file name: use letters, digits, '.', '_', '+' or '-' "
                         "(at most 100, not starting with '.'); it names the output files")
    return v


Name = Annotated[str, AfterValidator(_check_name)]


def safe_name(stem: str) -> str:
    """A scene or study name from a file name: characters outside NAME become '-'."""
    name = re.sub(r"[^A-Za-z0-9._+-]", "-", stem).lstrip(".")[:100]
    return name or "scene"


def dimensionless_value(v, what: str = "fraction") -> float:
    """The number in a dimensionless value: 0.02, "0.02", "2 %", "2 percent",
    "500 ppm" or "1 mm/m" (pint through taxel.units); ValueError (one line) for
    anything else, a unit with a dimension, or a value that is not finite."""
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise ValueError(f"expected a {what} such as 0.02 or \"2 %\", got {v!r}")
    if isinstance(v, str):
        try:
            q = units.quantity(v.strip())
            x = float(q.to("").magnitude) if hasattr(q, "to") else float(q)
        except Exception:
            raise ValueError(f"cannot read {v!r} as a {what}; write e.g. 0.02 or \"2 %\"") from None
    else:
        x = float(v)
    if not math.isfinite(x):
        raise ValueError(f"must be a finite number, got {v!r}")
    return x


def dimensionless(what: str, *, ge: float | None = None, gt: float | None = None, lt: float | None = None,
                  le: float | None = None):
    """A dimensionless field (a fraction, a loss factor, a gain in V/V): whatever
    `dimensionless_value` reads, checked against the bounds; one line naming the
    bound otherwise. The same in a file and from Python (no unit to confuse)."""
    def parse(v, info: ValidationInfo):
        if v is None:
            return v
        x = dimensionless_value(v, what)
        for bound, ok, word in ((ge, lambda b: x >= b, "at least"), (gt, lambda b: x > b, "above"),
                                (lt, lambda b: x < b, "below"), (le, lambda b: x <= b, "at most")):
            if bound is not None and not ok(bound):
                raise ValueError(f"{v!r} must be {word} {bound:g} ({bound * 100:g} %)")
        return x
    parse.unit = None
    return BeforeValidator(parse)


Fraction = Annotated[float, dimensionless("fraction", gt=0, lt=1)]      # (0, 1): a tolerance, "2 %"
LossFactor = Annotated[float, dimensionless("loss factor", ge=0, lt=1)]
Ratio = Annotated[float, dimensionless("ratio (V/V)", gt=0)]
