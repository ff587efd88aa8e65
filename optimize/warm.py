"""The warm touch as optimizer metrics (taxel.analyses.solves.warm_touch): a design's false
press from a warm finger at its readout, and that over its minimum detectable force.

    warm_touch_force   N       the press held as long as the finger that gives the same
                               peak output (the scene's [warm_touch], or its defaults: a
                               34 C finger held 1 s on a 23 C skin)
    warm_touch_ratio   ratio   warm_touch_force / min_detectable_force (the chain's noise
                               budget); "<= 100 %": a warm touch fakes no press the readout
                               could tell from noise

A requirement names them as any other metric (optimize.requirements):

    [requirements]
    warm_touch_ratio = "<= 100 %"
    warm_touch_force = "<= 5 mN"

Cost: one conduction and one static solve on the design's own model (2D or
axisymmetric: a few seconds).
"""

from __future__ import annotations

from taxel.analyses.solves.warm_touch import warm_touch
from taxel.scene import SceneError

WARM_METRICS = ("warm_touch_force", "warm_touch_ratio")


def warm_metrics(scene, rig=None) -> dict:
    """{warm_touch_force (N), warm_touch_ratio} of a design; None values when the design
    has no pressed taxel or its materials no heat."""
    try:
        r = warm_touch(scene, rig=rig)
    except SceneError:
        return dict.fromkeys(WARM_METRICS)
    return {"warm_touch_force": r.false_force, "warm_touch_ratio": r.ratio}
