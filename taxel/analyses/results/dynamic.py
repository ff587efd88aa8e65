"""The results of the dynamic analyses: a frequency sweep, a transient and the
3-DoF lumped model, each through the scene's readout chain.

Read back from a folder (`taxel.analyses.read`), a frequency result has no port
response (`port` is None: no open-circuit voltages or capacitances over
frequency, only the readout output) and a transient no full state (`transient`
is None: no electrode voltages and charges before the readout); the lumped model
is whole."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from taxel.fem.readout import Lumped
from taxel.fem.dynamics import PortResponse
from taxel.fem.dynamics import Transient
from taxel.scene import Scene
from taxel.analyses.results.base import ErrorEstimate, error_lines, error_record, read_error
from taxel.analyses.results.dynamic_figures import bode_png, lumped_png, resonance, transient_png
from taxel.analyses.results.base import FORMAT, write_csv, write_result, write_summary
from taxel.schema import electrode_name


def _pressed_index(scene: Scene, names: list[str]) -> int:
    """The column of the pressed taxel (scene.load.taxel) among `names`, else 0."""
    p = scene.load.taxel
    name = electrode_name(p[0], p[1])
    return names.index(name) if name in names else 0


@dataclass
class FrequencyResult:
    """A frequency sweep: what the readout chain outputs per newton, per electrode."""

    scene: Scene
    freqs: np.ndarray           # Hz
    output: np.ndarray          # (nf, na) complex readout output per newton (V/N)
    names: list[str]
    label: str                  # what the output is ("charge-amplifier output + 50 Hz notch")
    method: str                 # direct | reduced
    basis_size: int
    measured_error: float       # the reduced sweep's measured relative error
    seconds: float
    capacitance: dict[str, float]          # F, each electrode's capacitance at the lowest frequency
    error: ErrorEstimate | None = None     # estimated error of the readout output (taxel.analyses.accuracy.error_estimate)
    port: PortResponse | None = None       # open-circuit voltages and capacitances (None when read back)
    kind = "frequency"
    success = True             # no load to stop short of
    stop = None

    @classmethod
    def from_port(cls, scene: Scene, port: PortResponse, output: np.ndarray, label: str) -> FrequencyResult:
        C = np.diag(np.linalg.inv(port.Cinv[0])).real
        return cls(scene, port.freqs, output, list(port.names), label, port.method, port.basis_size, port.error,
                   port.seconds, {k: float(c) for k, c in zip(port.names, C)}, port=port)

    @property
    def pressed(self) -> str:
        """The electrode the outputs describe: the pressed taxel's, else the first."""
        return self.names[_pressed_index(self.scene, self.names)]

    def sweep_values(self) -> np.ndarray:
        """|readout output| per newton of the pressed (or first) taxel at each frequency."""
        return np.abs(self.output[:, _pressed_index(self.scene, self.names)])

    def first_resonance(self) -> float | None:
        """The resonance of the pressed (or first) taxel's sweep, Hz (dynamic_figures.resonance: the
        largest peak above the lowest decade, inside the sweep; the Bode plot marks it),
        to the sweep's resolution; None when the sweep holds none."""
        i = resonance(self.freqs, self.sweep_values())
        return None if i is None else float(self.freqs[i])

    def outputs(self) -> dict[str, float]:
        """readout_sensitivity: the largest |readout output| per newton of the pressed
        (or first) taxel over the sweep, V/N; peak_frequency: where it is, Hz."""
        y = self.sweep_values()
        return {"readout_sensitivity": float(y.max()), "peak_frequency": float(self.freqs[np.argmax(y)])}

    def record(self) -> dict:
        return {"kind": self.kind, "format": FORMAT, "scene": self.scene.name, "output": self.label,
                "method": self.method, "basis_size": self.basis_size, "measured_error": self.measured_error,
                "seconds": self.seconds, "capacitance_F": self.capacitance,
                "frequency_Hz": np.asarray(self.freqs).tolist(),
                "magnitude_V_per_N": {k: np.abs(self.output[:, i]).tolist() for i, k in enumerate(self.names)},
                "phase_deg": {k: np.degrees(np.angle(self.output[:, i])).tolist()
                              for i, k in enumerate(self.names)},
                "outputs": self.outputs(), **error_record(self.error, self.kind)}

    @classmethod
    def from_record(cls, scene: Scene, rec: dict) -> FrequencyResult:
        names = list(rec["magnitude_V_per_N"])
        out = np.array([np.asarray(rec["magnitude_V_per_N"][k]) * np.exp(1j * np.radians(rec["phase_deg"][k]))
                        for k in names]).T
        return cls(scene, np.asarray(rec["frequency_Hz"], dtype=float), out, names, rec["output"], rec["method"],
                   rec["basis_size"], rec["measured_error"], rec["seconds"], dict(rec.get("capacitance_F") or {}),
                   read_error(rec))

    def summary(self) -> list[str]:
        f, V = self.freqs, self.output
        out = [f"{len(f)} frequencies {f[0]:g}-{f[-1]:g} Hz, {self.method} ({self.basis_size} basis vectors, "
               f"measured error {self.measured_error:.1e}), {self.seconds:.2f} s"]
        for k, name in enumerate(self.names):
            mag = np.abs(V[:, k])
            out.append(f"{name}: |{self.label}| {mag[0]:.4g} V/N at {f[0]:g} Hz, {mag[-1]:.4g} V/N at {f[-1]:g} Hz, "
                       f"peak {mag.max():.4g} V/N at {f[np.argmax(mag)]:.4g} Hz")
        return out + error_lines(self.error, self.kind)

    def __str__(self) -> str:
        return "\n".join(self.summary())

    def to_folder(self, out) -> list[Path]:
        """result.json, scene.json, <scene>-frequency.csv, <scene>-bode.png and summary.txt."""
        out = Path(out)
        paths = write_result(out, self.record(), self.scene)
        header, cols = ["frequency_Hz"], [self.freqs]
        for k, name in enumerate(self.names):
            header += [f"{name}_mag_V_per_N", f"{name}_phase_deg"]
            cols += [np.abs(self.output[:, k]), np.degrees(np.angle(self.output[:, k]))]
        return paths + [write_csv(out / f"{self.scene.name}-frequency.csv", header, cols),
                        bode_png(self, out / f"{self.scene.name}-bode.png"), write_summary(out, self.summary())]


@dataclass
class TransientResult:
    """A transient: the force history (N) and what the readout chain outputs (V)."""

    scene: Scene
    t: np.ndarray               # s
    force: np.ndarray           # N
    output: np.ndarray          # (nt, na) readout output, V
    names: list[str]
    label: str
    basis_size: int
    seconds: float
    newton_iterations: list[int] | None = None    # per time step (Yeoh transients)
    transient: Transient | None = None            # electrode voltages and charges (None when read back)
    error: ErrorEstimate | None = None            # no estimate for a transient yet: always None
    kind = "transient"
    success = True             # no load to stop short of
    stop = None

    @classmethod
    def from_transient(cls, scene: Scene, tr: Transient, output: np.ndarray, label: str,
                       newton_iterations: list[int] | None = None) -> TransientResult:
        return cls(scene, tr.t, tr.force, output, list(tr.names), label, tr.basis_size, tr.seconds,
                   newton_iterations, tr)

    def outputs(self) -> dict[str, float]:
        """peak_output (the largest-magnitude readout output, signed) and final_output
        of the pressed (or first) taxel, V."""
        y = self.output[:, _pressed_index(self.scene, self.names)]
        return {"peak_output": float(y[np.argmax(np.abs(y))]), "final_output": float(y[-1])}

    def record(self) -> dict:
        return {"kind": self.kind, "format": FORMAT, "scene": self.scene.name, "output": self.label,
                "time_s": np.asarray(self.t).tolist(), "force_N": np.asarray(self.force).tolist(),
                "output_V": {k: self.output[:, i].tolist() for i, k in enumerate(self.names)},
                "basis_size": self.basis_size, "seconds": self.seconds,
                "newton_iterations": self.newton_iterations, "outputs": self.outputs(),
                **error_record(self.error, self.kind)}

    @classmethod
    def from_record(cls, scene: Scene, rec: dict) -> TransientResult:
        names = list(rec["output_V"])
        return cls(scene, np.asarray(rec["time_s"], dtype=float), np.asarray(rec["force_N"], dtype=float),
                   np.array([rec["output_V"][k] for k in names], dtype=float).reshape(len(names), -1).T,
                   names, rec["output"], rec["basis_size"], rec["seconds"], rec.get("newton_iterations"),
                   error=read_error(rec))

    def summary(self) -> list[str]:
        a, y = self.scene.analysis, self.output
        out = [f"{a.input} input, {len(self.t)} steps of {self.t[1] - self.t[0]:g} s, reduced model of "
               f"{self.basis_size} vectors, {self.seconds:.2f} s"]
        for k, name in enumerate(self.names):
            out.append(f"{name}: peak {y[np.argmax(abs(y[:, k])), k]:.4g} V, final {y[-1, k]:.4g} V")
        return out + error_lines(self.error, self.kind)

    def __str__(self) -> str:
        return "\n".join(self.summary())

    def to_folder(self, out) -> list[Path]:
        """result.json, scene.json, <scene>-transient.csv, <scene>-transient.png and summary.txt."""
        out = Path(out)
        paths = write_result(out, self.record(), self.scene)
        header, cols = ["time_s", "force_N"], [self.t, self.force]
        for k, name in enumerate(self.names):
            header.append(f"{name}_V")
            cols.append(self.output[:, k])
        return paths + [write_csv(out / f"{self.scene.name}-transient.csv", header, cols),
                        transient_png(self, out / f"{self.scene.name}-transient.png"),
                        write_summary(out, self.summary())]


@dataclass
class LumpedResult:
    """The 3-DoF lumped model's frequency response to a scene, through its readout."""

    scene: Scene
    model: Lumped
    freqs: np.ndarray
    output: np.ndarray          # (nf,) complex readout output per newton
    label: str
    error: ErrorEstimate | None = None     # no estimate for the lumped model: always None
    kind = "lumped"
    success = True             # no load to stop short of
    stop = None

    def resonances(self) -> list[float]:
        """The damped natural frequencies, Hz (empty when overdamped)."""
        A = self.model.state_space()[0]
        return sorted({round(abs(v.imag) / (2 * np.pi), 1) for v in np.linalg.eigvals(A) if abs(v.imag) > 0})

    def outputs(self) -> dict[str, float]:
        """sensitivity (open-circuit V/N) and charge_sensitivity (short-circuit C/N) at
        1 mHz (static), magnitudes; first_resonance (Hz) unless overdamped."""
        lm = self.model
        out = {"sensitivity": float(abs(lm.V_oc([1e-3])[0]) / lm.force),
               "charge_sensitivity": float(abs(lm.Q_sc([1e-3])[0]) / lm.force)}
        modes = self.resonances()
        if modes:
            out["first_resonance"] = float(modes[0])
        return out

    def summary(self) -> list[str]:
        lm = self.model
        modes = self.resonances()
        return [
            f"masses {', '.join(f'{m * 1e6:.3g} mg' for m in lm.m)}; stiffnesses "
            f"{', '.join(f'{k:.4g} N/m' for k in lm.k)}; damping {', '.join(f'{b:.3g} N s/m' for b in lm.b)}",
            f"static short-circuit charge {abs(lm.Q_sc([1e-3])[0]):.4g} C, open-circuit voltage "
            f"{abs(lm.V_oc([1e-3])[0]):.4g} V for {lm.force:g} N; C_p {lm.C_p:.4g} F",
            f"damped natural frequencies {', '.join(f'{m:g} Hz' for m in modes) or 'none (overdamped)'}",
        ] + error_lines(self.error, self.kind)

    def __str__(self) -> str:
        return "\n".join(self.summary())

    def record(self) -> dict:
        lm = self.model
        return {"kind": self.kind, "format": FORMAT, "scene": self.scene.name, "output": self.label,
                "masses_kg": lm.m.tolist(), "stiffnesses_N_per_m": lm.k.tolist(), "damping_N_s_per_m": lm.b.tolist(),
                "C_p_F": lm.C_p, "gain_C_per_m": lm.gain, "force_N": lm.force,
                "frequency_Hz": np.asarray(self.freqs).tolist(), "magnitude_V_per_N": np.abs(self.output).tolist(),
                "phase_deg": np.degrees(np.angle(self.output)).tolist(), "outputs": self.outputs(),
                **error_record(self.error, self.kind)}

    @classmethod
    def from_record(cls, scene: Scene, rec: dict) -> LumpedResult:
        lm = Lumped(np.asarray(rec["masses_kg"]), np.asarray(rec["stiffnesses_N_per_m"]),
                    np.asarray(rec["damping_N_s_per_m"]), rec["gain_C_per_m"], rec["C_p_F"], rec["force_N"])
        out = np.asarray(rec["magnitude_V_per_N"]) * np.exp(1j * np.radians(rec["phase_deg"]))
        return cls(scene, lm, np.asarray(rec["frequency_Hz"], dtype=float), out, rec["output"], read_error(rec))

    def to_folder(self, out) -> list[Path]:
        """result.json, scene.json, <scene>-lumped.csv, <scene>-lumped.png and summary.txt."""
        out = Path(out)
        return write_result(out, self.record(), self.scene) + [
            write_csv(out / f"{self.scene.name}-lumped.csv", ["frequency_Hz", "mag_V_per_N", "phase_deg"],
                      [self.freqs, np.abs(self.output), np.degrees(np.angle(self.output))]),
            lumped_png(self, out / f"{self.scene.name}-lumped.png"), write_summary(out, self.summary())]
