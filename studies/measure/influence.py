"""Influence functions of a press position, from static FEM solves, cached.

The 2D scene is the section through the middle row. A flat indenter as wide as a
taxel (radius = taxel_width / 2; at zero offset it is the scene's "taxel" load)
pressed at x (measured from the row's first taxel centre, every pitch / 4 from
half a pitch before the first taxel to half a pitch after the last, as far as
the indenter stays on the sensor) gives the
open-circuit voltage of every taxel of the row; G_c(x) = V_c(x) / V_c(x_c) is
taxel c's influence function, 1 at its own centre x_c = c * pitch (it changes
sign between taxels: a press in a gap lifts both neighbours). Between samples G is
a cubic spline (scipy.interpolate.CubicSpline). As in studies.measure.crosstalk,
the square array's two directions are taken alike and separable: a press at
(x, y) reaches taxel (r, c) as G_r(y) G_c(x).
Cached in ~/.cache/taxel (or $XDG_CACHE_HOME/taxel), keyed by the scene's SHA-256.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from taxel.scene import Scene
from taxel.studies.measure.crosstalk import cache_dir


@dataclass
class Influence:
    pitch: float                 # m, centre to centre
    x: np.ndarray                # (m,) m sample positions
    G: np.ndarray                # (m, cols) G_c at the samples

    def __post_init__(self):
        self._splines = [CubicSpline(self.x, self.G[:, c]) for c in range(self.G.shape[1])]

    @property
    def n(self) -> int:
        return self.G.shape[1]

    def at(self, x: float) -> np.ndarray:
        """(cols,) G_c(x), x clipped to the sampled span."""
        x = float(np.clip(x, self.x[0], self.x[-1]))
        return np.array([s(x) for s in self._splines])

    def record(self) -> dict:
        return {"pitch_m": self.pitch, "x_m": self.x.tolist(), "G": self.G.tolist()}


def influence(scene: Scene) -> Influence:
    """The scene's influence functions (module docstring); up to 4 (cols - 1) + 5 static solves, cached."""
    from taxel.analyses import solve_static
    arr = scene.array
    if arr is None:
        raise ValueError("influence functions need a taxel-array scene ([array])")
    pitch = arr.taxel_width + arr.gap
    key = hashlib.sha256(("influence" + scene.model_dump_json()).encode()).hexdigest()[:16]
    path = cache_dir() / f"influence-{key}.json"
    try:
        d = json.loads(path.read_text())
        return Influence(d["pitch_m"], np.array(d["x_m"]), np.array(d["G"]))
    except (OSError, ValueError, KeyError):
        pass
    row = arr.rows // 2
    xs = np.arange(-2, 4 * (arr.cols - 1) + 3) * pitch / 4
    span = arr.margin + arr.taxel_width / 2 - arr.taxel_width / 2       # the indenter stays on the sensor
    xs = xs[(xs >= -span - 1e-12) & (xs <= (arr.cols - 1) * pitch + span + 1e-12)]
    V = np.zeros((len(xs), arr.cols))
    for i, x in enumerate(xs):
        c = int(np.clip(np.round(x / pitch), 0, arr.cols - 1))
        s = scene.replace(**{"load.kind": "indenter", "load.taxel": [row, c], "load.radius": arr.taxel_width / 2,
                             "load.offset": [float(x - c * pitch), 0.0], "load.profile": "flat"})
        v = solve_static(s).voltages()
        V[i] = [v[f"taxel_{row}_{k}"] for k in range(arr.cols)]
    centre = [int(np.argmin(np.abs(xs - c * pitch))) for c in range(arr.cols)]
    G = V / V[centre, np.arange(arr.cols)][None, :]
    out = Influence(pitch, xs, G)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps({"scene_sha256": key, **out.record()}))
    except OSError:
        pass
    return out
