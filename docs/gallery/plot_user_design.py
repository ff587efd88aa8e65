"""
Your own design: requirements in, a recommendation out
======================================================

A user's sensor, not the thesis's: a PVDF array of 2 x 2 taxels of 5 mm under a
silicone of their own (a softer Yeoh law, ``[materials.soft-gel]``), read through a
charge amplifier (``[readout] circuit = "charge_amplifier"``). The optimization
file states what the sensor must meet (``[requirements]``): a minimum detectable
force through the readout, a pitch and a thickness. The sensitivity-crosstalk front
of the 2D section is searched; the report's answer names the user's reference
design as theirs, recommends the front design meeting every requirement that is
best by the objective (the most sensitive), and gives the readout's numbers (its V/N, crosstalk and the
minimum detectable force) beside the open-circuit ones. A second file with a
stricter minimum detectable force shows the requirement that binds.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import taxel
from taxel.reports.answer import headline_front, requirement_rows

folder = Path(tempfile.mkdtemp(prefix="taxel-user-"))
(folder / "my-sensor.toml").write_text('''
description = "my PVDF 2x2 array under a soft gel, charge amplifier"
[model]
type = "plane_strain"
[mesh]
size = "0.6 mm"
piezo_size = "0.15 mm"
order = 2
[array]
rows = 2
cols = 2
taxel_width = "5 mm"
piezo = "PVDF"
piezo_thickness = "52 um"
gap = "2 mm"
margin = "3 mm"
silicone = "soft-gel"
silicone_above = "1.5 mm"
silicone_below = "0.5 mm"
[load]
kind = "taxel"
taxel = [0, 0]
force = "1 N"
[supports]
bottom = "bonded"
[readout]
circuit = "charge_amplifier"
C_f = "100 pF"
[materials.soft-gel]
kind = "solid"
C10 = "20 kPa"
C20 = "0.3 kPa"
C30 = "0 Pa"
K = "40 MPa"
rho = "1070 kg/m^3"
''')
OPTIMIZATION = '''
description = "my sensor: the most sensitive design meeting my requirements"
base = "my-sensor.toml"
reference = {{silicone_above = "1.5 mm", gap = "2 mm"}}

[variables]
silicone_above = {{path = "array.silicone_above", min = "0.5 mm", max = "2 mm", start = "1.5 mm"}}
gap = {{path = "array.gap", min = "1 mm", max = "4 mm", start = "2 mm"}}

[objective]
maximize = "sensitivity"

[requirements]
min_detectable_force = "<= {mdf}"
pitch = "<= 9 mm"
total_thickness = "<= 2.6 mm"

[pareto]
points = 3

[algorithm]
global = "none"
local = "COBYLA"
max_evaluations = 8
'''
(folder / "front.toml").write_text(OPTIMIZATION.format(mdf="1 mN"))
front = taxel.run_optimization(folder / "front.toml", folder / "front", workers=1)
print("\n".join(front.summary()))

# %%
# The answer the report leads with: the user's reference design, the recommendation and
# each requirement against the prediction with its margin.
answer = headline_front(folder / "front")
print(answer.trade)
for row in requirement_rows(answer):
    print(" | ".join(row))
recommended = answer.recommended or answer.thesis
readout_V_per_N = recommended.values["readout_sensitivity"]
open_circuit_V_per_N = recommended.sensitivity_V_per_N
min_detectable_force = recommended.values["min_detectable_force"]
print(f"recommended: {readout_V_per_N:.3g} V/N at the charge amplifier, {open_circuit_V_per_N:.3g} V/N "
      f"open circuit; minimum detectable force {1e6 * min_detectable_force:.3g} uN")

# %%
# The same front against a minimum detectable force no design reaches: no
# recommendation, and the requirement that binds, by how much.
(folder / "strict.toml").write_text(OPTIMIZATION.format(mdf="1 uN"))
strict_front = taxel.run_optimization(folder / "strict.toml", folder / "strict", workers=1)
strict = headline_front(folder / "strict")
print(strict.trade)

# %%
# The front, the reference and the recommended design at the readout.
rows = [r for r in front.front_rows]
fig, ax = plt.subplots(figsize=(5, 3.5))
ax.plot([100 * r["readout_crosstalk"] for r in rows], [r["readout_sensitivity"] for r in rows], "o-",
        label="front (2D section)")
ax.plot(100 * answer.thesis.values["readout_crosstalk"], answer.thesis.values["readout_sensitivity"], "s",
        label="your reference design")
ax.plot(100 * recommended.values["readout_crosstalk"], readout_V_per_N, "*", ms=12, label="recommended")
ax.set_xlabel("crosstalk at the readout (%)")
ax.set_ylabel("sensitivity at the readout (V/N)")
ax.legend()
fig.tight_layout()
plt.show()
