"""Crosstalk weights of a press on each taxel, from static FEM solves, cached.

The 2D scene (`thesis-pzt-3x3-2d` or any 2D array scene) is the section through
the pressed row: pressing taxel (row, c) for each column c gives the open-circuit
voltage of every taxel in that row, and W1[c, c'] = V(c') / V(c) (1 on the
diagonal; about -0.075 for a neighbour in the thesis sensor). A press at
(pr, pc) reaches taxel (r, c) with weight W1[pr, r] * W1[pc, c]: the square
array's two directions taken alike and separable (an approximation: a 3D solve
per press position would remove it, at minutes rather than a second).
Cached in ~/.cache/taxel (or $XDG_CACHE_HOME/taxel), keyed by the scene's SHA-256.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import numpy as np

from taxel.scene import Scene
from taxel.schema import electrode_name


def cache_dir() -> Path:
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "taxel"


def profile(scene: Scene) -> np.ndarray:
    """W1 (cols, cols): voltage on each taxel of the row per voltage on the pressed one."""
    from taxel.analyses.solves.analysis import solve_static
    arr = scene.array
    if arr is None or arr.cols == 1:
        return np.ones((1, 1))
    key = hashlib.sha256(scene.model_dump_json().encode()).hexdigest()[:16]
    path = cache_dir() / f"crosstalk-{key}.json"
    try:
        return np.array(json.loads(path.read_text())["W1"])
    except (OSError, ValueError, KeyError):
        pass
    row = arr.rows // 2
    W1 = np.zeros((arr.cols, arr.cols))
    for c in range(arr.cols):
        v = solve_static(scene.replace(**{"load.kind": "taxel", "load.taxel": [row, c]})).voltages()
        W1[c] = [v[electrode_name(row, k)] / v[electrode_name(row, c)] for k in range(arr.cols)]
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps({"scene_sha256": key, "W1": W1.tolist()}))
    except OSError:
        pass
    return W1


def weights(W1: np.ndarray, press: tuple[int, int], taxels: list[tuple[int, int]]) -> np.ndarray:
    """The weight of a press at `press` on each of `taxels` (row, col)."""
    n = len(W1)

    def w(a, b):
        return W1[a, b] if a < n and b < n else 0.0
    return np.array([w(press[0], r) * w(press[1], c) for r, c in taxels])
