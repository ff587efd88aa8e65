"""
A press with a probe
====================

The thesis's rig presses a rigid probe, not a pressure patch. ``[load] kind =
"probe"`` with ``contact = true`` solves the contact of a rigid indenter (here a
cylinder of 2 mm radius on the 2D section) with the silicone, to a force; each
converged load step is a point of the voltage-force and force-travel curves.
Sticking friction is the default (a dry probe on tacky silicone).
"""

import matplotlib.pyplot as plt
import numpy as np

import taxel

scene = taxel.load("thesis-pzt-single-2d").replace(**{
    "load.kind": "probe", "load.contact": True, "load.shape": "cylinder",
    "load.radius": "2 mm", "load.force": "0.5 N",
})
result = taxel.solve(scene)
print("\n".join(result.summary()))

# %%
# The press record: every converged state on the way to the force.
press = result.contact_record()
curve = press["curve"]
travel = np.array(curve["travel_m"]) * 1e3
force = np.array(curve["force_N"])
volts = np.array(curve["voltages_V"]["taxel_0_0"]) * 1e3
print(f"contact half-width {press['contact_half_width_m'] * 1e3:.2f} mm, "
      f"largest pressure {press['max_pressure_Pa'] / 1e3:.1f} kPa, {press['load_steps']} load steps")
fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.2))
a.plot(travel, force, "o-")
a.set(xlabel="indenter travel (mm)", ylabel="force (N)", title="force-travel")
b.plot(force, volts, "o-", color="C3")
b.set(xlabel="force (N)", ylabel="open-circuit voltage (mV)", title="voltage-force")
fig.tight_layout()
