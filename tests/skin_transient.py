"""The skin runtime and the FEM transient of one press, side by side (tests/test_skin_fem.py,
benchmarks/skin_accuracy.py): a taxel-wide flat probe of 1 N on the middle row at x, with
the load history `history` of the scene's [analysis] (its keys in `histories`)."""

import numpy as np

import taxel
from taxel.schema import electrode_name
from taxel.skin.runtime import SkinRuntime

# the thesis PZT 3 x 3 array's 2D section on a coarse mesh, read through 500 Mohm
COARSE = {"readout.circuit": "resistor", "mesh.size": "1 mm", "mesh.piezo_size": "0.2 mm"}


def fem_and_runtime(scene, sk, x: float, history: str, histories: dict) -> tuple[np.ndarray, np.ndarray]:
    """(runtime, FEM) voltages of the middle row's three taxels, (steps, 3) each, for the
    press at x (m from the first column's centre) with the skin `sk` at its dt."""
    p, w = sk.pitch, sk.taxel_width
    c = int(round(x / p))
    s = scene.replace(**{"load.kind": "probe", "load.taxel": [1, c], "load.radius": w / 2,
                         "load.offset": [x - c * p, 0.0], "load.profile": "flat", "load.force": 1.0,
                         "analysis.type": "transient", "analysis.input": history, "analysis.dt": sk.dt,
                         **histories[history]})
    tr = taxel.solve(s)
    V = np.array(tr.output)[:, [tr.names.index(electrode_name(1, k)) for k in range(3)]]
    v = SkinRuntime(sk).run(np.tile([[x, p]], (len(tr.t), 1, 1)), tr.force[:, None])[:, 1, :]
    return v, V
