"""Requirements on a design's outputs: `output = "<= 2 %"` or `output = ">= 0.7 V/N"`.

One grammar, shared by every file that states what a design must meet (a tolerance
study's `[requirements]`, from which its yield is counted):

    requirement := ("<=" | ">=") number [unit | "%"]

The output must be one the caller produces (`outputs`: name -> its SI unit, "" for a
ratio, "dB" for a level), and the bound's unit must have that output's dimension
(pint): crosstalk "<= 2 %" or "<= 0.02", sensitivity ">= 0.7 V/N" or ">= 700 mV/N",
snr ">= 40 dB". A bound without a unit is accepted only for a ratio. Anything else is
refused with one line naming `requirements.OUTPUT` and the fix (RequirementError).

    from taxel.studies.requirements import Requirement, parse_requirements
    reqs = parse_requirements({"crosstalk": "<= 2 %"}, units_of("tolerance"))
    reqs["crosstalk"].met(values)          # bool array; NaN (a failed point) never meets it
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from taxel import units

# The outputs a tolerance study has per point and their SI units are the output table's
# "tolerance" ones (taxel.analyses.results.outputs.units_of("tolerance")).

_GRAMMAR = re.compile(r"\s*(<=|>=)\s*(\S.*?)\s*")
_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


class RequirementError(ValueError):
    """A requirement that cannot be read or cannot apply; one line naming it and the fix."""


@dataclass(frozen=True)
class Requirement:
    """`output op bound`: bound in the output's SI unit (a ratio as a fraction, a level in dB)."""

    output: str
    op: str                # "<=" or ">="
    bound: float
    unit: str = ""         # the output's SI unit ("" for a ratio)

    def margin(self, value: float | None) -> float | None:
        """The margin of `value` relative to the bound, positive when met:
        (value - bound) / |bound| for ">=", (bound - value) / |bound| for "<="; None when
        the value is unknown (None or not finite)."""
        if value is None or not math.isfinite(value):
            return None
        scale = abs(self.bound) or 1.0
        return (value - self.bound) / scale if self.op == ">=" else (self.bound - value) / scale

    def met(self, values) -> np.ndarray:
        """Which values meet it (NaN, a failed point, does not)."""
        v = np.asarray(values, float)
        with np.errstate(invalid="ignore"):
            return np.where(np.isnan(v), False, v <= self.bound if self.op == "<=" else v >= self.bound)

    def text(self) -> str:
        return f"{self.output} {self.op} {self.bound:g}" + (f" {self.unit}" if self.unit else "")


def _example(unit: str) -> str:
    return {"": '"<= 2 %" or "<= 0.02"', "dB": '">= 40 dB"'}.get(unit, f'">= 1 {unit}"')


def parse_requirement(output: str, text, outputs: dict[str, str | None] | None = None) -> Requirement:
    """The Requirement `output = text`, checked against `outputs` (name -> SI unit); with
    outputs None (a caller that checks its own names) or an output's unit None (unknown),
    the grammar only, the bound in SI base units."""
    where = f"requirements.{output}"
    if outputs is not None and output not in outputs:
        raise RequirementError(f"{where}: not an output; require one of {', '.join(sorted(outputs))}")
    unit = outputs[output] if outputs is not None else None
    if unit is None:
        return _unchecked(where, output, text)
    m = _GRAMMAR.fullmatch(str(text)) if isinstance(text, str) else None
    if m is None:
        raise RequirementError(f"{where} = {text!r}: write \"<= value\" or \">= value\", e.g. {_example(unit)}")
    op, value = m.groups()
    number = _NUMBER.match(value)
    if number is None:
        raise RequirementError(f"{where} = {text!r}: no number after {op}; write e.g. {_example(unit)}")
    rest = value[number.end():].strip()
    x = float(number.group())
    if unit == "dB":
        if rest != "dB":
            raise RequirementError(f"{where} = {text!r}: {output} is a level in dB; write e.g. {_example(unit)}")
        bound = x
    elif rest == "%":
        if unit:
            raise RequirementError(f"{where} = {text!r}: a percentage fits a ratio, but {output} is in {unit}; "
                                   f"write e.g. {_example(unit)}")
        bound = x / 100
    elif not rest:
        if unit:
            raise RequirementError(f"{where} = {text!r}: missing unit; {output} is in {unit}, "
                                   f"write e.g. {_example(unit)}")
        bound = x
    else:
        try:
            q = units.quantity(f"{x!r} {rest}")
            want = units.quantity(f"1 {unit}") if unit else None
            if want is None:
                ok = q.dimensionless
            else:
                ok = q.dimensionality == want.dimensionality
        except Exception:
            raise RequirementError(f"{where} = {text!r}: cannot read the unit {rest!r}; "
                                   f"write e.g. {_example(unit)}") from None
        if not ok:
            raise RequirementError(f"{where} = {text!r}: {rest} does not fit {output}, which is "
                                   f"{'a ratio' if not unit else 'in ' + unit}; write e.g. {_example(unit)}")
        bound = float(q.to(unit).magnitude) if unit else float(q.to("").magnitude)
    if not math.isfinite(bound):
        raise RequirementError(f"{where} = {text!r}: the bound is not finite")
    return Requirement(output, op, bound, unit)


def _unchecked(where: str, output: str, text) -> Requirement:
    m = _GRAMMAR.fullmatch(str(text)) if isinstance(text, str) else None
    if m is None:
        raise RequirementError(f"{where} = {text!r}: write \"<= value\" or \">= value\", e.g. \">= 0.7 V/N\"")
    op, value = m.groups()
    try:
        if value.endswith("%"):
            bound = float(value[:-1]) / 100
        else:
            q = units.quantity(value)
            bound = float(q.to_base_units().magnitude) if hasattr(q, "to_base_units") else float(q)
    except Exception:
        raise RequirementError(f"{where} = {text!r}: cannot read {value!r}; write e.g. \">= 0.7 V/N\"") from None
    if not math.isfinite(bound):
        raise RequirementError(f"{where} = {text!r}: the bound is not finite")
    return Requirement(output, op, bound, "")


def parse_requirements(texts: dict, outputs: dict[str, str]) -> dict[str, Requirement]:
    """Every `output = text` of a `[requirements]` table, checked (parse_requirement)."""
    return {k: parse_requirement(k, v, outputs) for k, v in texts.items()}
