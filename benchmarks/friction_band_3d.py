"""How far the answer's friction band from the 2D press is from a 3D one (taxel.jobs.friction_band).

The main job's band is the probe front's 2D press (plane strain, the base scene's mesh) with
only load.friction changed, because the 3D frictionless press of the rig's probe stops short
of 1 N (issue 47). Here the thesis PZT design (3x3 array, silicone 1 / 1 mm, gap 3 mm; the
NAME-probe-front spec's probe: a 4 mm flat punch, 0.2 mm edge radius, Yeoh silicone) is
pressed at a force the 3D press reaches at both limits (default 0.5 N), frictionless and
sticking, in 2D (the job's model) and in 3D (the probe front's level-C model,
optimize.probe_front.PRESS_3D: the default press mesh, a quarter), and the band

    spread = |V/N| frictionless / |V/N| sticking - 1    (and the crosstalk of each)

of the two models is compared: the 2D band's error as a model of the 3D band.

Measured (one run, load 4-6 on 2 cores, the thesis PZT design at 0.5 N):
  2D press: sticking 0.74704 V/N (crosstalk 4.22 %), frictionless 0.80136 V/N (6.47 %): band +7.27 %
  3D press: sticking 0.83525 V/N (crosstalk 1.23 %), frictionless 0.88779 V/N (1.60 %): band +6.29 %
  (3D: sticking 70 s, frictionless 698 s; 2D: 3 s and 5 s)
so the 2D band is 1.0 point of sensitivity wider than the 3D one; the crosstalk grows by 1.53
times in 2D, 1.30 in 3D (the plane section's crosstalk is itself about 3 times too high).

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/friction_band_3d.py [--force 0.5] [--material pzt]
writes benchmarks/out/friction_band_3d.json.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from taxel.analyses import friction_leg
from taxel.optimize import spec as O
from taxel.optimize.multifidelity import fine_data
from taxel.optimize.probe import press_scene
from taxel.optimize.probe_front import PRESS_3D
from taxel.scene import parse

THESIS_X = [1.0, 1.0, 3.0]        # silicone above, below, gap (mm): the thesis design


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--force", type=float, default=0.5, help="N")
    ap.add_argument("--material", default="pzt", choices=["pzt", "pvdf"])
    args = ap.parse_args()
    prob = O.load_optimization(f"thesis-{args.material}-probe-front")
    out = {"force_N": args.force, "design_mm": dict(zip(prob.names, THESIS_X)), "press": prob.spec.press.model_dump()}
    for model, data in (("2d", prob.scene_data(THESIS_X)), ("3d", fine_data(prob, THESIS_X, PRESS_3D))):
        data = press_scene(data, prob.spec.press)
        data["load"]["force"] = f"{args.force} N"
        scene = parse({**data, "name": f"band-{model}"})
        legs = {}
        for law in ("sticking", "frictionless"):
            t0 = time.perf_counter()
            leg = friction_leg(scene, law)
            legs[law] = {**leg.record(), "seconds": time.perf_counter() - t0}
            print(f"{model} {law}: |V/N| {abs(leg.sensitivity):.5g}, crosstalk {leg.crosstalk}, force {leg.force:.4g} N"
                  f"{'' if leg.success else ' STOPPED: ' + leg.stop}, {legs[law]['seconds']:.0f} s", flush=True)
        s = {k: abs(v["sensitivity_V_per_N"]) for k, v in legs.items()}
        out[model] = {"legs": legs, "spread": s["frictionless"] / s["sticking"] - 1,
                      "crosstalk_ratio": (legs["frictionless"]["crosstalk"] / legs["sticking"]["crosstalk"]
                                          if legs["sticking"]["crosstalk"] else None)}
        print(f"{model}: band (frictionless / sticking - 1) {100 * out[model]['spread']:+.2f} %", flush=True)
    out["spread_difference"] = out["2d"]["spread"] - out["3d"]["spread"]
    print(f"2D band {100 * out['2d']['spread']:+.2f} % against 3D {100 * out['3d']['spread']:+.2f} %")
    Path("benchmarks/out").mkdir(parents=True, exist_ok=True)
    Path(f"benchmarks/out/friction_band_3d_{args.material}.json").write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
