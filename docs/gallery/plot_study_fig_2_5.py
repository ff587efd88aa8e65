"""
A parameter study: the thesis's Fig. 2.5, small
===============================================

A study file names a base scene and the parameters to sweep; ``taxel.run_study``
solves every point not already in the folder's store (on Dask workers, or in the
process with ``workers=1``), then writes ``results.csv`` and plots. This is the
built-in ``fig-2-5`` (pressed-taxel voltage against silicone thickness and force,
PZT and PVDF, plane stress) on fewer points; ``taxel study run fig-2-5`` runs the
whole of it.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import taxel

folder = Path(tempfile.mkdtemp(prefix="taxel-study-"))
(folder / "fig-2-5-small.toml").write_text('''
description = "Fig. 2.5, small: pressed-taxel voltage vs silicone thickness"
base = "thesis-pzt-single-2d"
outputs = ["voltage", "short_circuit_charge", "max_strain"]

[overrides]
"model.type" = "plane_stress"

[[parameters]]
path = "array"
label = "piezo"
values = [{piezo = "PSI-5H4E", piezo_thickness = "0.127 mm"}, {piezo = "PVDF", piezo_thickness = "52 um"}]
labels = ["PZT", "PVDF"]

[[parameters]]
path = ["array.silicone_above", "array.silicone_below"]
label = "silicone_thickness"
start = "0.5 mm"
stop = "3 mm"
step = "0.5 mm"
''')
run = taxel.run_study(folder / "fig-2-5-small.toml", folder / "out", workers=1, progress=False)
print(f"{run.total} points, {run.done} solved, {run.failed} failed, {run.seconds:.1f} s")
print(run.rows[0])  # one tidy row: the parameters as given, the outputs in SI

# %%
fig, ax = plt.subplots(figsize=(7, 3.5))
for piezo in ("PZT", "PVDF"):
    rows = sorted((r for r in run.rows if r["piezo"] == piezo), key=lambda r: float(r["silicone_thickness"].split()[0]))
    ax.plot([float(r["silicone_thickness"].split()[0]) for r in rows], [abs(r["pressed_voltage"]) for r in rows], "o-",
            label=piezo)
ax.set(xlabel="silicone above and below (mm)", ylabel="|pressed-taxel voltage| (V) at 1 N", yscale="log",
       title="Fig. 2.5 (small): plane stress")
ax.legend()
fig.tight_layout()
