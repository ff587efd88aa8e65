"""The optimizer's metrics, each with its unit and its axis label: the output table's
"metric" rows (taxel.analyses.results.outputs, which statics and tolerances read too).

A metric with unit "ratio" or "dB" is dimensionless (its bound is a plain number);
the others are SI (a bound may carry any unit of the same kind: "2 mm").
The noise metrics come from optimize.resolution, the warm touch's from optimize.warm, the robust ones (a percentile over
the design's fabrication spread, the yield) from optimize.robust, coverage and
localization_error from the influence functions (optimize.coverage), the geometric
ones from the scene alone (`geometry`).
"""

from __future__ import annotations

from taxel.analyses.results.outputs import Output, table

# the optimizer's metrics: the output table's "metric" ones (taxel.analyses.results.outputs),
# each an Output with its label, SI unit, bounds and axis label
METRIC_TABLE: dict[str, Output] = table("metric")
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
