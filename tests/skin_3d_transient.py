"""The 3D skin against the 3D FEM's own dynamics at off-centre presses (tests/test_skin_3d_transient.py,
benchmarks/skin_3d_transient.py).

A linear 3D transient through a readout is the static surface map times the circuit's
dynamics when the mechanics is quasi-static (the pad's first resonance far above the
band): the skin's factoring. The independent reference is the 3D model's own dynamics,
not the map and not the 2D section: the Krylov-reduced 3D model (fem.dynamics.build:
its basis moment-matched to direct 3D frequency solves within 1e-4 at its check
frequencies, the causal loss law kept) of the whole 2 x 2 array with every electrode
on the scene's resistor, driven by 1 N pressing on the top-surface nodes within
RADIUS of each press point (one column per point, one reduced model for all), its
state space simulated by first-order hold (exact for the piecewise-linear histories,
as the skin's own discretization). The skin: the 3D surface map's W (non-separable)
times h of the 2D section's reduced model (taxel.skin.build), the same nodal forces as
its contacts. Consistent-mesh: the map and the reference on the scene's mesh (a
coarse one: the 2 mm / 0.8 mm reduction passed 3 GB).
"""

import numpy as np

from taxel.analyses.model.problem import problem, readout
from taxel.analyses.solves.dynamic import force_history
from taxel.fem import dynamics
from taxel.schema import electrode_name
from taxel.skin.runtime import SkinRuntime

SMALL = {"array.rows": 2, "array.cols": 2, "readout.circuit": "resistor", "load.taxel": [1, 1],
         "mesh.size": "3 mm", "mesh.piezo_size": "1.2 mm", "model.symmetry": "full"}
RADIUS = 1.6e-3                    # m: the nodes carrying each press (tests/skin_3d_loads.py's)
# the press centres in the skin frame (p the pitch, w the taxel width): tests/skin_3d_loads.POINTS
POINTS = {"diagonal": lambda p, w: (0.25 * p, 0.25 * p), "gap": lambda p, w: (0.5 * p, 0.0),
          "edge": lambda p, w: (-(w / 2 + 1.5e-3), 0.0)}
CENTRE = (0.0, 0.0)                # taxel (0, 0)'s centre, the nearest taxel of every point: the pressed taxel's peak
HISTORIES = {"step": {"analysis.duration": 0.2, "analysis.rise": 0.005},
             "impulse": {"analysis.duration": 0.1, "analysis.width": 0.01},
             "chirp": {"analysis.duration": 0.5, "analysis.f0": 0.0, "analysis.f1": 100.0}}


class Reference:
    """The reduced 3D model of the scene's array pressed at `centres` (skin frame, m)."""

    def __init__(self, scene, sk, centres: dict, f_max: float = 2000.0):
        s = scene.replace(**{"model.symmetry": "full", "load.kind": "pressure", "load.pressure": 1.0,
                             "model.silicone": "linear"})
        self.scene, self.sk = s, sk
        dm = dynamics.model(problem(s))
        sy = dm.sy
        ub = next(iter(sy.ubases.values()))
        top = np.unique(sy.tm.mesh.facets[:, sy.tm.facets["top"]])
        xy = sy.tm.mesh.p[:2, top].T
        shift = np.array([(sk.cols - 1) * sk.pitch / 2, (sk.rows - 1) * sk.pitch / 2])   # map frame -> skin frame
        self.points, cols = {}, []
        for name, c in centres.items():
            nodes = top[np.hypot(*(xy - (np.asarray(c) - shift)).T) <= RADIUS]
            F = np.zeros(sy.A.shape[0])
            F[ub.nodal_dofs[2, nodes]] = -1.0 / len(nodes)                  # 1 N pressing (-z)
            cols.append(dm.red.P.T @ F)
            self.points[name] = sy.tm.mesh.p[:2, nodes].T + shift
        self.names = list(centres)
        self.red = dynamics.build(dm, np.column_stack(cols), f_max, max(s.analysis.f_min, 0.1), 1e-4)
        self.ss = dynamics.realize(self.red, readout(s), (max(s.analysis.f_min, 0.1), f_max))
        self.order = [self.red.names.index(electrode_name(sk.rows - 1 - r, k))
                      for r in range(sk.rows) for k in range(sk.cols)]
        self.unknowns = int(dm.M.shape[0])

    def first_resonance(self) -> float:
        """Hz: the lowest oscillatory pole of the realization (the pad's first resonance)."""
        lam = np.linalg.eigvals(self.ss.A)
        osc = lam[np.abs(lam.imag) > 0.05 * np.abs(lam)]
        return float(np.abs(osc).min() / (2 * np.pi)) if len(osc) else float("inf")

    def compare(self, where: str, history: str) -> dict:
        """Skin runtime and reduced 3D model, every taxel (skin order), the same force history."""
        sk = self.sk
        a = self.scene.replace(**{"analysis.type": "transient", "analysis.input": history, "analysis.dt": sk.dt,
                                  **HISTORIES[history]}).analysis
        t, F = force_history(a, 1.0)
        u = np.zeros((len(t), len(self.names)))
        u[:, self.names.index(where)] = F
        V = self.ss.simulate(t, u)[:, self.order]
        pts = self.points[where]
        f = np.repeat(F[:, None] / len(pts), len(pts), axis=1)
        v = SkinRuntime(sk).run(np.broadcast_to(pts, (len(t), *pts.shape)), f).reshape(len(t), -1)
        return {"t": t, "skin": v, "fem": V}


def centres(p: float, w: float) -> dict:
    """The reference's press points (skin frame, m) for pitch p, taxel width w: POINTS and the centre press."""
    return {**{k: f(p, w) for k, f in POINTS.items()}, "centre": CENTRE}


def errors(r: dict, peak: float | None = None) -> dict:
    """max |skin - 3D| of the pressed taxel's peak (`peak`: the largest |v_3D| of the same history
    pressed by the same nodes on the nearest taxel's centre; else this press's own largest |v_3D|),
    that peak, this press's own peak, and whether every taxel above 1 % of the pressed peak has
    the 3D model's sign at its own peak."""
    v, V = r["skin"], r["fem"]
    own = float(np.abs(V).max())
    peak = own if peak is None else float(peak)
    at = np.argmax(np.abs(V), axis=0)
    cols = np.arange(V.shape[1])
    big = np.abs(V[at, cols]) > 0.01 * peak
    return {"error": float(np.abs(v - V).max() / peak), "peak": peak, "own_peak": own,
            "error_of_own_peak": float(np.abs(v - V).max() / own),
            "signs": bool(np.all((np.sign(v[at, cols]) == np.sign(V[at, cols]))[big])),
            "fem_at_peaks": V[at, cols].tolist(), "skin_at_peaks": v[at, cols].tolist()}
