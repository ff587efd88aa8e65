"""A labelled dataset of presses on a skin, for learning localization and force
estimation, and its baseline (the model-based estimator of taxel.measure).

`write(skin, path, presses, seed)` draws `presses` presses from numpy's default_rng(seed)
(the same seed and skin give the same file) and runs each through the skin's runtime
(taxel.skin.runtime, from rest, noise on unless noise=False) for `duration` seconds:

- position: the press's centre, uniform over the taxels' span [0, (cols - 1) pitch] x
  [0, (rows - 1) pitch] (m, the skin frame: x along the columns from taxel (0, 0));
- force: the peak normal force, uniform in [0.2, 2] N;
- history (the force's time course, peak 1): "step" (a 5 ms ramp at 20 ms, held),
  "impulse" (a 10 ms half-sine at 20 ms), "press" (50 ms ramp, 100 ms hold, 50 ms release);
- probe (how the force is spread, points with weights summing to 1): "point"; "flat"
  (a 2 mm-radius disc, uniform); "sphere" (a 1.5 mm-radius Hertzian patch,
  p ~ sqrt(1 - r^2 / a^2)); "edge" (an 8 mm line at a uniform angle).

HDF5 schema (format "taxel-skin-dataset/1"; N presses, T samples, R x C taxels):

    attrs   format, seed, dt (s), noise (bool), duration (s), scene_sha256, taxel_version
    t                 (T,)          s
    position          (N, 2)        m, the press's centre (x, y)
    force             (N,)          N, the peak normal force
    history           (N,)          str: step | impulse | press
    probe             (N,)          str: point | flat | sphere | edge
    probe_size        (N,)          m: 0 | disc radius | contact radius | line length
    angle             (N,)          rad, the edge's direction from x (0 for the others)
    force_history     (N, T)        N, the total normal force
    voltage           (N, T, R, C)  V, each taxel's readout output (noise, saturation, ADC as the skin's)
    skin              (bytes,)      uint8: the skin file (.npz) the voltages came from

Baseline (`baseline(path)`): per press, the readings are the taxels' voltages at the
sample where sum_k |v_k| peaks; the sensitivities S_k are calibrated (as on the bench)
by noise-free point presses of 1 N with the same history at every taxel's centre; the
estimate is studies.measured.localize.fit_press (the model-based estimator behind
taxel.measure.localize: least squares of V_k = S_k F G_r(y) G_c(x) on the skin's
influence functions). Scores: position error |(x, y) - position| (mm) and force error
100 % (F - force) / force, per probe and over all presses.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from taxel.skin.model import SkinModel
from taxel.skin.runtime import SkinRuntime

FORMAT = "taxel-skin-dataset/1"
HISTORIES = ("step", "impulse", "press")
PROBES = ("point", "flat", "sphere", "edge")
T0 = 0.02          # s, when a press starts


def history(kind: str, t: np.ndarray) -> np.ndarray:
    """The force's time course (peak 1) of a history kind at times t (s)."""
    s = t - T0
    if kind == "step":
        return np.clip(s / 0.005, 0, 1)
    if kind == "impulse":
        return np.where((s >= 0) & (s < 0.01), np.sin(np.pi * np.clip(s, 0, 0.01) / 0.01), 0.0)
    return np.clip(s / 0.05, 0, 1) * np.clip((0.2 - s) / 0.05, 0, 1)


def _sunflower(n: int) -> np.ndarray:
    """n points evenly over the unit disc (r, theta) (Vogel's spiral)."""
    k = np.arange(n) + 0.5
    return np.stack([np.sqrt(k / n), k * np.pi * (3 - np.sqrt(5))], axis=1)


def probe(kind: str, size: float, angle: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(offsets (k, 2) m, weights (k,) summing to 1) of a probe's contact."""
    if kind == "point":
        return np.zeros((1, 2)), np.ones(1)
    if kind == "edge":
        s = np.linspace(-size / 2, size / 2, 17)
        return np.stack([s * np.cos(angle), s * np.sin(angle)], axis=1), np.full(17, 1 / 17)
    rt = _sunflower(19)
    pts = size * rt[:, :1] * np.stack([np.cos(rt[:, 1]), np.sin(rt[:, 1])], axis=1)
    w = np.ones(19) if kind == "flat" else np.sqrt(np.clip(1 - rt[:, 0] ** 2, 0, None))
    return pts, w / w.sum()


SIZES = {"point": 0.0, "flat": 2e-3, "sphere": 1.5e-3, "edge": 8e-3}


def write(skin: SkinModel, path, presses: int = 200, seed: int = 0, duration: float = 0.3,
          noise: bool = True) -> Path:
    """Draw and run the presses (module docstring); write the HDF5 file."""
    import h5py
    if presses < 1:
        raise ValueError(f"--presses {presses}: at least 1")
    if not skin.dt * 10 <= duration <= 60:
        raise ValueError(f"--duration {duration:g}: between 10 steps ({10 * skin.dt:g} s) and 60 s")
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(duration / skin.dt))) * skin.dt
    L = np.array([(skin.cols - 1) * skin.pitch, (skin.rows - 1) * skin.pitch])
    pos = rng.uniform(0, 1, (presses, 2)) * L
    force = rng.uniform(0.2, 2.0, presses)
    hist = rng.choice(HISTORIES, presses)
    kinds = rng.choice(PROBES, presses)
    angle = np.where(kinds == "edge", rng.uniform(0, np.pi, presses), 0.0)
    size = np.array([SIZES[k] for k in kinds])
    rt = SkinRuntime(skin, noise=noise, seed=int(rng.integers(2 ** 62)))
    F = force[:, None] * np.array([history(h, t) for h in hist])
    V = np.zeros((presses, len(t), skin.rows, skin.cols))
    for i in range(presses):
        off, w = probe(kinds[i], size[i], angle[i])
        pts = pos[i] + off
        rt.reset()
        V[i] = rt.run(np.broadcast_to(pts, (len(t), *pts.shape)), F[i][:, None] * w)   # = a step per t
    buf = io.BytesIO()
    skin.save(buf)
    path = Path(path)
    with h5py.File(path, "w") as h:
        h.attrs.update({"format": FORMAT, "seed": seed, "dt": skin.dt, "noise": noise, "duration": duration,
                        "scene_sha256": skin.provenance.get("scene_sha256", ""),
                        "taxel_version": skin.provenance.get("taxel_version", "")})
        s = h5py.string_dtype()
        h["t"], h["position"], h["force"] = t, pos, force
        h.create_dataset("history", data=hist.astype(object), dtype=s)
        h.create_dataset("probe", data=kinds.astype(object), dtype=s)
        h["probe_size"], h["angle"], h["force_history"] = size, angle, F
        h.create_dataset("voltage", data=V, compression="gzip")
        h["skin"] = np.frombuffer(buf.getvalue(), dtype=np.uint8)
    return path


@dataclass
class Dataset:
    """A dataset file read back (the module docstring's schema)."""

    attrs: dict
    t: np.ndarray
    position: np.ndarray
    force: np.ndarray
    history: np.ndarray
    probe: np.ndarray
    probe_size: np.ndarray
    angle: np.ndarray
    force_history: np.ndarray
    voltage: np.ndarray
    skin: SkinModel


def read(path) -> Dataset:
    """A file written by `write`; ValueError (one line) for another."""
    import h5py
    try:
        with h5py.File(path, "r") as h:
            if h.attrs.get("format") != FORMAT:
                raise KeyError(f"format {h.attrs.get('format')!r}")
            d = {k: h[k][()] for k in ("t", "position", "force", "probe_size", "angle", "force_history", "voltage")}
            d.update({k: np.array(h[k].asstr()[()]) for k in ("history", "probe")})
            attrs, raw = dict(h.attrs), h["skin"][()].tobytes()
    except (OSError, KeyError) as exc:
        raise ValueError(f"{path}: not a skin dataset ({exc}); write one with taxel skin dataset SKIN.npz -o FILE.h5") \
            from None
    return Dataset(attrs=attrs, skin=SkinModel.load(io.BytesIO(raw)), **d)


def readings(v: np.ndarray) -> np.ndarray:
    """(N, taxels) the voltages at the sample where sum_k |v_k| peaks, per press; v (N, T, R, C)."""
    flat = v.reshape(v.shape[0], v.shape[1], -1)
    k = np.abs(flat).sum(axis=2).argmax(axis=1)
    return flat[np.arange(len(flat)), k]


def calibrate(skin: SkinModel, t: np.ndarray, kind: str) -> np.ndarray:
    """S_k (taxels,) V/N: noise-free readings of 1 N point presses with history `kind` at each taxel's centre."""
    rt = SkinRuntime(skin)
    F = history(kind, t)
    S = np.zeros(skin.taxels)
    for k, (x, y) in enumerate(skin.centres().reshape(-1, 2)):
        rt.reset()
        v = np.array([rt.step([[x, y]], [f]) for f in F])
        S[k] = readings(v[None])[0][k]
    return S


def baseline(data: Dataset) -> dict:
    """The model-based estimator's scores on a dataset (module docstring)."""
    from taxel.analyses.surface.influence import Influence
    from taxel.studies.measured.localize import fit_press
    sk = data.skin
    G = sk.influence(sk.knots)
    infl = Influence(sk.pitch, sk.knots, G)
    rows, cols = np.divmod(np.arange(sk.taxels), sk.cols)
    S = {h: calibrate(sk, data.t, h) for h in HISTORIES}
    v = readings(data.voltage)
    est = np.array([fit_press(v[i], S[data.history[i]], infl, rows, cols, float(data.force[i]))
                    for i in range(len(v))])
    pos_mm = 1e3 * np.hypot(*(est[:, :2] - data.position).T)
    force_pc = 100 * (est[:, 2] - data.force) / data.force

    def scores(sel):
        p, f = pos_mm[sel], force_pc[sel]
        return {"presses": int(sel.sum()), "position_error_mm_median": float(np.median(p)),
                "position_error_mm_rms": float(np.sqrt(np.mean(p ** 2))),
                "position_error_mm_p90": float(np.percentile(p, 90)),
                "force_error_pc_median_abs": float(np.median(np.abs(f))),
                "force_error_pc_rms": float(np.sqrt(np.mean(f ** 2)))}
    out = {"method": "model-based (taxel.measure: least squares on the FEM influence functions)",
           "all": scores(np.ones(len(v), bool))}
    out.update({k: scores(data.probe == k) for k in PROBES if (data.probe == k).any()})
    return out
