"""Typed quantities for the schemas (scenes, studies, rig files): pydantic field
types that read a string with a unit ("0.5 mm") through taxel.units, or an SI
number when the model is validated from Python (context {"si_numbers": True}),
and names that are safe as file names."""

from __future__ import annotations

import re
from typing import Annotated

from pydantic import AfterValidator, BeforeValidator, ValidationInfo

from taxel import units


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
