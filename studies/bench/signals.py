"""A simulated rig: the bench's signals, made by the models, as frames.

Physics, per taxel k at (r, c) and per press p (the scene's pressed taxel for
step, impulse and chirp; random taxels for "presses", and with `between` > 0
that fraction of the presses at random points of the array, between taxels and
over the margins):
  force      F_p(t): the commanded force through the actuator's roll-off (a
             second-order Butterworth low-pass, corner `actuator_Hz`);
  charge     model "lumped": Q_k = q_per_N * g_k * sum_p W[p, k] F_p, with q_per_N the
             lumped model's short-circuit charge per newton at 1 Hz (`lumped_model(scene)`;
             its resonances are above 10 kHz, so it is quasi-static at the bench's
             rates), W the FEM's crosstalk weights (taxel.analyses.solves.crosstalk; with
             `between` > 0 the influence functions of position, W[p, (r, c)] =
             G_r(y_p) G_c(x_p), taxel.analyses.surface.influence, for every press) and
             g_k a per-taxel gain spread (log-normal, `gain_spread`);
             model "fem": the FEM transient (Newmark, electrodes shorted: fem.dynamics)
             of the scene under the rolled-off force on its pressed taxel gives the
             short-circuit charge of every modelled electrode; a 2D scene models the
             pressed row, and the other rows get W1[pressed row, row] of it. The FEM
             charge is about 4.5 x the lumped one for the thesis taxel (lateral flow,
             docs/verification.md); step, impulse and chirp only;
             model "reduced": the scene's reduced model (taxel.analyses.solves.reduced, inputs a
             force on each taxel, outputs the short-circuit charges; cached), MIMO, so
             the crosstalk within the modelled row (2D) or array (3D) is the FEM's own and
             its dynamics (resonances, losses) are in; in 2D a press on row r reaches row r'
             with W1[r, r'] of the modelled row's charges; `crosstalk` False keeps each
             taxel's own path only; not with presses between taxels;
  readout    the rig's conditioning of taxel k with its time constant scaled by
             a per-taxel factor s_k (log-normal, `tau_spread`; the thesis measured
             1.7 s and 3.1 s on two PZT taxels at 500 MOhm): open V = -Q / C_p;
             resistor V/Q = -sR/(1 + sRC_p), tau = R C_p; charge amplifier
             V/Q = -(1/C_f) sR_fC_f/(1 + sR_fC_f) / (1 + sR_i(C_p + C_c)), tau = R_f C_f;
             bilinear-discretised at the rig's rate; then the notch (fem.readout.notch_in_time);
  travel     with a travel channel in the rig, the actuator's travel: the total force
             through the compliance of the lumped taxel (top displacement per newton) whose
             silicone has its moduli scaled by `modulus_scale` and loss factor
             `silicone_loss` (studies.measured.silicone), + the sensor's white noise;
  ADC        volts = V * gain + white noise + 50 Hz hum with its 3rd and 5th
             harmonics + baseline drift; the load cell F * sensitivity + its noise;
             quantised to the rig's ADC (16 bits over +-10 V in the thesis rig) and clipped.
Frames: seq from `seq0`, t_us from `t0_us` at the nominal rate with 1 us clock jitter
(both wrap). The truth (forces, per-taxel parameters, clean signals) is kept.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Literal

import numpy as np
from scipy import signal

from taxel.analyses.surface.bench_model import compliance, fem_charges, loss_factor, scaled_model
from taxel.analyses.solves.crosstalk import profile, weights
from taxel.fem.readout import notch_in_time
from taxel.scene import Scene
from taxel.studies.bench.protocol import Frames
from taxel.studies.bench.rig import Rig
from taxel.schema import electrode_name

Input = Literal["step", "impulse", "chirp", "presses"]
INPUTS = ("step", "impulse", "chirp", "presses")


@dataclass
class Settings:
    input: Input = "step"
    seconds: float = 10.0
    amplitude: float | None = None     # N; default: the scene's load.force
    onset: float = 0.5                 # s: when the step, the first impulse or the chirp starts
    actuator_Hz: float = 150.0
    tau_spread: float = 0.3            # log-normal sigma of the time-constant factor
    gain_spread: float = 0.1
    noise_V: float = 1e-3              # white noise at the ADC, rms
    hum_V: tuple[float, float, float] = (5e-3, 1.5e-3, 0.5e-3)   # 50, 150, 250 Hz amplitudes at the ADC
    drift_V: float = 20e-3             # baseline drift, rms over the record
    force_noise_N: float = 5e-3        # load-cell noise, rms
    amplitude_spread: float = 0.0      # impulses: relative rms spread of each impulse's force (repeatability)
    seed: int = 0
    seq0: int = 0
    t0_us: int = 0
    crosstalk: bool = True             # FEM crosstalk weights (else none)
    model: Literal["lumped", "fem", "reduced"] = "lumped"
    between: float = 0.0               # presses: the fraction at random points of the array (else on taxel centres)
    modulus_scale: float = 1.0         # the silicone's true moduli over the scene's (the travel channel)
    silicone_loss: float | None = None # its true loss factor (default: the scene's)
    travel_noise_m: float = 1e-6       # the travel sensor's noise, rms


@dataclass
class Truth:
    """What the simulator knows and the capture does not (saved beside the stream)."""

    t: np.ndarray                      # (N,) s
    force_command: np.ndarray          # (N, P) N per press position (the taxels, then one per off-centre press)
    force: np.ndarray                  # (N,) N total on the sensor, after the actuator roll-off
    charge: np.ndarray                 # (N, taxels) C short-circuit charge into each taxel's chain
    clean_volts: np.ndarray            # (N, n) at the ADC, before noise and quantisation
    frames: Frames                     # as sent (before any corruption)
    params: dict = field(default_factory=dict)


def command(s: Settings, rate: float, n_press: int, centre: int, rng, spots=None) -> tuple[np.ndarray, np.ndarray, list]:
    """(t, F (N, n_press + extra), presses): the commanded force at each press position; with
    spots = (positions, pitch, edge) a "presses" record puts the fraction s.between of its presses
    at a uniform random point (x, y) in [-edge, (cols - 1) pitch + edge] x [-edge, (rows - 1) pitch + edge],
    each in an extra column of F, and the others on the taxels in turn (each taxel is pressed, and so
    can be calibrated); every press carries its xy_mm."""
    t = np.arange(int(round(s.seconds * rate))) / rate
    F = np.zeros((len(t), n_press))
    A = s.amplitude
    presses = []
    if s.input == "step":
        rise = 5e-3
        F[:, centre] = A * np.clip((t - s.onset) / rise, 0, 1)
        presses.append({"t": s.onset, "position": centre, "force_N": A, "rise_s": rise})
    elif s.input == "impulse":
        width = 10e-3
        for t0 in np.arange(s.onset, s.seconds - width, 2.0):
            on = (t >= t0) & (t < t0 + width)
            a = A * (1 + s.amplitude_spread * rng.standard_normal()) if s.amplitude_spread else A
            F[on, centre] += a * np.sin(np.pi * (t[on] - t0) / width)
            presses.append({"t": float(t0), "position": centre, "force_N": float(a), "width_s": width})
    elif s.input == "chirp":
        f0, f1, T, t0 = 0.0, 100.0, min(8.0, s.seconds - s.onset), s.onset
        tau = np.clip(t - t0, 0, T)
        phase = 2 * np.pi * (f0 * tau + (f1 - f0) * tau ** 2 / (2 * T))
        on = (t >= t0) & (t <= t0 + T)
        F[on, centre] = 0.5 * A * (1 - np.cos(phase[on]))
        presses.append({"t": t0, "position": centre, "force_N": A, "chirp_Hz": [f0, f1], "duration_s": T})
    else:
        t0, edge, extra, n_on = s.onset, 20e-3, [], 0
        while t0 < s.seconds - 0.5:
            pos, dur, amp = int(rng.integers(n_press)), float(rng.uniform(0.2, 0.4)), float(rng.uniform(0.3, 1.5) * A)
            x = np.clip(np.minimum(t - t0, t0 + dur - t) / edge, 0, 1)
            press = {"t": round(t0, 6), "position": pos, "force_N": amp, "duration_s": dur}
            if spots is not None:
                positions, pitch, e = spots
                rows, cols = max(r for r, _ in positions) + 1, max(c for _, c in positions) + 1
                if s.between:                          # the on-taxel presses go round the taxels in turn
                    pos = press["position"] = n_on % n_press
                xy = (positions[pos][1] * pitch, positions[pos][0] * pitch)
                if s.between and rng.random() < s.between:
                    xy = (rng.uniform(-e, (cols - 1) * pitch + e), rng.uniform(-e, (rows - 1) * pitch + e))
                    near = (int(np.clip(np.round(xy[1] / pitch), 0, rows - 1)),
                            int(np.clip(np.round(xy[0] / pitch), 0, cols - 1)))
                    press.update(position=positions.index(near), column=n_press + len(extra))
                    extra.append(amp * 0.5 * (1 - np.cos(np.pi * x)))
                else:
                    n_on += 1
                press["xy_mm"] = [float(1e3 * xy[0]), float(1e3 * xy[1])]
            if "column" not in press:
                F[:, pos] += amp * 0.5 * (1 - np.cos(np.pi * x))
            presses.append(press)
            t0 += dur + float(rng.uniform(0.2, 0.5))
        if extra:
            F = np.column_stack([F] + extra)
    return t, F, presses


def travel(lm, force: np.ndarray, rate: float) -> np.ndarray:
    """The top of the stack's displacement (m) under `force` (N): the lumped model's compliance
    X1 / F applied in the frequency domain (zero-padded FFT: no wrap-around)."""
    n = 2 * len(force)
    f = np.fft.rfftfreq(n, 1 / rate)
    return np.fft.irfft(np.fft.rfft(force, n) * compliance(lm, f), n)[:len(force)]


def conditioning_tf(cond, C_p: float, factor: float):
    """(num, den) of V/Q for one taxel's conditioning with its time constant scaled."""
    if cond.circuit == "open":
        return [-1.0 / C_p], [1.0], None
    if cond.circuit == "resistor":
        R = cond.R * factor
        return [-R, 0.0], [R * C_p, 1.0], R * C_p
    tf = cond.R_f * cond.C_f * factor
    num = [-tf / cond.C_f, 0.0]
    den = np.polymul([tf, 1.0], [cond.R_i * (C_p + cond.C_c), 1.0])
    return num, den, tf


def simulate(rig: Rig, scene: Scene, s: Settings) -> Truth:
    from taxel.analyses import lumped_model
    rng = np.random.default_rng(s.seed)
    rate = rig.sampling.rate
    chans = rig.ordered()
    taxel_ch = [c for c in chans if c.kind == "taxel"]
    taxels = [c.taxel for c in taxel_ch]
    arr = scene.array
    rows, cols = (arr.rows, arr.cols) if arr is not None else (1, 1)
    positions = [(r, c) for r in range(rows) for c in range(cols)]
    centre = positions.index(tuple(scene.load.taxel)) if tuple(scene.load.taxel) in positions else 0
    s.amplitude = s.amplitude if s.amplitude is not None else float(scene.load.force or 1.0)
    infl = None
    if s.input == "presses" and s.between and arr is not None:
        from taxel.analyses.surface.influence import influence
        infl = influence(scene)
    spots = (positions, infl.pitch, -float(infl.x[0])) if infl is not None else \
        (positions, arr.pitch, 0.0) if arr is not None else None
    t, Fcmd, presses = command(s, rate, len(positions), centre, rng, spots)
    sos = signal.butter(2, min(s.actuator_Hz, 0.45 * rate), fs=rate, output="sos")
    F = signal.sosfilt(sos, Fcmd, axis=0)
    model = lumped_model(scene)
    q_per_N = float((model.Q_sc([1.0])[0] / model.force).real)
    W1 = profile(scene) if s.crosstalk else np.eye(cols)
    if infl is None:
        Wm = np.array([weights(W1, p, taxels) for p in positions])      # (P, taxels)
    else:                                                               # influence functions of position
        xy = [(c * infl.pitch, r * infl.pitch) for r, c in positions]
        xy += [(1e-3 * p["xy_mm"][0], 1e-3 * p["xy_mm"][1]) for p in presses if "column" in p]
        Wm = np.array([infl.weights(q, taxels) for q in xy])
    gain = np.exp(s.gain_spread * rng.standard_normal(len(taxels)))
    tau_f = np.exp(s.tau_spread * rng.standard_normal(len(taxels)))
    if s.model == "fem":
        if s.input == "presses":
            raise ValueError("the FEM transient drives the scene's pressed taxel: use --input step, impulse or "
                             "chirp, or the lumped model for presses")
        Qe, names = fem_charges(scene, t, F[:, centre])
        pr = positions[centre][0]
        Q = np.zeros((len(t), len(taxels)))
        for k, (r, c) in enumerate(taxels):
            if electrode_name(r, c) in names:                       # modelled (3D, or the pressed row)
                Q[:, k] = Qe[:, names.index(electrode_name(r, c))]
            elif electrode_name(pr, c) in names and r < len(W1) and pr < len(W1):
                Q[:, k] = Qe[:, names.index(electrode_name(pr, c))] * W1[pr, r]
        Q *= gain[None, :]
    elif s.model == "reduced":
        if F.shape[1] > len(positions):
            raise ValueError("the reduced model takes presses on the taxels: use --between 0, or --model lumped")
        Q, C_p, q_per_N = reduced_charges(scene, t, F, positions, taxels, W1, s.crosstalk)
        Q *= gain[None, :]
    else:
        Q = q_per_N * (F @ Wm) * gain[None, :]
    C_p = C_p if s.model == "reduced" else model.C_p
    chains = rig.chains()
    clean = np.zeros((len(t), rig.n))
    per_taxel = {}
    for k, ch in enumerate(taxel_ch):
        cond = chains[ch.name]
        num, den, tau = conditioning_tf(cond, C_p, tau_f[k])
        b, a = signal.bilinear(num, den, fs=rate)
        v = signal.lfilter(b, a, Q[:, k])
        if cond.notch:
            v = notch_in_time(t, v[:, None], cond.readout())[:, 0]
        clean[:, ch.index] = v * ch.volts_per_si
        per_taxel[ch.name] = {"taxel": list(ch.taxel), "gain_factor": float(gain[k]), "tau_factor": float(tau_f[k]),
                              "tau_s": tau, "circuit": cond.circuit, "notch": cond.notch}
    force_ch = [c for c in chans if c.kind == "force"]
    for c in force_ch:
        clean[:, c.index] = F.sum(axis=1) * c.volts_per_si
    travel_ch = [c for c in chans if c.kind == "travel"]
    silicone = None
    if travel_ch:
        lm_true = scaled_model(scene, s.modulus_scale, s.silicone_loss)
        silicone = {"modulus_scale": s.modulus_scale, "loss_factor": loss_factor(lm_true, scene)}
        delta = travel(lm_true, F.sum(axis=1), rate)
        for c in travel_ch:
            clean[:, c.index] = delta * c.volts_per_si
    volts = clean.copy()
    for c in chans:
        if c.kind == "taxel":
            ph = rng.uniform(0, 2 * np.pi, 3)
            hum = sum(h * np.sin(2 * np.pi * f * t + p) for h, f, p in zip(s.hum_V, (50, 150, 250), ph))
            walk = np.cumsum(rng.standard_normal(len(t)))
            walk = signal.sosfilt(signal.butter(1, 0.5, fs=rate, output="sos"), walk)
            walk = s.drift_V * (walk - walk.mean()) / (walk.std() or 1.0)
            volts[:, c.index] += s.noise_V * rng.standard_normal(len(t)) + hum + walk
        elif c.kind == "travel":
            volts[:, c.index] += s.travel_noise_m * c.volts_per_si * rng.standard_normal(len(t))
        else:
            volts[:, c.index] += s.force_noise_N * c.volts_per_si * rng.standard_normal(len(t))
    lo, hi = rig.adc.code_limits
    counts = np.clip(np.round((volts - rig.adc.offset) / rig.adc.lsb), lo, hi).astype(np.int32)
    k = np.arange(len(t))
    jitter = np.round(rng.standard_normal(len(t))).astype(np.int64)
    seq = ((s.seq0 + k) % (1 << 16)).astype(np.uint16)
    t_us = ((s.t0_us + np.round(k * 1e6 / rate).astype(np.int64) + jitter) % (1 << 32)).astype(np.uint32)
    params = {"settings": asdict(s), "rate_Hz": rate, "q_per_N_C": q_per_N, "C_p_F": C_p,
              "crosstalk_W1": W1.tolist(), "positions": [list(p) for p in positions], "presses": presses,
              "taxels": per_taxel, "channels": rig.names, "clipped_samples": int(np.sum((counts == lo) | (counts == hi)))}
    params["model"] = s.model
    if silicone is not None:
        params["silicone"] = silicone
    return Truth(t, Fcmd, F.sum(axis=1), Q, clean, Frames(seq, t_us, counts), params)


def reduced_charges(scene: Scene, t, F, positions, taxels, W1, crosstalk: bool = True):
    """(Q (nt, taxels), C_p, q): the short-circuit charges of `taxels` under the forces F (nt,
    positions) by the scene's reduced model (see the module docstring), and the FEM's
    static capacitance (F) and charge per newton (C/N) of the pressed taxel."""
    from taxel.analyses.solves.reduced import cached
    from taxel.fem.dynamics import ports
    rm = cached(scene, "taxels", "charge")
    where = {electrode_name(r, c): (r, c) for r, c in positions}
    ins = [where[n.split(":", 1)[1]] for n in rm.input_names]
    outs = [n.split(":", 1)[1] for n in rm.output_names]
    Q = np.zeros((len(t), len(taxels)))
    row_model = len({r for r, _ in ins}) == 1 and len(set(r for r, _ in positions)) > 1   # 2D: one row
    press_rows = sorted({r for r, _ in positions}) if row_model else [None]
    for pr in press_rows:
        cols = [positions.index((pr, c) if row_model else (r, c)) for r, c in ins]
        U = F[:, cols]
        if not np.any(U):
            continue
        runs = [(U, None)] if crosstalk else [(np.where(np.arange(U.shape[1]) == j, U, 0.0), j)
                                              for j in range(U.shape[1]) if np.any(U[:, j])]
        for Uj, j in runs:
            Y = rm.simulate(t, Uj)
            for k, (r, c) in enumerate(taxels):
                name = electrode_name(ins[0][0], c) if row_model else electrode_name(r, c)
                if name not in outs or (j is not None and outs.index(name) != j):
                    continue
                w = 1.0 if not row_model else (W1[pr, r] if pr < len(W1) and r < len(W1) else 0.0)
                if not crosstalk and row_model and r != pr:
                    w = 0.0
                Q[:, k] += w * Y[:, outs.index(name)]
    pressed = electrode_name(*scene.load.taxel)
    V, Ci = ports(rm.red, [1e-3])
    C = np.linalg.inv(Ci[0]).real
    i = rm.red.names.index(pressed) if pressed in rm.red.names else 0
    j = next((k for k, n in enumerate(rm.input_names) if n.endswith(":" + pressed)), 0)
    return Q, float(C[i, i]), float(-(C @ V[0].real)[i, j])


def save_truth(truth: Truth, folder, extra: dict | None = None) -> None:
    """truth.npz (arrays) and truth.json (parameters) in `folder`."""
    import json
    from pathlib import Path
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    arrays = {"t": truth.t, "force_command": truth.force_command, "force": truth.force, "charge": truth.charge,
              "clean_volts": truth.clean_volts, "seq": truth.frames.seq, "t_us": truth.frames.t_us,
              "counts": truth.frames.counts}
    for k, v in (extra or {}).items():
        if isinstance(v, np.ndarray):
            arrays[k] = v
    np.savez_compressed(folder / "truth.npz", **arrays)
    meta = {**truth.params, **{k: v for k, v in (extra or {}).items() if not isinstance(v, np.ndarray)}}
    (folder / "truth.json").write_text(json.dumps(meta, indent=1))
