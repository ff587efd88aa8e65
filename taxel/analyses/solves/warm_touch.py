r"""A warm finger on the skin: the heat through the silicone, the films' pyroelectric
charge, and what the scene's readout makes of it beside a press.

scene -> its mesh (the mechanics' own, tagged) with each region's conductivity and heat
capacity (fem.constitution; a user material gives `conductivity` and `specific_heat`) ->
the transient conduction (fem.thermal, Crank-Nicolson): the finger at
`warm_touch.finger` on the load's footprint through `contact_conductance` for
`duration`, the rest of the surface (the footprint after the lift) convective to
`ambient` -> each taxel's pyroelectric short-circuit charge (fem.thermal.pyro_charge,
exact for a thin film) -> the readout chain in time (fem.readout.in_time: the same
circuits as the static and transient analyses), on a grid fine enough for the press's
rise.

The press beside it: the static solve's short-circuit charge per newton of every taxel
(`solve_static`: linear, Yeoh or a contact press, as the scene says), times the scene's
force held for the same `duration` (ramped over `analysis.rise` at both ends): a
quasi-static charge source (the thermal and press signals are far below the first
resonance), capacitance C_p = |Q_sc / V_oc| of the pressed taxel for every taxel.

    warm touch      the output of the pyroelectric charge alone;
    warm press      the heat and the force together (charges add: one-way, linear);
    false force     F_false = max_t |y_touch| / max_t |y_press| x F: the press held as long
                    that gives the same peak output (y_press is linear in F);
    ratio           F_false over the chain's minimum detectable force (the static solve's
                    noise budget, taxel.analyses.solves.quasi_static_noise): <= 1, a warm
                    finger does not fake a press the readout could see.

The sensitivity drift: the piezo's temperature coefficients (fem.constitution: permittivity_tc
of eps33^T, d_tc of the d constants; linear about the skin's `ambient`) over DRIFT_RANGE_K,
0 to 50 C: the capacitance changes by permittivity_tc (T - ambient), the short-circuit charge
per newton (the charge amplifier's sensitivity) by d_tc (T - ambient), the open-circuit
sensitivity by their ratio; a coefficient no datasheet gives is None, "no drift data"
(never zero).

Assumptions: fem.thermal's (one-way coupling; free film, datasheet constant-stress p3;
the silicone's thermal stress neglected); the finger a body at a fixed temperature behind
a contact conductance (not its own transient); no heat from the press itself.
"""

from __future__ import annotations

import json
import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from taxel.analyses.model.problem import check, mesh, readout, solve_model
from taxel.analyses.results.static import DRIFT_RANGE_K, drift_words  # noqa: F401  (drift_words: its words)
from taxel.fem import constitution, thermal
from taxel.fem import readout as circuits
from taxel.scene import Scene, SceneError
from taxel.schema import electrode_name
from taxel.scene_tables import WarmTouchTable

__all__ = ["FILE", "WarmTouchResult", "warm_touch", "thermal_model", "surfaces", "drift", "drift_words"]

FILE = "warm-touch.json"      # a warm touch's record in a result folder (WarmTouchResult.write)


@dataclass
class WarmTouchResult:
    """A warm touch and a warm press of a scene, per taxel electrode (SI: s, K, C, V, N)."""

    scene: Scene
    pressed: str
    force: float                       # N, the press beside the touch
    t: np.ndarray                      # s, the readout's grid
    film_temperature: dict             # electrode -> (nt,) K, the film's mean temperature
    pyro_charge: dict                  # electrode -> (nt,) C
    touch: dict                        # electrode -> (nt,) output of the warm touch alone
    press: dict                        # the press alone
    warm_press: dict                   # both
    label: str                         # what the chain outputs
    false_force: float                 # N
    min_detectable_force: float | None
    field_time: float                  # s, the time of the stored field (the touch's end)
    points: np.ndarray = field(repr=False)       # (dim, nv) the mesh's vertices
    cells: np.ndarray = field(repr=False)        # (nodes per element, ne) its elements
    temperature: np.ndarray = field(repr=False)  # (nv,) K at field_time, at the vertices
    timings: dict = field(default_factory=dict)
    drift: dict = field(default_factory=dict)   # the piezo's sensitivity drift (drift(), below)

    @property
    def ratio(self) -> float | None:
        """The false force over the minimum detectable force."""
        mdf = self.min_detectable_force
        return self.false_force / mdf if mdf else None

    @property
    def touch_peak_time(self) -> float:
        """s: when the pressed taxel's warm-touch output peaks."""
        return float(self.t[np.argmax(np.abs(self.touch[self.pressed]))])

    @property
    def peak_at_end(self) -> bool:
        """The touch's output peaks in the last 5 % of the simulated time: the heat has not
        reached the film yet (thick silicone), and the false force is a lower bound; make
        warm_touch.time longer."""
        return bool(self.touch_peak_time >= 0.95 * self.t[-1])

    def summary(self) -> dict:
        """The numbers, JSON-ready."""
        p, T = self.pressed, self.film_temperature[self.pressed]
        dTdt = np.gradient(T, self.t)
        w = self.scene.warm_touch or WarmTouchTable()
        return {"pressed": p, "force_N": self.force, "readout": self.label,
                "finger_K": w.finger, "ambient_K": w.ambient, "duration_s": w.duration,
                "film_rise_K": float(T.max() - T[0]), "film_max_rate_K_per_s": float(np.abs(dTdt).max()),
                "pyro_charge_C": float(self.pyro_charge[p][np.argmax(abs(self.pyro_charge[p]))]),
                "touch_peak": float(np.abs(self.touch[p]).max()), "press_peak": float(np.abs(self.press[p]).max()),
                "warm_press_peak": float(np.abs(self.warm_press[p]).max()),
                "touch_peak_time_s": self.touch_peak_time, "peak_at_end": self.peak_at_end,
                "false_force_N": self.false_force, "min_detectable_force_N": self.min_detectable_force,
                "ratio": self.ratio, "timings_s": self.timings, "drift": self.drift}


    def write(self, folder, points: int = 600) -> Path:
        """FILE in `folder`: the summary, the pressed taxel's traces (`points` samples) and,
        for a 2D or axisymmetric model, the temperature field at the touch's end (the
        report's section, reports.warm_touch, draws them; no solve there)."""
        p = self.pressed
        w = self.scene.warm_touch or WarmTouchTable()
        near = ((self.t <= 0.03) | ((self.t >= w.duration) & (self.t <= w.duration + 0.03)))   # the press's spikes
        k = np.unique(np.r_[np.linspace(0, len(self.t) - 1, points).round().astype(int), np.flatnonzero(near)])
        two_d = self.points.shape[0] == 2
        rec = {**self.summary(), "scene": self.scene.name, "model": self.scene.model.type,
               "t_s": self.t[k].tolist(), "film_temperature_K": self.film_temperature[p][k].tolist(),
               "touch": self.touch[p][k].tolist(), "press": self.press[p][k].tolist(),
               "warm_press": self.warm_press[p][k].tolist(), "field_time_s": self.field_time,
               "field": None if not two_d else {"points_m": self.points.tolist(), "triangles": self.cells[:3].T.tolist(),
                                                "temperature_K": self.temperature.tolist()}}
        path = Path(folder) / FILE
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(rec))
        return path


def thermal_model(scene: Scene, tm=None):
    """(ThermalModel, tagged mesh) of the scene's mesh with its materials' heat."""
    mats = check(scene)
    tm = tm or mesh(scene)
    heat = {}
    for region, (name, _) in tm.materials.items():
        m = mats[name]
        if m.conductivity is None or m.specific_heat is None:
            raise SceneError(f"materials.{name}: no thermal properties for a warm touch; add conductivity "
                             f"(e.g. \"0.2 W/(m*K)\") and specific_heat (e.g. \"1200 J/(kg*K)\")")
        heat[region] = thermal.Heat(m.conductivity, m.rho * m.specific_heat)
    kin = constitution.kinematics(tm.layout.model, tm.layout.depth)
    return thermal.ThermalModel(tm.mesh, tm.regions, heat, kin, scene.mesh.order), tm


def surfaces(tm, w: WarmTouchTable) -> list:
    """The finger on the load's footprint (top facets whose centre is in it) while it stays,
    the air on every other outer facet (and on the footprint after the lift); the axis and
    mirror planes carry no flux."""
    m, lay = tm.mesh, tm.layout
    top = np.asarray(tm.facets["top"])
    centre = m.p[:, m.facets[:, top]].mean(axis=1)
    inside = np.ones(len(top), bool) if lay.load is None else \
        np.array([lay.load.contains(*c[:-1]) if lay.dim == 3 else lay.load.contains(c[0]) for c in centre.T])
    touch = top[inside]
    if not len(touch):
        raise SceneError("warm_touch: the load's footprint holds no facet of the top surface; make load.radius "
                         "larger than the mesh size")
    no_flux = set().union(*(set(tm.facets[k]) for k in ("axis", "mirror_x", "mirror_y") if k in tm.facets))
    air = np.array(sorted(set(m.boundary_facets()) - set(touch) - no_flux), int)
    on = (lambda t: t < w.duration)
    return [thermal.Surface(touch, w.contact_conductance, lambda t: w.finger, on),
            thermal.Surface(touch, w.convection, lambda t: w.ambient, lambda t: not on(t)),
            thermal.Surface(air, w.convection, lambda t: w.ambient)]


def warm_touch(scene: Scene, static=None, rig=None) -> WarmTouchResult:
    """The warm touch and the warm press of an array scene (`static`: its static solve, if
    done; `rig`: a bench rig whose converter and band the minimum detectable force takes)."""
    import time
    if scene.array is None:
        raise SceneError("warm_touch needs an [array] scene (taxels with their films)")
    w = scene.warm_touch or WarmTouchTable()
    t0 = time.perf_counter()
    therm_scene = scene if scene.model.type != "3d" else scene.replace(**{"model.symmetry": "full"})
    model, tm = thermal_model(therm_scene)
    t_th = np.linspace(0.0, w.time, int(round(w.time / w.dt)) + 1)
    cond = thermal.conduct(model, t_th, surfaces(tm, w), w.ambient, theta=0.5)
    t1 = time.perf_counter()
    a = scene.array
    films = {electrode_name(*map(int, r.split("_")[1:3])): thermal.Film(tm.regions[r], check(scene)[name].pyro, s,
                                                                         a.piezo_thickness)
             for r, (name, s) in tm.materials.items() if r.startswith("piezo_")}
    pyro = {e: thermal.pyro_charge(cond, f) for e, f in films.items()}
    film_T = {e: thermal.mean_temperature(cond, f.cells) for e, f in films.items()}
    static = static or solve_model(scene)
    t2 = time.perf_counter()
    taxels = {k: e for k, e in static.electrodes.items() if e.state != "reference" and k in pyro}
    pressed = static.pressed if static.pressed in taxels else next(iter(taxels))
    force = abs(static.applied_force) or 1.0
    q_per_n = {k: e.short_circuit_charge / force for k, e in taxels.items()}
    v_per_n = taxels[pressed].voltage / force
    C_p = abs(q_per_n[pressed] / v_per_n) if v_per_n else None
    if not C_p:
        raise SceneError("warm_touch: the pressed taxel has no voltage or charge under the scene's load")
    rise = scene.analysis.rise
    t = np.arange(0.0, w.time + 1e-12, min(w.dt, rise / 4))
    F = force * (_ramp(t, rise) - _ramp(t - w.duration, rise))
    names = list(taxels)
    Q_touch = np.column_stack([np.interp(t, t_th, pyro[k]) for k in names])
    Q_press = np.column_stack([q_per_n[k] * F for k in names])
    r = readout(scene)
    y = {what: circuits.in_time(t, Q, np.full(len(names), C_p), r)
         for what, Q in (("touch", Q_touch), ("press", Q_press), ("warm_press", Q_touch + Q_press))}
    k = names.index(pressed)
    false_force = float(np.abs(y["touch"][:, k]).max() / np.abs(y["press"][:, k]).max() * force)
    mdf = _min_detectable_force(scene, v_per_n, q_per_n[pressed], rig)
    at = int(np.argmin(abs(t_th - w.duration)))
    if np.argmax(np.abs(y["touch"][:, k])) >= 0.95 * (len(t) - 1):
        logging.getLogger(__name__).warning("%s: the warm touch's output peaks at the end of warm_touch.time = %g s; "
                                            "the false force is a lower bound: make the time longer", scene.name, w.time)
    per = {what: {n: y[what][:, j] for j, n in enumerate(names)} for what in y}
    return WarmTouchResult(scene, pressed, force, t, {n: np.interp(t, t_th, film_T[n]) for n in names},
                           {n: Q_touch[:, j] for j, n in enumerate(names)}, per["touch"], per["press"],
                           per["warm_press"], r.label, false_force, mdf, float(t_th[at]), tm.mesh.p, tm.mesh.t,
                           cond.T[at][:tm.mesh.p.shape[1]],
                           {"thermal": t1 - t0, "static": t2 - t1, "readout": time.perf_counter() - t2},
                           drift(check(scene)[a.piezo], w.ambient))


def drift(material, reference_K: float) -> dict:
    """The piezo's sensitivity drift over DRIFT_RANGE_K about `reference_K` (relative
    changes at the range's ends, linear in the material's temperature coefficients): the
    capacitance, the charge per newton, the open-circuit volts per newton; None for one
    whose coefficient no datasheet gives ("no drift data"), and the coefficients' source."""
    def change(tc):
        return None if tc is None else [tc * (T - reference_K) for T in DRIFT_RANGE_K]
    cap, charge = change(material.permittivity_tc), change(material.d_tc)
    volts = None if cap is None or charge is None else [(1 + q) / (1 + c) - 1 for q, c in zip(charge, cap)]
    return {"range_K": list(DRIFT_RANGE_K), "reference_K": reference_K, "capacitance": cap,
            "charge_sensitivity": charge, "open_circuit_sensitivity": volts,
            "source": material.drift_source or "none given"}


def _ramp(t, rise):
    """0 before 0, 1 after `rise`, linear between (the scene's step input, taxel.analyses.solves)."""
    return np.clip(np.asarray(t, float) / rise, 0.0, 1.0)


def _min_detectable_force(scene, v_per_n, q_per_n, rig=None):
    """The chain's minimum detectable force (N) from the static solve's numbers, None when
    the chain's noise budget cannot be built (the open circuit has none here)."""
    from taxel.analyses.solves.noise import quasi_static_noise
    try:
        return float(quasi_static_noise(scene, v_per_n, q_per_n, rig).min_detectable_force)
    except (SceneError, ValueError):
        return None

