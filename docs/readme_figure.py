"""The landing picture (docs/thesis-pzt-3x3-2d.png, on the front page and the docs index):
the thesis PZT 3x3 array in 2D, 1 N on the middle taxel,
deformed cross-section coloured by the potential, and the vertical displacement.

Run: python docs/readme_figure.py   (writes docs/thesis-pzt-3x3-2d.png and prints the numbers)
"""

from pathlib import Path

import taxel
from taxel.analyses.results.figures import cross_section

result = taxel.solve("thesis-pzt-3x3-2d")
cross_section(result, Path(__file__).parent / "thesis-pzt-3x3-2d.png")
v = result.voltages()
print({k: f"{x * 1e3:.1f} mV" for k, x in v.items()}, f"crosstalk {100 * result.crosstalk:.2f} %",
      f"largest silicone strain {100 * result.max_strain:.0f} %")
