"""The static result: per-electrode voltage, charge, short-circuit charge and
capacitance, the support reaction, the largest silicone strain, the press of an
indenter, and (a fresh solve only) the mesh and fields."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np

from taxel.fem.static import ElectrodeResult, Solution
from taxel.fem.hyperelastic import NewtonResult
from taxel.meshing.build import TaggedMesh
from taxel.scene import Scene
from taxel.units import engineering
from taxel.analyses.results.readout import AtReadout
from taxel.analyses.results.base import ErrorEstimate, error_lines, error_record, pressed_name, read_error
from taxel.analyses.results.figures import FIELDS, SolvedFields, contact_curves, field_figures
from taxel.analyses.results.base import FORMAT, write_csv, write_result, write_summary

# Linear silicone's taxel-voltage error per unit of its own largest silicone strain:
# the worst ratio measured over the thesis PZT and PVDF taxels, 0.05 to 0.45 N
# (benchmarks/silicone_model_error.py: 0.223 least squares, 0.257 worst).
LINEAR_ERROR_PER_STRAIN = 0.257


def linear_error(max_strain: float) -> float:
    """Estimated relative voltage error of a linear silicone at this largest strain."""
    return LINEAR_ERROR_PER_STRAIN * max_strain


@dataclass(frozen=True)
class Stop:
    """Why a static solve stopped short of its load: the result is then its last converged
    state (`StaticResult.success` is False; taxel.analyses.solve)."""

    requested: float           # the load asked for, in `unit`
    load: Literal["force", "pressure", "travel"]   # which: the scene's load.force, load.pressure or load.travel
    message: str               # what stopped it and what it measured there (one line)
    cause: str | None = None   # a press's stop cause (fem.contact.StopCause); None for a Yeoh Newton

    @property
    def unit(self) -> str:
        return {"force": "N", "pressure": "Pa", "travel": "m"}[self.load]


@dataclass
class StaticResult:
    """A static solve of a scene: per-electrode voltage, charge, short-circuit charge
    and capacitance, the support reaction and the fields.

    Read back from a folder (`taxel.analyses.read`), the numbers are all there but
    the solution has no mesh and no fields (`mesh`, `fields` are None) and no
    capacitance matrix; the press is kept as its record (`contact_record()`), and
    `contact` is None."""

    scene: Scene
    solution: Solution
    times: dict[str, float] = field(default_factory=dict)     # s: mesh, assemble, solve, total
    model_note: str = ""       # which silicone model was used and why (model.silicone = "auto")
    error: ErrorEstimate | None = None     # estimated error per output (taxel.analyses.accuracy.error_estimate)
    yeoh: bool = False         # the silicone was solved as Yeoh (model.silicone = "yeoh", or "auto" chose it)
    contact_data: dict | None = None       # the press record of a result read back (else from the solution)
    stop: Stop | None = None   # the solve stopped short of its load: this is its last converged state
    readout: AtReadout | None = None       # the scene's [readout] chain's numbers (taxel.analyses.solves.at_readout)
    # a scene's [warm_touch]: its WarmTouchResult (taxel.analyses.solves.warm_touch), or read back, its summary
    warm_touch: object | None = None
    kind = "static"

    @property
    def success(self) -> bool:
        """The solve reached its load (else `stop` says how far it got and why)."""
        return self.stop is None

    @property
    def electrodes(self) -> dict[str, ElectrodeResult]:
        return self.solution.electrodes

    @property
    def applied_force(self) -> float:
        return self.solution.applied_force

    @property
    def reaction(self) -> np.ndarray:
        return self.solution.reaction

    @property
    def max_strain(self) -> float:
        return self.solution.max_strain

    @property
    def mesh(self) -> TaggedMesh | None:
        return self.solution.mesh

    @property
    def fields(self):
        return self.solution.fields

    @property
    def newton(self):
        return self.solution.newton

    @property
    def unknowns(self) -> int:
        return self.solution.unknowns

    @property
    def solver(self) -> str:
        return self.solution.solver

    @property
    def residual(self) -> float:
        return self.solution.residual

    def voltages(self) -> dict[str, float]:
        """The open-circuit voltage of every electrode but the reference, V."""
        return {k: e.voltage for k, e in self._taxels().items()}

    def _taxels(self) -> dict[str, ElectrodeResult]:
        """The electrodes but the reference (the taxels, or a plate's electrodes)."""
        return {k: e for k, e in self.electrodes.items() if e.state != "reference"}

    @property
    def pressed(self) -> str | None:
        """The electrode of the pressed taxel, if the load presses one."""
        return pressed_name(self.scene, self.electrodes)

    @property
    def crosstalk(self) -> float | None:
        """Largest |V| of a neighbour over |V| of the pressed taxel (None without one)."""
        v = self.voltages()
        p = self.pressed
        if p is None or len(v) < 2 or v[p] == 0:
            return None
        return max(abs(x) for k, x in v.items() if k != p) / abs(v[p])

    def outputs(self) -> dict[str, float]:
        """The named outputs (SI; the output table's "static" ones, taxel.analyses.results.outputs): sensitivity (open-circuit V/N),
        charge_sensitivity (short-circuit C/N) and pressed_voltage (V) of the pressed
        taxel, or of the first taxel when the load presses none (signed; per newton
        of |applied force|); crosstalk (with a pressed taxel and a neighbour);
        max_strain (the largest principal strain in the silicone)."""
        out: dict[str, float] = {}
        taxels = self._taxels()
        if taxels:
            e = taxels[self.pressed or next(iter(taxels))]
            force = abs(self.applied_force) or 1.0
            out = {"sensitivity": e.voltage / force, "charge_sensitivity": e.short_circuit_charge / force,
                   "pressed_voltage": e.voltage}
            if self.crosstalk is not None:
                out["crosstalk"] = self.crosstalk
            if self.readout is not None:      # the scene names a readout: its numbers beside the open circuit's
                out.update(self.readout.outputs())
            w = self.warm_touch_summary()
            if w is not None:                 # a [warm_touch]: the false force of a warm finger
                out.update(warm_touch_force=w["false_force_N"], warm_touch_ratio=w["ratio"])
        out["max_strain"] = self.max_strain
        return out

    def warm_touch_summary(self) -> dict | None:
        """The warm touch's numbers (WarmTouchResult.summary), None without a [warm_touch]."""
        w = self.warm_touch
        return w.summary() if hasattr(w, "summary") else w

    def at_readout(self) -> AtReadout | None:
        """The pressed taxel's numbers through the scene's [readout] chain (set by
        taxel.analyses.solve: taxel.analyses.solves.at_readout), None for the open circuit."""
        return self.readout

    @property
    def contact(self):
        """The press (fem.contact.PressResult) of an indenter scene, else None."""
        return getattr(self.solution, "contact", None)

    def contact_record(self) -> dict | None:
        """The press in SI units: the final state and every converged state of the path
        (force-travel and voltage-force curves), sorted by travel."""
        c = self.contact
        if c is None or not c.points:
            return self.contact_data
        last = c.points[-1]
        pts = sorted(c.points, key=lambda p: p.travel)
        return {"indenter": {"shape": c.indenter.shape, "radius_m": c.indenter.radius,
                             "edge_radius_m": c.indenter.edge_radius},
                "force_N": last.force, "travel_m": last.travel, "contact_area_m2": last.area,
                "contact_half_width_m": last.half_width, "max_pressure_Pa": last.max_pressure,
                "penetration_m": last.penetration, "newton_iterations": c.total_iterations,
                "load_steps": len(c.points), "failed_trials": c.failed_trials, "penalty_Pa_per_m": c.penalty,
                "friction": c.indenter.friction, "slip_zone": c.slip_zone.record(c.indenter.centre),
                "curve": {"travel_m": [p.travel for p in pts], "force_N": [p.force for p in pts],
                          "voltages_V": {k: [p.voltages[k] for p in pts] for k in last.voltages},
                          "contact_area_m2": [p.area for p in pts],
                          "max_pressure_Pa": [p.max_pressure for p in pts]}}

    def record(self) -> dict:
        """One JSON-ready record of the numbers a user asks for (SI units)."""
        n = self.newton
        return {"kind": self.kind, "format": FORMAT, "contact": self.contact_record(),
            "scene": self.scene.name, "model": self.scene.model.type,
            "electrodes": {k: {"state": e.state, "voltage_V": e.voltage, "charge_C": e.charge,
                               "short_circuit_charge_C": e.short_circuit_charge,
                               "capacitance_F": e.capacitance} for k, e in self.electrodes.items()},
            "applied_force_N": self.applied_force, "reaction_N": np.asarray(self.reaction).tolist(),
            "max_strain": self.max_strain, "unknowns": self.unknowns,
            "solver": self.solver, "relative_residual": self.residual,
            "times_s": self.times, "silicone": self.scene.model.silicone, "model_note": self.model_note,
            "yeoh": self.yeoh, "outputs": self.outputs(), **error_record(self.error, self.kind),
            "newton": None if n is None else {"converged": n.converged, "load_factors": n.load_factors,
                                              "iterations": n.iterations, "cutbacks": n.cutbacks,
                                              "message": n.message},
            "at_readout": None if self.readout is None else self.readout.record(),
            "warm_touch": self.warm_touch_summary(),
            "stop": None if self.stop is None else {"requested": self.stop.requested, "load": self.stop.load,
                                                    "message": self.stop.message, "cause": self.stop.cause},
        }

    @classmethod
    def from_record(cls, scene: Scene, rec: dict) -> StaticResult:
        """The result of a result.json record (no mesh, no fields)."""
        els = {k: ElectrodeResult(k, e["state"], e["voltage_V"], e["charge_C"], e["short_circuit_charge_C"],
                                  e["capacitance_F"]) for k, e in rec["electrodes"].items()}
        n = rec.get("newton")
        newton = None if n is None else NewtonResult(n.get("converged", True), list(n["load_factors"]),
                                                     list(n["iterations"]), cutbacks=n["cutbacks"],
                                                     message=n["message"])
        sol = Solution(els, rec["applied_force_N"], np.asarray(rec["reaction_N"], dtype=float),
                       rec["max_strain"], rec["unknowns"], rec["solver"], rec["relative_residual"],
                       None, None, newton)
        st = rec.get("stop")
        return cls(scene, sol, dict(rec.get("times_s", {})), rec.get("model_note", ""), read_error(rec),
                   bool(rec["yeoh"]), rec.get("contact"),
                   None if st is None else Stop(st["requested"], st["load"], st["message"], st.get("cause")),
                   AtReadout.from_record(rec.get("at_readout")), rec.get("warm_touch"))

    def to_folder(self, out) -> list[Path]:
        """The result's folder, as `taxel solve --out` leaves it: result.json, scene.json,
        for a press contact-curve.csv and <scene>-contact.png, the figures of the solved
        fields (`fields/`, a fresh solve only) and summary.txt."""
        out = Path(out)
        paths = write_result(out, self.record(), self.scene)
        c = self.contact_record()
        if c is not None:               # the force-travel / voltage-force curve
            cv = c["curve"]
            paths.append(write_csv(out / "contact-curve.csv",
                                   ["travel_m", "force_N", "contact_area_m2", "max_pressure_Pa"]
                                   + [f"{k}_V" for k in cv["voltages_V"]],
                                   [cv["travel_m"], cv["force_N"], cv["contact_area_m2"], cv["max_pressure_Pa"]]
                                   + list(cv["voltages_V"].values())))
            paths.append(contact_curves(c, out / f"{self.scene.name}-contact.png", title=self.scene.name))
        sol = self.solution
        if sol.mesh is not None:          # a fresh solve: its fields drawn (a result read back has none)
            paths += field_figures(SolvedFields(self.scene, sol.mesh, sol.fields, sol.electrodes, sol.applied_force,
                                                self.pressed, sol.unknowns), out / FIELDS)
        if hasattr(self.warm_touch, "write"):      # a fresh warm touch: its traces and field (reports.warm_touch)
            paths.append(self.warm_touch.write(out))
        return paths + [write_summary(out, self.summary())]

    def summary(self) -> list[str]:
        """The electrodes' table, the press and the error estimate, for a person."""
        s, m = self.scene, self.scene.mesh
        lines = [f"scene {s.name}: {s.model.type}, order {m.order} ({s.model.silicone} silicone, {m.formulation}), "
                 f"{self.unknowns} unknowns, solver {self.solver}"
                 + (f", {self.times['total']:.3f} s" if "total" in self.times else ""),
                 f"{'electrode':<12}{'state':<10}{'voltage':>12}{'charge':>13}{'short-circuit Q':>18}"
                 f"{'capacitance':>14}"]
        for e in self.electrodes.values():
            lines.append(f"{e.name:<12}{e.state:<10}{engineering(e.voltage, 'V'):>12}"
                         f"{engineering(e.charge, 'C'):>13}{engineering(e.short_circuit_charge, 'C'):>18}"
                         f"{engineering(e.capacitance, 'F'):>14}")
        if self.readout is not None:
            lines += self.readout.lines(self.outputs())
        w = self.warm_touch_summary()
        if w is not None:
            mdf = w["min_detectable_force_N"]
            lines.append(f"warm touch ({w['finger_K'] - 273.15:.1f} C for {w['duration_s']:g} s): film +"
                         f"{w['film_rise_K']:.3g} K, false force {engineering(w['false_force_N'], 'N')}"
                         + ("" if mdf is None else f" ({w['ratio']:.3g} x the minimum detectable "
                                                   f"{engineering(mdf, 'N')})") + f", {w['readout']}")
            lines.append("  sensitivity drift 0-50 C: " + drift_words(w.get("drift"), w["readout"], "C"))
        if self.stop is not None:
            st = self.stop
            lines.insert(1, f"STOPPED SHORT of load.{st.load} = {engineering(st.requested, st.unit)}: these are "
                            f"its last converged state's numbers ({st.message})")
        c = self.contact_record()
        if c is not None:
            lines.append(f"indenter ({c['indenter']['shape']}): force {engineering(c['force_N'], 'N')} at travel "
                         f"{engineering(c['travel_m'], 'm')}, contact area {1e6 * c['contact_area_m2']:.4g} mm2, "
                         f"max pressure {engineering(c['max_pressure_Pa'], 'Pa')}, penetration "
                         f"{engineering(c['penetration_m'], 'm')}; {c['load_steps']} load steps, "
                         f"{c['newton_iterations']} Newton iterations")
            lines.append(f"{'travel':>12}{'force':>12}" + "".join(f"{k:>14}" for k in c["curve"]["voltages_V"]))
            cv = c["curve"]
            for i, d in enumerate(cv["travel_m"]):
                lines.append(f"{engineering(d, 'm'):>12}{engineering(cv['force_N'][i], 'N'):>12}"
                             + "".join(f"{engineering(v[i], 'V'):>14}" for v in cv["voltages_V"].values()))
        return lines + error_lines(self.error, self.kind)

    def details(self) -> list[str]:
        """What `taxel solve` prints below the summary: times, force and reaction, the Newton
        solve, the model note and, for an array, the largest silicone strain with the error a
        linear silicone makes there."""
        lines = []
        if self.times:                        # a stopped solve's last converged state has none
            lines.append(f"times: mesh {self.times['mesh']:.3f} s, assemble {self.times['assemble']:.3f} s, "
                         f"solve {self.times['solve']:.3f} s")
        lines.append(f"applied force {engineering(self.applied_force, 'N')}, support reaction "
                     f"{engineering(self.reaction[-1], 'N')} (vertical), relative residual {self.residual:.1e}")
        if self.newton is not None:
            lines.append(f"Newton: {self.newton.message}")
        if self.model_note:
            lines.append(self.model_note)
        if self.mesh is not None and self.mesh.layout.taxels:
            est = linear_error(self.max_strain)
            lines.append(f"largest silicone strain {100 * self.max_strain:.1f} %"
                         + (f" (a linear silicone errs by about {100 * est:.2g} % here; model.silicone = 'auto' "
                            "or 'yeoh' to do better)" if not self.yeoh and est > 0.02 else ""))
        return lines

    def to_vtu(self, path) -> Path:
        """The displacement, potential, strain and stress fields of a fresh solve, as .vtu."""
        from taxel.meshing.build import export
        f = self.fields
        export(self.mesh, path, point_data={"u": f.u, "phi": f.phi}, cell_data={"strain": f.strain, "stress": f.stress})
        return Path(path)

    def __str__(self) -> str:
        return "\n".join(self.summary())


DRIFT_RANGE_K = (273.15, 323.15)   # a warm touch's sensitivity drift range: 0 to 50 C (solves.warm_touch.drift)


def drift_words(d: dict | None, readout: str, degree: str = "°C") -> str:
    """A drift() record in words: the readout's sensitivity (the charge per newton at a charge
    amplifier, named by the readout's label; the open-circuit volts per newton otherwise) and
    the capacitance at the range's ends; "no drift data" where no coefficient is given."""
    d = d or {}
    lo, hi = (f"{T - 273.15:.0f} {degree}" for T in d.get("range_K", DRIFT_RANGE_K))
    sens = d.get("charge_sensitivity" if readout.startswith("charge") else "open_circuit_sensitivity")
    cap = d.get("capacitance")
    text = ("no drift data (no temperature coefficient of the d constants found)" if sens is None else
            f"{100 * sens[0]:+.3g} % at {lo}, {100 * sens[1]:+.3g} % at {hi}")
    if cap is not None:
        text += f"; capacitance {100 * cap[0]:+.3g} % at {lo}, {100 * cap[1]:+.3g} % at {hi}"
    return text

