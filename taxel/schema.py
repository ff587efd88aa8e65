"""The base of the four TOML schemas (scene, study, optimization, rig): one strict
pydantic model, typed quantities and safe names.

`Strict`: unknown keys are refused, models are frozen, defaults are validated.

Quantities: pydantic field types that read a string with a unit ("0.5 mm")
through taxel.units, or an SI number when the model is validated from Python
(context {"si_numbers": True}). Names: safe as file names.
"""

from __future__ import annotations

import copy
import math
import re
import tomllib
import typing
from pathlib import Path
from typing import Annotated, Literal

from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict, ValidationError, ValidationInfo

from taxel import units


class Strict(BaseModel):
    """The strict base of every schema model (see the module docstring)."""

    # a field's docstring is its description (JSON Schema, `taxel schema`, the key reference)
    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True, use_attribute_docstrings=True)


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
    parse.bounds = {k: b for k, b in (("ge", ge), ("gt", gt), ("le", le), ("lt", lt)) if b is not None}
    return BeforeValidator(parse)


Fraction = Annotated[float, dimensionless("fraction", gt=0, lt=1)]      # (0, 1): a tolerance, "2 %"
LossFactor = Annotated[float, dimensionless("loss factor", ge=0, lt=1)]


def friction_law(v):
    """load.friction: "frictionless", "sticking", or a Coulomb coefficient (a number >= 0)."""
    if v is None or v in ("frictionless", "sticking"):
        return v
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
        raise ValueError(f'expected "frictionless", "sticking" or a Coulomb coefficient >= 0 such as 0.4, got {v!r}')
    if v > MAX_FRICTION:
        raise ValueError(f"a Coulomb coefficient of {v:g} is beyond any measured for a silicone (about 0.2 to 3, "
                         f"up to {MAX_FRICTION:g} here): for no slip at all write \"sticking\"")
    return float(v)


# the largest Coulomb coefficient accepted: tacky silicones on glass or steel measure about 0.2 to 3;
# a far larger one is "sticking" (and overflows the return mapping's slip bound, mu * pressure)
MAX_FRICTION = 10.0


FrictionLaw = Annotated[Literal["frictionless", "sticking"] | float | None, BeforeValidator(friction_law)]

Ratio = Annotated[float, dimensionless("ratio (V/V)", gt=0)]

NoiseVoltage = Annotated[float, _quantity("V/Hz**0.5", "voltage noise density", nonnegative=True)]
NoiseCurrent = Annotated[float, _quantity("A/Hz**0.5", "current noise density", nonnegative=True)]
Voltage = Annotated[float, _quantity("V", "voltage", nonnegative=True)]
SignedVoltage = Annotated[float, _quantity("V", "voltage")]     # an ADC's input range may go below zero
Temperature = Annotated[float, _quantity("K", "temperature", positive=True)]
# a surface's heat transfer coefficient: a contact conductance or a convection coefficient
HeatTransfer = Annotated[float, _quantity("W/(m^2*K)", "heat transfer coefficient", nonnegative=True)]


# --------------------------------------------------------------------------------------
# documents: reading a TOML file, one-line errors, dotted paths, back to TOML-like data
# --------------------------------------------------------------------------------------

def read_toml(path: Path, error: type[Exception]) -> dict:
    """A TOML file as a dict; an unreadable or invalid file raises `error` with one
    line naming it."""
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML: {exc}") from None
    except UnicodeDecodeError:
        raise error(f"{path}: not UTF-8 text; save it as a UTF-8 TOML file") from None
    except OSError as exc:
        raise error(f"{path}: cannot read it ({exc.strerror or exc})") from None


def one_line(err: ValidationError) -> str:
    """The first problem of a pydantic error as one line: the key, the problem, the fix."""
    e = err.errors()[0]
    loc = ".".join(str(x) for x in e["loc"] if not str(x).startswith("function-after"))
    msg = e["msg"].removeprefix("Value error, ")
    if e["type"] == "extra_forbidden":
        return f"unknown key '{loc}'; check its spelling against 'taxel schema' (or the key reference in the docs)"
    if e["type"] == "missing":
        return f"'{loc}' is required; add it"
    if e["type"] == "literal_error":
        return f"{loc}: {msg} (got {e['input']!r})"
    return f"{loc}: {msg}" if loc else msg


def set_path(data: dict, path: str, value):
    """Set `value` at a dotted path of a document (a scene, study or rig dict); a table is merged (deeply) into
    the table there. The path "" is the scene itself. Raises KeyError(path) where a
    key on the way is not a table."""
    if path == "":
        if not isinstance(value, dict):
            raise KeyError(path)
        _merge(data, value)
        return
    keys = path.split(".")
    node = data
    for k in keys[:-1]:
        node = node.setdefault(k, {})
        if not isinstance(node, dict):
            raise KeyError(path)
    if isinstance(value, dict) and isinstance(node.get(keys[-1]), dict):
        _merge(node[keys[-1]], value)
    else:
        node[keys[-1]] = value


def _merge(node: dict, value: dict):
    for k, v in value.items():
        if isinstance(v, dict) and isinstance(node.get(k), dict):
            _merge(node[k], v)
        else:
            node[k] = v


def to_data(model: BaseModel) -> dict:
    """A validated document (a scene or part of one) as a TOML-like dict that its
    model reads back: quantities as
    strings with their SI unit ("0.001 m"), everything else as is."""
    out = {}
    for name, info in type(model).model_fields.items():
        value = getattr(model, name)
        if value is None:
            continue
        unit = next((getattr(m.func, "unit", None) for m in info.metadata if hasattr(m, "func")), None)
        if unit is None:                                  # tuple[Coordinate, Coordinate] and friends
            for arg in typing.get_args(info.annotation):
                for m in getattr(arg, "__metadata__", ()):
                    unit = getattr(getattr(m, "func", None), "unit", unit)
        if isinstance(value, BaseModel):
            out[name] = to_data(value)
        elif isinstance(value, list) and value and isinstance(value[0], BaseModel):
            out[name] = [to_data(v) for v in value]
        elif unit and isinstance(value, float):
            out[name] = f"{value!r} {unit}"
        elif unit and isinstance(value, tuple):
            out[name] = [f"{v!r} {unit}" for v in value]
        else:
            out[name] = copy.deepcopy(list(value) if isinstance(value, tuple) else value)
    return out
