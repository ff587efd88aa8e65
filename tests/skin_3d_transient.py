"""The 3D skin against the 3D FEM's own dynamics at off-centre presses (tests/test_skin_3d.py's
transient check, benchmarks/skin_3d_transient.py).

A linear 3D transient through a readout is the static surface map times the circuit's
dynamics when the mechanics is quasi-static (the pad's first resonance far above the
band), which is the skin's factoring; the independent reference is the 3D model's own
dynamics: the Krylov-reduced 3D model of the same scene pressed by the same probe
(taxel.analyses.solves.reduced.reduce, inputs = 'probe': its basis moment-matched to
direct 3D solves within 1e-4 at its check frequencies; its state space simulated by
first-order hold, exact for the piecewise-linear histories, as the skin's own). The
skin: the 3D surface map's W (non-separable) times h from the 2D section's reduced
model (taxel.skin.build), the probe's uniform pressure as point forces at the
footprint's quadrature points (`footprint`).
"""

import numpy as np

from taxel.analyses.solves.dynamic import force_history
from taxel.analyses.solves.reduced import reduce
from taxel.schema import electrode_name
from taxel.skin.runtime import SkinRuntime

# a 2 x 2 PZT array on a coarse 3D mesh (2 mm / 0.8 mm: the check is consistent-mesh, the map, the skin and
# the reference on the same mesh), read through the scene's resistor on every electrode
SMALL = {"array.rows": 2, "array.cols": 2, "readout.circuit": "resistor", "load.taxel": [1, 1],
         "mesh.size": "2 mm", "mesh.piezo_size": "0.8 mm"}
PROBE = 1e-3                       # m: the probe's radius (a flat, uniform pressure)
# the press centres in the skin frame (p the pitch, w the taxel width): tests/skin_3d_loads.POINTS
POINTS = {"diagonal": lambda p, w: (0.25 * p, 0.25 * p), "gap": lambda p, w: (0.5 * p, 0.0),
          "edge": lambda p, w: (-(w / 2 + 1.5e-3), 0.0)}
HISTORIES = {"step": {"analysis.duration": 0.2, "analysis.rise": 0.005},
             "impulse": {"analysis.duration": 0.1, "analysis.width": 0.01},
             "chirp": {"analysis.duration": 0.5, "analysis.f0": 0.0, "analysis.f1": 100.0}}


def footprint(c, radius: float = PROBE, rings: int = 4, per_ring: int = 12):
    """(points (k, 2), weights (k,)) of a uniform pressure of 1 N over a disc about c:
    midpoint rings in r, equal sectors in angle (the weights are the cells' areas)."""
    r_edges = np.linspace(0.0, radius, rings + 1)
    pts, wts = [], []
    for r0, r1 in zip(r_edges[:-1], r_edges[1:]):
        n = 1 if r0 == 0 and rings > 1 and False else per_ring
        th = (np.arange(n) + 0.5) * 2 * np.pi / n
        rm = 0.5 * (r0 + r1)
        pts.append(np.stack([c[0] + rm * np.cos(th), c[1] + rm * np.sin(th)], axis=1))
        wts.append(np.full(n, (r1 ** 2 - r0 ** 2) / radius ** 2 / n))
    return np.concatenate(pts), np.concatenate(wts)


def scene_at(scene, sk, c):
    """The scene pressed by the flat probe centred at c (skin frame)."""
    p, rows = sk.pitch, sk.rows
    col = int(np.clip(np.round(c[0] / p), 0, sk.cols - 1))
    r_skin = int(np.clip(np.round(c[1] / p), 0, rows - 1))
    return scene.replace(**{"load.kind": "probe", "load.taxel": [rows - 1 - r_skin, col], "load.radius": PROBE,
                            "load.offset": [float(c[0] - col * p), float(c[1] - r_skin * p)],
                            "load.profile": "flat", "load.force": 1.0})


def reference(scene, sk, c):
    """The reduced 3D model of the press at c (readout voltages of every taxel per newton)."""
    return reduce(scene_at(scene, sk, c), inputs="probe")


def first_resonance(rm) -> float:
    """Hz: the lowest oscillatory pole of the reduced 3D model's realization (the pad's first resonance)."""
    lam = np.linalg.eigvals(rm.state_space().A)
    osc = lam[np.abs(lam.imag) > 0.05 * np.abs(lam)]
    return float(np.abs(osc).min() / (2 * np.pi)) if len(osc) else float("inf")


def compare(scene, sk, rm, c, history: str) -> dict:
    """Skin runtime and reduced 3D model, every taxel (skin order), the same force history."""
    a = scene.replace(**{"analysis.type": "transient", "analysis.input": history, "analysis.dt": sk.dt,
                         **HISTORIES[history]}).analysis
    t, F = force_history(a, 1.0)
    names = [n.split(":", 1)[1] for n in rm.output_names]
    order = [names.index(electrode_name(sk.rows - 1 - r, k)) for r in range(sk.rows) for k in range(sk.cols)]
    V = rm.simulate(t, F[:, None])[:, order]
    pts, w = footprint(c)
    v = SkinRuntime(sk).run(np.broadcast_to(pts, (len(t), *pts.shape)), F[:, None] * w[None, :]).reshape(len(t), -1)
    return {"t": t, "skin": v, "fem": V}
