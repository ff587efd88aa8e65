"""Robust design: a design's metrics under its fabrication spread, for the optimizer.

An optimization with a [robust] table evaluates each design x on a small tolerance
sample about it (studies.tolerance: the same spreads, distributions and scrambled
Sobol' points as a tolerance study) and gives three more metrics:

- robust_sensitivity: the `percentile` (e.g. the 5th) of |sensitivity| over the parts, V/N;
- robust_crosstalk: the (100 - percentile)th of crosstalk (the bad tail), ratio;
- yield: the fraction of the parts meeting every other [requirements] entry, ratio.

    [objective]
    maximize = "robust_sensitivity"
    [requirements]                    # the search obeys them all; a part's are all but the yield
    yield = ">= 0.9"
    crosstalk = "<= 8 %"
    [robust]
    percentile = 5
    samples = 16                      # parts per design (a power of two keeps Sobol' balanced)
    seed = 0                          # the same quasi-random parts for every design and every run
    [[robust.parameters]]
    path = "array.silicone_above"
    tolerance = "0.1 mm"              # about the design's value ("10 %": relative)
    distribution = "uniform"          # or "normal" (tolerance = 3 sigma)

Every part is a point of the optimization's store (keyed by its scene), so a
part shared by two designs, or by two runs, is solved once. The parts of every
design come from the same probabilities u (the fixed seed): the metrics are
common-random-number estimates, smooth in x up to the discretisation noise, and a
run is reproducible. A failed part counts as a reject (sensitivity 0, crosstalk inf).
The percentile is the sample's (numpy's linear interpolation): with n parts its
sampling error is about sqrt(p (1 - p) / n) / pdf in probability; the yield's
resolution is 1 / n (its 95 % interval: studies.yield_analysis.yield_of).
"""

from __future__ import annotations

import json
from typing import Any, Callable, Literal

import numpy as np
from pydantic import Field

from taxel.schema import Strict
from taxel.studies.spec import get_value, set_value
from taxel.studies.tolerance import Spread, meets, sample, spread

ROBUST_METRICS = ("robust_sensitivity", "robust_crosstalk", "yield")


class RobustParameter(Strict):
    path: str
    label: str | None = None
    tolerance: Any
    distribution: Literal["normal", "uniform"] = "normal"

    @property
    def name(self) -> str:
        return self.label or self.path.split(".")[-1]


class Robust(Strict):
    """The [robust] table of an optimization."""
    percentile: float = Field(5.0, gt=0, lt=100)
    samples: int = Field(16, ge=2, le=4096)
    seed: int = 0
    parameters: list[RobustParameter] = Field(min_length=1)


def spreads(robust: Robust, data: dict) -> list[Spread]:
    """Each tolerance about the design `data`'s value at its path (the scene default when unset)."""
    out = []
    full = None
    for p in robust.parameters:
        nominal = get_value(data, p.path)
        if nominal is None:
            if full is None:
                from taxel.scene import parse
                from taxel.schema import to_data
                full = to_data(parse({**data, "name": "nominal"}))
            nominal = get_value(full, p.path)
        out.append(spread(p.name, nominal, p.tolerance, p.distribution))
    return out


def parts(robust: Robust, data: dict) -> tuple[list[Spread], np.ndarray, list[dict]]:
    """(spreads, values (n, d), the parts' scene dicts) of design `data`."""
    sp = spreads(robust, data)
    x = sample(sp, robust.samples, robust.seed)
    scenes = []
    for row in x:
        d = json.loads(json.dumps(data))
        for p, s, v in zip(robust.parameters, sp, row):
            set_value(d, p.path, s.text(v))
        scenes.append(d)
    return sp, x, scenes


def robust_metrics(robust: Robust, requirements: dict[str, tuple[str, float]], data: dict,
                   evaluate: Callable[[dict, dict], dict]) -> dict:
    """robust_sensitivity, robust_crosstalk and yield of design `data`; `evaluate(part, params)`
    gives a part's metrics (sensitivity, crosstalk, ...), from the store when it was solved."""
    sp, x, scenes = parts(robust, data)
    got = [evaluate(d, {s.name: float(v) for s, v in zip(sp, row)}) for d, row in zip(scenes, x)]

    def column(name, bad):
        v = np.array([m.get(name) if m.get(name) is not None else np.nan for m in got], float)
        return np.where(np.isfinite(v), v, bad)
    p = robust.percentile
    out = {"robust_sensitivity": float(np.percentile(np.abs(column("sensitivity", 0.0)), p)),
           "robust_crosstalk": float(np.percentile(column("crosstalk", np.inf), 100 - p))
           if any(m.get("crosstalk") is not None for m in got) else None}
    part = {k: v for k, v in requirements.items() if k not in ROBUST_METRICS}   # a part's spec, not the yield's
    if part:
        ok = np.logical_and.reduce([meets([m.get(k) if m.get(k) is not None else np.nan for m in got], op, b)
                                    for k, (op, b) in part.items()])
        out["yield"] = float(np.mean(ok))
    else:
        out["yield"] = None
    return out
