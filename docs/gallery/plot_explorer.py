"""
The explorer's answers without a browser
========================================

`taxel explore` puts sliders over a scene's design variables. Behind the page is
a session that turns the controls' values into a scene (`taxel.explore.controls`)
and answers it through a study store (`taxel.explore.session`): a design seen
before is read, not solved, so moving a slider back is instant.

Here the same path runs without a server: the silicone above the taxel goes
from 0.5 to 2 mm, as a hand would drag the slider there and back, and each
answer is checked against a fresh `taxel.solve` of the same scene.
"""

import time

import matplotlib.pyplot as plt
import numpy as np

import taxel
from taxel.explore.controls import ControlValues, scene_of
from taxel.explore.session import Session

base = taxel.load("thesis-pzt-single-2d")
design = ControlValues.of(base)
session = Session()                       # a fresh store in a temporary folder

thickness = np.round(np.arange(0.5, 2.01, 0.25), 2)
volts, first, again = [], [], []
for t in list(thickness) + list(thickness[::-1]):          # there and back
    scene = scene_of(base, ControlValues({**design.numbers, "silicone_above": f"{t:g}"}, design.piezo))
    t0 = time.perf_counter()
    a = session.answer(scene)
    (again if a.cached else first).append(time.perf_counter() - t0)
    if not a.cached:
        volts.append(a.pressed_voltage)
        direct = taxel.solve(scene).voltages()[a.pressed]          # the same scene, solved directly
        assert abs(direct - a.pressed_voltage) <= 1e-9 * abs(direct), (direct, a.pressed_voltage)
session.close()
print(f"{len(first)} designs solved, median {1e3 * np.median(first):.0f} ms; "
      f"{len(again)} read back from the store, median {1e3 * np.median(again):.1f} ms")

fig, ax = plt.subplots(figsize=(6, 3.5), constrained_layout=True)
ax.plot(thickness, np.array(volts) * 1e3, "o-")
ax.set_xlabel("silicone above the taxel (mm)")
ax.set_ylabel("pressed-taxel open-circuit voltage (mV)")
ax.set_title(f"{base.name}: 1 N on the taxel, 2D (plane strain)")
ax.grid(alpha=0.3)
plt.show()
