"""Run a scene's analysis and write its outputs (CSV + PNG) into a folder.

static     -> fem.solve.solve (printed by the CLI)
frequency  -> fem.dynamics.sweep, the [readout] applied (fem.circuits), Bode plot
transient  -> fem.dynamics.transient (open, resistive coupled, or short circuit +
              charge amplifier), the notch as a digital filter, time plot
lumped     -> fem.lumped: the 3-DoF model's answer to the same scene
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fem import circuits, dynamics, lumped
from reports import figures
from studies.scene import Scene


@dataclass
class Output:
    files: list[Path] = field(default_factory=list)
    summary: list[str] = field(default_factory=list)


def _write_csv(path: Path, header, columns):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for row in zip(*columns):
            w.writerow([f"{v:.9g}" for v in row])
    return path


def _readout_label(r):
    return {"open": "open-circuit voltage", "resistor": f"voltage across {r.R:.3g} ohm",
            "charge_amplifier": "charge-amplifier output"}[r.circuit] + (" + 50 Hz notch" if r.notch else "")


def frequency(scene: Scene, out: Path) -> Output:
    dm = dynamics.model(scene)
    freqs = dynamics.frequencies(scene.analysis)
    port = dynamics.sweep(dm, freqs, scene.analysis.method, scene.analysis.tolerance)
    V = circuits.readout(port, scene.readout) / dm.sy.applied_force          # per newton
    o = Output()
    header, cols = ["frequency_Hz"], [freqs]
    for k, name in enumerate(port.names):
        header += [f"{name}_mag_V_per_N", f"{name}_phase_deg"]
        cols += [np.abs(V[:, k]), np.degrees(np.angle(V[:, k]))]
    o.files.append(_write_csv(out / f"{scene.name}-frequency.csv", header, cols))
    o.files.append(figures.bode(freqs, V, port.names, _readout_label(scene.readout),
                                out / f"{scene.name}-bode.png", title=scene.name))
    o.summary.append(f"{len(freqs)} frequencies {freqs[0]:g}-{freqs[-1]:g} Hz, {port.method} "
                     f"({port.basis_size} basis vectors, measured error {port.error:.1e}), {port.seconds:.2f} s")
    for k, name in enumerate(port.names):
        o.summary.append(f"{name}: |{_readout_label(scene.readout)}| {abs(V[0, k]):.4g} V/N at {freqs[0]:g} Hz, "
                         f"{abs(V[-1, k]):.4g} V/N at {freqs[-1]:g} Hz, peak {abs(V[:, k]).max():.4g} V/N at "
                         f"{freqs[np.argmax(abs(V[:, k]))]:.4g} Hz")
    return o


def transient(scene: Scene, out: Path) -> Output:
    a, r = scene.analysis, scene.readout
    t, f = dynamics.load_history(a)
    if a.input == "csv":                        # the file gives newtons: rescale to the scene's force
        f = f / scene.load.force
    if r.circuit == "charge_amplifier":
        dm = dynamics.model(scene, short=True)
        tr = dynamics.transient(dm, t, f)
        C_p = np.diag(dynamics.direct(dynamics.model(scene), 1.0)[1].real)
        y = circuits.amplifier_in_time(t, tr.Q, 1 / C_p, r)
    elif scene.model.silicone == "yeoh":
        tr, _ = dynamics.transient_hyperelastic(scene, t, f)
        y = tr.V
    else:
        dm = dynamics.model(scene)
        tr = dynamics.transient(dm, t, f, R=r.R if r.circuit == "resistor" else None)
        y = tr.V
    if r.notch:
        y = circuits.notch_in_time(t, y, r)
    o = Output()
    header, cols = ["time_s", "force_N"], [t, tr.force]
    for k, name in enumerate(tr.names):
        header.append(f"{name}_V")
        cols.append(y[:, k])
    o.files.append(_write_csv(out / f"{scene.name}-transient.csv", header, cols))
    o.files.append(figures.time_response(t, tr.force, y, tr.names, _readout_label(r),
                                         out / f"{scene.name}-transient.png", title=scene.name))
    o.summary.append(f"{a.input} input, {len(t)} steps of {a.dt:g} s, reduced model of {tr.basis_size} vectors, "
                     f"{tr.seconds:.2f} s")
    for k, name in enumerate(tr.names):
        o.summary.append(f"{name}: peak {y[np.argmax(abs(y[:, k])), k]:.4g} V, final {y[-1, k]:.4g} V")
    return o


def lumped_model(scene: Scene, out: Path) -> Output:
    lm = lumped.from_scene(scene)
    freqs = dynamics.frequencies(scene.analysis)
    port = dynamics.PortResponse(freqs, lm.V_oc(freqs)[:, None], np.full((len(freqs), 1, 1), 1 / lm.C_p),
                                 ["lumped"], "lumped", 0.0)
    V = circuits.readout(port, scene.readout) / lm.force
    o = Output()
    o.files.append(_write_csv(out / f"{scene.name}-lumped.csv", ["frequency_Hz", "mag_V_per_N", "phase_deg"],
                              [freqs, np.abs(V[:, 0]), np.degrees(np.angle(V[:, 0]))]))
    o.files.append(figures.bode(freqs, V, ["lumped 3-DoF"], _readout_label(scene.readout),
                                out / f"{scene.name}-lumped.png", title=f"{scene.name} (lumped)"))
    A = lm.state_space()[0]
    modes = sorted({round(abs(l.imag) / (2 * np.pi), 1) for l in np.linalg.eigvals(A) if abs(l.imag) > 0})
    o.summary += [
        f"masses {', '.join(f'{m * 1e6:.3g} mg' for m in lm.m)}; stiffnesses "
        f"{', '.join(f'{k:.4g} N/m' for k in lm.k)}; damping {', '.join(f'{b:.3g} N s/m' for b in lm.b)}",
        f"static short-circuit charge {abs(lm.Q_sc([1e-3])[0]):.4g} C, open-circuit voltage "
        f"{abs(lm.V_oc([1e-3])[0]):.4g} V for {lm.force:g} N; C_p {lm.C_p:.4g} F",
        f"damped natural frequencies {', '.join(f'{m:g} Hz' for m in modes) or 'none (overdamped)'}",
        f"{lumped.points_per_second(lm):.3g} frequency points per second",
    ]
    return o
