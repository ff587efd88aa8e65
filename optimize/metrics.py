"""The optimizer's metrics, each with its unit and its axis label: one table.

A metric with unit "ratio" or "dB" is dimensionless (its bound is a plain number);
the others are SI (a bound may carry any unit of the same kind: "2 mm").
The noise metrics come from optimize.resolution, the warm touch's from optimize.warm, the robust ones (a percentile over
the design's fabrication spread, the yield) from optimize.robust, coverage and
localization_error from the influence functions (optimize.coverage), the geometric
ones from the scene alone (`geometry`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Metric:
    """One optimizer metric: what it is called on an axis and its SI unit."""
    label: str
    unit: str
    lo: float = 0.0               # the values it can take: a requirement outside them cannot be met
    hi: float = math.inf

    @property
    def axis(self) -> str:
        """The axis label, its unit in parentheses."""
        return f"{self.label} ({self.unit})"


METRIC_TABLE = {
    "sensitivity": Metric("sensitivity", "V/N"),
    "tangent_sensitivity": Metric("small-signal sensitivity", "V/N"),
    "crosstalk": Metric("crosstalk", "ratio"),
    "readout_sensitivity": Metric("sensitivity at the readout", "V/N"),
    "readout_crosstalk": Metric("crosstalk at the readout", "ratio"),
    "max_strain": Metric("largest silicone strain", "ratio"),
    "total_thickness": Metric("total thickness", "m"),
    "footprint": Metric("footprint", "m"),
    "pitch": Metric("pitch", "m"),
    "gap": Metric("gap", "m"),
    "localization_error": Metric("localization error", "m"),
    "coverage": Metric("coverage", "ratio", hi=1.0),
    "min_detectable_force": Metric("minimum detectable force", "N"),
    "snr": Metric("SNR", "dB", lo=-math.inf),
    "dynamic_range": Metric("dynamic range", "dB", lo=-math.inf),
    "robust_sensitivity": Metric("sensitivity percentile", "V/N"),
    "robust_crosstalk": Metric("crosstalk percentile", "ratio"),
    "yield": Metric("yield", "ratio", hi=1.0),
    "warm_touch_force": Metric("warm-touch false force", "N"),
    "warm_touch_ratio": Metric("warm-touch false force / minimum detectable force", "ratio"),
}
PLAIN = ("ratio", "dB")                  # units whose bounds are plain numbers
METRICS = tuple(METRIC_TABLE)


def geometry(scene) -> dict:
    """The geometric metrics of a taxel-array scene, without FEM (m): total thickness (silicone
    above + piezo + below), footprint (the array's width along x with its margins), gap, pitch."""
    a = scene.array
    return {"total_thickness": a.silicone_above + a.piezo_thickness + a.silicone_below,
            "footprint": a.footprint, "gap": a.gap, "pitch": a.pitch}


def axis_label(metric: str) -> str:
    """The axis label of a metric; a metric missing from METRIC_TABLE is a KeyError
    (every metric carries its unit)."""
    return METRIC_TABLE[metric].axis
