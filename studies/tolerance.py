"""Fabrication tolerances of a design: how a tolerance study samples its spread.

A study with sampling = "tolerance" varies each parameter about its nominal value
(the base scene's, or `nominal = ...`) by its `tolerance`, absolute ("0.1 mm") or
relative ("10 %"), with its `distribution`:

- "uniform": nominal +- tolerance, flat;
- "normal":  mean nominal, standard deviation tolerance / 3 (the tolerance is the
  +-3 sigma band of a capable process; 0.27 % of the parts fall outside it).

The points are quasi-random: a scrambled Sobol' sequence (scipy.stats.qmc, seeded
by the study's `seed`) mapped through each distribution's inverse CDF, `samples`
points (a power of two keeps the sequence balanced). A study's `[requirements]`
table, e.g. {sensitivity = ">= 0.7 V/N", crosstalk = "<= 2 %"}, gives the yield
(studies.yield_analysis); its grammar and units are studies.requirements', checked when
the study file is read against the outputs a tolerance study has (the output table's "tolerance" ones, taxel.analyses.results.outputs).

    sampling = "tolerance"
    samples = 64
    [requirements]
    sensitivity = ">= 0.7 V/N"
    [[parameters]]
    path = "array.silicone_above"
    tolerance = "0.1 mm"
    distribution = "uniform"
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from taxel import units
from taxel.studies.requirements import Requirement

DISTRIBUTIONS = ("normal", "uniform")


class ToleranceError(ValueError):
    """A tolerance that cannot be read; one line naming the parameter and the fix."""


@dataclass(frozen=True)
class Spread:
    """One parameter's fabrication spread: value = nominal + width * z, z standardised."""

    name: str
    nominal: float
    unit: str                     # the nominal's unit ("" for a plain number)
    distribution: str             # normal | uniform
    half_width: float             # the tolerance, in the nominal's unit

    @property
    def sigma(self) -> float:
        """The standard deviation, in the nominal's unit."""
        return self.half_width / 3 if self.distribution == "normal" else self.half_width / math.sqrt(3)

    def value(self, u: np.ndarray) -> np.ndarray:
        """The values at probabilities u in (0, 1) (inverse CDF)."""
        if self.distribution == "uniform":
            return self.nominal + self.half_width * (2 * np.asarray(u) - 1)
        from scipy.stats import norm
        return self.nominal + (self.half_width / 3) * norm.ppf(u)

    def salib(self) -> tuple[list[float], str]:
        """(bounds, dist) of this parameter in SALib's problem dict."""
        if self.distribution == "uniform":
            return [self.nominal - self.half_width, self.nominal + self.half_width], "unif"
        return [self.nominal, self.half_width / 3], "norm"

    def text(self, x: float):
        """The value as a scene takes it ("1.02 mm", or a number)."""
        x = round(float(x), 12)
        return f"{x:.9g} {self.unit}" if self.unit else x


def spread(name: str, nominal, tolerance, distribution: str) -> Spread:
    """A Spread from the study file's values (nominal: a quantity or a number; tolerance:
    a quantity in a compatible unit, a number, or a percentage "10 %")."""
    if distribution not in DISTRIBUTIONS:
        raise ToleranceError(f"parameters '{name}': distribution = '{distribution}'; use normal or uniform")
    if nominal is None:
        raise ToleranceError(f"parameters '{name}': no nominal value (the base scene has none at the path); "
                             "give nominal = ...")
    try:
        x0, unit = units.in_unit(nominal)
    except units.UnitError as exc:
        raise ToleranceError(f"parameters '{name}': nominal: {exc}") from None
    if isinstance(tolerance, str) and tolerance.strip().endswith("%"):
        try:
            width = abs(x0) * float(tolerance.strip()[:-1]) / 100
        except ValueError:
            raise ToleranceError(f"parameters '{name}': tolerance {tolerance!r}; write e.g. \"10 %\"") from None
    else:
        try:
            width = units.in_unit(tolerance, unit or None)[0]
        except units.UnitError as exc:
            raise ToleranceError(f"parameters '{name}': tolerance: {exc}") from None
    if not width > 0:
        raise ToleranceError(f"parameters '{name}': the tolerance must be positive, got {tolerance!r}")
    return Spread(name, float(x0), unit, distribution, float(width))


def sample(spreads: list[Spread], n: int, seed: int) -> np.ndarray:
    """(n, d) values: a scrambled Sobol' sequence through each spread's inverse CDF."""
    import warnings
    from scipy.stats import qmc
    with warnings.catch_warnings():            # n not a power of two: still low-discrepancy, less balanced
        warnings.simplefilter("ignore", UserWarning)
        u = qmc.Sobol(d=len(spreads), scramble=True, seed=seed).random(n)
    u = np.clip(u, 1e-12, 1 - 1e-12)
    return np.column_stack([s.value(u[:, j]) for j, s in enumerate(spreads)])


def meets(values: np.ndarray, op: str, bound: float) -> np.ndarray:
    """Which values meet a requirement (NaN, a failed point, does not)."""
    return Requirement("", op, bound, "").met(values)
