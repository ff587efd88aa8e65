"""Influence functions of a press position, from static FEM solves, cached.

The 2D scene is the section through the middle row. A flat indenter as wide as a
taxel (radius = taxel_width / 2; at zero offset it is the scene's "taxel" load)
pressed at x (measured from the row's first taxel centre) gives the open-circuit
voltage of every taxel of the row; G_c(x) = V_c(x) / V_c(x_c) is taxel c's
influence function, 1 at its own centre x_c = c * pitch (it changes sign between
taxels: a press in a gap lifts both neighbours). Between samples G is a cubic
spline (scipy.interpolate.CubicSpline). As in taxel.analyses.solves.crosstalk, the
square array's two directions are taken alike and separable: a press at (x, y)
reaches taxel (r, c) as G_r(y) G_c(x).

Samples: every pitch / `per_pitch` over the taxels, x in [0, (cols - 1) pitch];
with `edges`, also every pitch / per_pitch beyond the outer taxels as far as the
indenter's centre stays over the sensor's margin. The row is mirror-symmetric
about its middle (equal margins, identical taxels), so V_c(x) = V_(cols-1-c)(L - x)
with L = (cols - 1) pitch: only the samples with x <= L / 2 are solved and the
rest mirrored (benchmarks/measure_influence_cost.py checks the mirror against
direct solves, and the interpolation error of per_pitch 2 and 4 against 8).
per_pitch 8 (the default): the slopes of G, which the position estimate and its
Cramer-Rao bound live on, change fast at the taxels' edges, and a spline through
every pitch / 4 puts the bound of taxel.analyses.surface.localization 0.7-9 x off (pitch / 8
within 0.2 % of every-position solves at pitch / 8; the benchmark). Solves for a
3-taxel row at per_pitch 8: 12 with edges (23 samples), 9 without (17).

`solve(scene) -> {electrode name: V}` does each static solve: by default
solve_static; the optimizer passes one backed by its study store, so every press
position of every design is a cached study point. The result is also cached in
~/.cache/taxel (or $XDG_CACHE_HOME/taxel), keyed by the scene's SHA-256 and the
sampling.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.interpolate import CubicSpline

from taxel.scene import Scene
from taxel.analyses.solves.crosstalk import cache_dir
from taxel.schema import electrode_name

Solve = Callable[[Scene], dict]


@dataclass
class Influence:
    pitch: float                 # m, centre to centre
    x: np.ndarray                # (m,) m sample positions
    G: np.ndarray                # (m, cols) G_c at the samples
    solves: int = 0              # static solves it took (0: read from the cache)
    sensitivity: np.ndarray | None = None   # (cols,) V/N: each taxel's open-circuit voltage pressed at its centre

    def __post_init__(self):
        self._spline = CubicSpline(self.x, self.G, axis=0)

    @property
    def n(self) -> int:
        return self.G.shape[1]

    def at(self, x) -> np.ndarray:
        """G_c(x), x clipped to the sampled span: (cols,) for a scalar x, (len(x), cols) for an array."""
        return self._spline(np.clip(x, self.x[0], self.x[-1]))

    def weights(self, xy, taxels: list[tuple[int, int]]) -> np.ndarray:
        """The weight G_r(y) G_c(x) of a press at xy = (x, y) (m) on each taxel (row, col)."""
        gx, gy = self.at(xy[0]), self.at(xy[1])
        return np.array([gy[r] * gx[c] if r < self.n and c < self.n else 0.0 for r, c in taxels])

    def record(self) -> dict:
        return {"pitch_m": self.pitch, "x_m": self.x.tolist(), "G": self.G.tolist(),
                "sensitivity_V_per_N": None if self.sensitivity is None else self.sensitivity.tolist()}


def samples(scene: Scene, per_pitch: int = 8, edges: bool = True) -> np.ndarray:
    """The sample positions (m) of the module docstring."""
    arr = scene.array
    pitch = arr.pitch
    h = pitch / per_pitch
    k = int(np.floor(arr.margin / h + 1e-9)) if edges else 0       # the indenter's centre stays over the margin
    return np.arange(-k, per_pitch * (arr.cols - 1) + k + 1) * h


def _static_voltages(scene: Scene) -> dict:
    from taxel.analyses.solves.analysis import solve_static
    return solve_static(scene).voltages()


def influence(scene: Scene, per_pitch: int = 8, edges: bool = True, solve: Solve | None = None) -> Influence:
    """The scene's influence functions (module docstring), cached."""
    arr = scene.array
    if arr is None:
        raise ValueError("influence functions need a taxel-array scene ([array])")
    pitch = arr.pitch
    tag = f"influence-{per_pitch}-{int(edges)}"
    key = hashlib.sha256((tag + scene.model_dump_json()).encode()).hexdigest()[:16]
    path = cache_dir() / f"{tag}-{key}.json"
    try:
        d = json.loads(path.read_text())
        S = d.get("sensitivity_V_per_N")
        return Influence(d["pitch_m"], np.array(d["x_m"]), np.array(d["G"]), 0, None if S is None else np.array(S))
    except (OSError, ValueError, KeyError):
        pass
    solve = solve or _static_voltages
    row, n = arr.rows // 2, arr.cols
    xs = samples(scene, per_pitch, edges)
    L = (n - 1) * pitch
    V = np.full((len(xs), n), np.nan)
    count = 0
    for i, x in enumerate(xs):
        mirror = int(np.argmin(np.abs(xs - (L - x))))
        if x > L / 2 + 1e-12 and abs(xs[mirror] - (L - x)) < 1e-12 * max(pitch, 1.0):
            V[i] = V[mirror][::-1]                     # solved already (x <= L/2 come first)
            continue
        c = int(np.clip(np.round(x / pitch), 0, n - 1))
        s = scene.replace(**{"load.kind": "probe", "load.taxel": [row, c], "load.radius": arr.taxel_width / 2,
                             "load.offset": [float(x - c * pitch), 0.0], "load.profile": "flat"})
        v = solve(s)
        V[i] = [v[electrode_name(row, k)] for k in range(n)]
        count += 1
    centre = [int(np.argmin(np.abs(xs - c * pitch))) for c in range(n)]
    G = V / V[centre, np.arange(n)][None, :]
    out = Influence(pitch, xs, G, count, V[centre, np.arange(n)] / float(scene.load.force or 1.0))
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps({"scene_sha256": key, **out.record()}))
    except OSError:
        pass
    return out
