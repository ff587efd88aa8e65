"""Result objects of the analyses: typed fields, `.record()` (JSON-ready, SI) and
`.to_folder(dir)` (the scene and the data files). The CLI, studies and reports
read these and never re-derive what a result holds."""

from __future__ import annotations

import contextlib
import csv
import json
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from taxel.fem.lumped import Lumped
from taxel.fem.linear import ElectrodeResult, Solution
from taxel.fem.sweep import PortResponse
from taxel.fem.timestep import Transient
from taxel.meshing.build import TaggedMesh
from taxel.scene import Scene, to_data
from taxel.units import engineering


@contextlib.contextmanager
def output_folder(path, replace: bool = False):
    """A folder written whole or not at all: the work goes to a temporary sibling
    that is renamed to `path` at the end and removed on failure, together with any
    parent folders made for it. An existing folder is updated in place, or, with
    `replace`, swapped for the new one only when it is complete.
    Raises ValueError (one line) when `path` cannot be a folder."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{path}: exists and is not a folder; choose another output folder")
    if path.is_dir() and not replace:
        yield path
        return
    made = [p for p in reversed(path.parents) if not p.exists()]
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", dir=path.parent))
    except OSError as exc:
        for p in reversed(made):
            shutil.rmtree(p, ignore_errors=True)
        raise ValueError(f"{path}: cannot create the output folder ({exc.strerror or exc}); "
                         "choose a writable place") from None
    try:
        yield tmp
        if path.is_dir():
            old = Path(tempfile.mkdtemp(prefix=f".{path.name}.old.", dir=path.parent))
            path.rename(old / path.name)
            tmp.rename(path)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(path)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        for p in reversed(made):
            shutil.rmtree(p, ignore_errors=True)
        raise


def write_csv(path: Path, header, columns) -> Path:
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for row in zip(*columns):
            w.writerow([f"{v:.9g}" for v in row])
    return path


def write_scene(out: Path, scene: Scene) -> Path:
    """scene.json: the validated scene with units, readable by taxel.scene.parse."""
    path = Path(out) / "scene.json"
    path.write_text(json.dumps(to_data(scene), indent=1))
    return path


OUTPUT_NAMES = {"voltage_per_newton": "pressed-taxel voltage per newton", "crosstalk": "crosstalk",
                "short_circuit_charge": "pressed-taxel short-circuit charge per newton",
                "readout_output": "readout output, largest over the sweep"}


@dataclass
class OutputError:
    """The estimated relative error of one output, split into its parts (each a
    relative error >= 0, or None when that part was not estimated)."""

    value: float                          # the output itself (SI: V/N, ratio, C/N)
    discretisation: float | None = None   # against the same model on a converged mesh
    model_form: float | None = None       # 2D / axisymmetric against 3D
    material: float | None = None         # linear silicone against Yeoh

    @property
    def total(self) -> float:
        """The parts added (a bound: they may partly cancel)."""
        return sum(x for x in (self.discretisation, self.model_form, self.material) if x is not None)

    def record(self) -> dict:
        return {"value": self.value, "discretisation": self.discretisation, "model_form": self.model_form,
                "material": self.material, "total": self.total}


@dataclass
class ErrorEstimate:
    """A result's estimated error on each output (taxel.analyses.error_estimate), how
    each part was found, and what the estimate cost."""

    outputs: dict[str, OutputError]
    how: list[str] = field(default_factory=list)
    seconds: float = 0.0

    def within(self, tolerance: float, names=None) -> bool:
        return all(self.outputs[k].total <= tolerance for k in (names or self.outputs) if k in self.outputs)

    def record(self) -> dict:
        return {"outputs": {k: e.record() for k, e in self.outputs.items()}, "how": self.how,
                "seconds": self.seconds}

    def lines(self) -> list[str]:
        def pct(x):
            return "-" if x is None else f"{100 * x:.2g} %"
        out = [f"{'estimated error':<46}{'discretisation':>15}{'model form':>12}{'material':>10}{'total':>10}"]
        for k, e in self.outputs.items():
            out.append(f"{OUTPUT_NAMES.get(k, k):<46}{pct(e.discretisation):>15}{pct(e.model_form):>12}"
                       f"{pct(e.material):>10}{pct(e.total):>10}")
        return out + [f"  {h}" for h in self.how] + [f"  (the estimate took {self.seconds:.2f} s)"]


@dataclass
class StaticResult:
    """A static solve of a scene: per-electrode voltage, charge, short-circuit charge
    and capacitance, the support reaction and the fields."""

    scene: Scene
    solution: Solution
    times: dict[str, float] = field(default_factory=dict)     # s: mesh, assemble, solve, total
    model_note: str = ""       # which silicone model was used and why (model.silicone = "auto")
    error: ErrorEstimate | None = None     # estimated error per output (taxel.analyses.error_estimate)
    yeoh: bool = False         # the silicone was solved as Yeoh (model.silicone = "yeoh", or "auto" chose it)

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
    def max_silicone_strain(self) -> float:
        return self.solution.max_solid_strain

    @property
    def mesh(self) -> TaggedMesh:
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
        return self.solution.voltages()

    @property
    def pressed(self) -> str | None:
        """The electrode of the pressed taxel, if the load presses one."""
        s = self.scene
        if s.array is None or s.load.kind not in ("taxel", "indenter"):
            return None
        name = f"taxel_{s.load.taxel[0]}_{s.load.taxel[1]}"
        return name if name in self.electrodes else None

    @property
    def crosstalk(self) -> float | None:
        """Largest |V| of a neighbour over |V| of the pressed taxel (None without one)."""
        v = self.voltages()
        p = self.pressed
        if p is None or len(v) < 2 or v[p] == 0:
            return None
        return max(abs(x) for k, x in v.items() if k != p) / abs(v[p])

    @property
    def contact(self):
        """The press (fem.press.ContactResult) of an indenter scene, else None."""
        return getattr(self.solution, "contact", None)

    def contact_record(self) -> dict | None:
        """The press in SI units: the final state and every converged state of the path
        (force-travel and voltage-force curves), sorted by travel."""
        c = self.contact
        if c is None or not c.points:
            return None
        last = c.points[-1]
        pts = sorted(c.points, key=lambda p: p.travel)
        return {"indenter": {"shape": c.indenter.shape, "radius_m": c.indenter.radius,
                             "edge_radius_m": c.indenter.edge_radius},
                "force_N": last.force, "travel_m": last.travel, "contact_area_m2": last.area,
                "contact_half_width_m": last.half_width, "max_pressure_Pa": last.max_pressure,
                "penetration_m": last.penetration, "newton_iterations": c.total_iterations,
                "load_steps": len(c.points), "failed_trials": c.failed_trials, "penalty_Pa_per_m": c.penalty,
                "curve": {"travel_m": [p.travel for p in pts], "force_N": [p.force for p in pts],
                          "voltages_V": {k: [p.voltages[k] for p in pts] for k in last.voltages},
                          "contact_area_m2": [p.area for p in pts],
                          "max_pressure_Pa": [p.max_pressure for p in pts]}}

    def record(self) -> dict:
        """One JSON-ready record of the numbers a user asks for (SI units)."""
        n = self.newton
        return {"contact": self.contact_record(),
            "scene": self.scene.name, "model": self.scene.model.type,
            "electrodes": {k: {"state": e.state, "voltage_V": e.voltage, "charge_C": e.charge,
                               "short_circuit_charge_C": e.short_circuit_charge,
                               "capacitance_F": e.capacitance} for k, e in self.electrodes.items()},
            "applied_force_N": self.applied_force, "reaction_N": self.reaction.tolist(),
            "max_silicone_strain": self.max_silicone_strain, "unknowns": self.unknowns,
            "solver": self.solver, "relative_residual": self.residual,
            "times_s": self.times, "silicone": self.scene.model.silicone, "model_note": self.model_note,
            "error_estimate": None if self.error is None else self.error.record(),
            "newton": None if n is None else {"load_factors": n.load_factors, "iterations": n.iterations,
                                              "cutbacks": n.cutbacks, "message": n.message},
        }

    def to_folder(self, out) -> list[Path]:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        path = out / "result.json"
        path.write_text(json.dumps(self.record(), indent=1))
        paths = [write_scene(out, self.scene), path]
        c = self.contact_record()
        if c is not None:               # the force-travel / voltage-force curve
            cv = c["curve"]
            paths.append(write_csv(out / "contact-curve.csv",
                                   ["travel_m", "force_N", "contact_area_m2", "max_pressure_Pa"]
                                   + [f"{k}_V" for k in cv["voltages_V"]],
                                   [cv["travel_m"], cv["force_N"], cv["contact_area_m2"], cv["max_pressure_Pa"]]
                                   + list(cv["voltages_V"].values())))
        return paths

    def __str__(self) -> str:
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
        if self.error is not None:
            lines += self.error.lines()
        return "\n".join(lines)


@dataclass
class FrequencyResult:
    """A frequency sweep: what the readout chain outputs per newton, per electrode."""

    scene: Scene
    port: PortResponse          # open-circuit voltages and capacitances per newton
    output: np.ndarray          # (nf, na) complex readout output per newton (V/N)
    label: str                  # what the output is ("charge-amplifier output + 50 Hz notch")
    error: ErrorEstimate | None = None     # estimated error of the readout output (taxel.analyses.error_estimate)

    @property
    def freqs(self) -> np.ndarray:
        return self.port.freqs

    @property
    def names(self) -> list[str]:
        return self.port.names

    def record(self) -> dict:
        return {"scene": self.scene.name, "output": self.label, "method": self.port.method,
                "basis_size": self.port.basis_size, "measured_error": self.port.error,
                "seconds": self.port.seconds, "frequency_Hz": self.freqs.tolist(),
                "magnitude_V_per_N": {k: np.abs(self.output[:, i]).tolist() for i, k in enumerate(self.names)},
                "phase_deg": {k: np.degrees(np.angle(self.output[:, i])).tolist()
                              for i, k in enumerate(self.names)},
                "error_estimate": None if self.error is None else self.error.record()}

    def summary(self) -> list[str]:
        f, V, p = self.freqs, self.output, self.port
        out = [f"{len(f)} frequencies {f[0]:g}-{f[-1]:g} Hz, {p.method} ({p.basis_size} basis vectors, "
               f"measured error {p.error:.1e}), {p.seconds:.2f} s"]
        for k, name in enumerate(self.names):
            mag = np.abs(V[:, k])
            out.append(f"{name}: |{self.label}| {mag[0]:.4g} V/N at {f[0]:g} Hz, {mag[-1]:.4g} V/N at {f[-1]:g} Hz, "
                       f"peak {mag.max():.4g} V/N at {f[np.argmax(mag)]:.4g} Hz")
        if self.error is not None:
            out += self.error.lines()
        return out

    def to_folder(self, out) -> list[Path]:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        header, cols = ["frequency_Hz"], [self.freqs]
        for k, name in enumerate(self.names):
            header += [f"{name}_mag_V_per_N", f"{name}_phase_deg"]
            cols += [np.abs(self.output[:, k]), np.degrees(np.angle(self.output[:, k]))]
        return [write_scene(out, self.scene), write_csv(out / f"{self.scene.name}-frequency.csv", header, cols)]


@dataclass
class TransientResult:
    """A transient: the force history (N) and what the readout chain outputs (V)."""

    scene: Scene
    transient: Transient
    output: np.ndarray          # (nt, na) readout output, V
    label: str
    newton_iterations: list[int] | None = None    # per time step (Yeoh transients)

    @property
    def t(self) -> np.ndarray:
        return self.transient.t

    @property
    def force(self) -> np.ndarray:
        return self.transient.force

    @property
    def names(self) -> list[str]:
        return self.transient.names

    def record(self) -> dict:
        return {"scene": self.scene.name, "output": self.label, "time_s": self.t.tolist(),
                "force_N": self.force.tolist(),
                "output_V": {k: self.output[:, i].tolist() for i, k in enumerate(self.names)},
                "basis_size": self.transient.basis_size, "seconds": self.transient.seconds}

    def summary(self) -> list[str]:
        a, y = self.scene.analysis, self.output
        out = [f"{a.input} input, {len(self.t)} steps of {self.t[1] - self.t[0]:g} s, reduced model of "
               f"{self.transient.basis_size} vectors, {self.transient.seconds:.2f} s"]
        for k, name in enumerate(self.names):
            out.append(f"{name}: peak {y[np.argmax(abs(y[:, k])), k]:.4g} V, final {y[-1, k]:.4g} V")
        return out

    def to_folder(self, out) -> list[Path]:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        header, cols = ["time_s", "force_N"], [self.t, self.force]
        for k, name in enumerate(self.names):
            header.append(f"{name}_V")
            cols.append(self.output[:, k])
        return [write_scene(out, self.scene), write_csv(out / f"{self.scene.name}-transient.csv", header, cols)]


@dataclass
class LumpedResult:
    """The 3-DoF lumped model's frequency response to a scene, through its readout."""

    scene: Scene
    model: Lumped
    freqs: np.ndarray
    output: np.ndarray          # (nf,) complex readout output per newton
    label: str

    def summary(self) -> list[str]:
        lm = self.model
        A = lm.state_space()[0]
        modes = sorted({round(abs(v.imag) / (2 * np.pi), 1) for v in np.linalg.eigvals(A) if abs(v.imag) > 0})
        return [
            f"masses {', '.join(f'{m * 1e6:.3g} mg' for m in lm.m)}; stiffnesses "
            f"{', '.join(f'{k:.4g} N/m' for k in lm.k)}; damping {', '.join(f'{b:.3g} N s/m' for b in lm.b)}",
            f"static short-circuit charge {abs(lm.Q_sc([1e-3])[0]):.4g} C, open-circuit voltage "
            f"{abs(lm.V_oc([1e-3])[0]):.4g} V for {lm.force:g} N; C_p {lm.C_p:.4g} F",
            f"damped natural frequencies {', '.join(f'{m:g} Hz' for m in modes) or 'none (overdamped)'}",
        ]

    def record(self) -> dict:
        lm = self.model
        return {"scene": self.scene.name, "output": self.label, "masses_kg": lm.m.tolist(),
                "stiffnesses_N_per_m": lm.k.tolist(), "damping_N_s_per_m": lm.b.tolist(), "C_p_F": lm.C_p,
                "frequency_Hz": self.freqs.tolist(), "magnitude_V_per_N": np.abs(self.output).tolist()}

    def to_folder(self, out) -> list[Path]:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        return [write_scene(out, self.scene),
                write_csv(out / f"{self.scene.name}-lumped.csv", ["frequency_Hz", "mag_V_per_N", "phase_deg"],
                          [self.freqs, np.abs(self.output), np.degrees(np.angle(self.output))])]
