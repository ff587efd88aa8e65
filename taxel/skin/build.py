r"""A skin file from the FEM: `build(scene)` (taxel skin SCENE -o skin.npz).

Physics. The taxel array is linear (small strain, linear piezoelectricity, a linear
readout), so a normal force F(t) at a surface point p reaches taxel k through the
FEM's path from p to k. The skin factors that path as v_k(t) = h(s) [W_k(p) F(t)],
the spatial factor W_k(p) the static FEM's influence and the temporal factor h the
reference taxel's own dynamics through its readout. The array is taken, as in
taxel.analyses.solves.crosstalk and .influence, separable and alike in its two directions:
W_rc(x, y) = g_rc G_r(y) G_c(x), G_c = V_c(x) / V_c(x_c) the row's influence
functions from static FEM presses (a flat probe as wide as a taxel, pressed every
pitch / per_pitch; taxel.analyses.surface.influence), g_rc = S_r S_c / S_ref^2 the columns'
and rows' open-circuit sensitivities S relative to the reference (middle) taxel's.
The factoring is exact at low frequency (the quasi-static influence) and for presses
on the reference taxel; it assumes the other paths share h's frequency dependence,
which the pad's resonances (from 585 Hz in the coarse thesis 3 x 3 section) break at
fast edges between taxels (benchmarks/skin_accuracy.py measures it).
Every taxel shares h = the reference taxel's path from a force on its footprint to
its readout output, the reduced FEM model of `taxel reduce` (inputs: that taxel's
load; the causal loss law kept), so that at DC (open circuit) h = S_ref and a press at
a taxel's centre gives S_k F there (tests/test_skin_fem.py checks the whole against the
FEM transient at and between taxels). Assumed also: the force is normal (shear and the probe's contact mechanics are
outside: points and normal forces in, as simulators give them).

The interpolation error of G is measured: `checks` FEM presses halfway between knots
(in the row's first half; the row is mirror-symmetric), against the spline there.
h, the pressed path of the reduced model's state space (all its electrodes' modes,
185 states for the thesis 3 x 3 section), is cut to the modes that matter for this
path (`truncate`: modal truncation with the dropped modes' static parts kept, the
greedy order and measured-error stop of fem.dynamics.realize; python-control's
balanced truncation (balred, slycot), tried, lost the path at every order 4-16 on this
stiff SI-scaled system: relative errors 0.6-1.7) with its error measured over 0.01 Hz..1 / (2 dt); then it
is discretized at the simulator's step dt with scipy.signal.cont2discrete, first-
order hold (exact for forces linear between steps). Noise: the scene's chain
(taxel.analyses.solves.noise: per-source PSDs at the reference taxel's readout output, with a
rig its ADC) and the saturation (amplifier swing or ADC range). With a rig, the rig's
conditioning of the reference taxel's channel is the skin's readout chain (for h and
the noise alike), and the ADC's quantisation is left out of the PSDs: the runtime
quantizes.
"""

from __future__ import annotations

import hashlib
import json
from datetime import datetime, timezone

import numpy as np
from scipy import signal
from scipy.interpolate import CubicSpline

from taxel.scene import Scene, SceneError
from taxel.schema import electrode_name, to_data
from taxel.analyses.surface import influence as influence_mod
from taxel.analyses.solves import reduced
from taxel.analyses.solves.noise import chain as noise_chain
from taxel.analyses.solves.noise import noise as noise_budget
from taxel.analyses.solves.noise import with_readout
from taxel.analyses.solves.version import code_version
from taxel.skin.model import SkinModel


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("taxel")
    except PackageNotFoundError:
        return "unknown"


def check(scene: Scene, dt: float, per_pitch: int, checks: int) -> None:
    """Refuse what cannot make a skin, before any solve (SceneError, one line)."""
    a = scene.array
    if a is None:
        raise SceneError("taxel skin needs a taxel-array scene ([array]); use e.g. thesis-pzt-3x3-2d")
    if a.rows != a.cols:
        raise SceneError(f"array.rows = {a.rows}, array.cols = {a.cols}: the skin's influence is separable and "
                         "alike in both directions; use a square array (rows = cols)")
    if a.rows < 2:
        raise SceneError("array.rows = 1: a skin needs at least 2 x 2 taxels")
    if scene.load.kind == "probe" and scene.load.contact:
        raise SceneError("load.contact = true: the skin is the linear sensor; use load.kind = 'taxel'")
    if scene.model.silicone == "yeoh":
        raise SceneError("model.silicone = 'yeoh': the skin is the linear sensor; use model.silicone = 'linear'")
    if not (np.isfinite(dt) and 1e-6 <= dt <= 0.1):
        raise SceneError(f"--dt {dt:g}: the simulator's step in seconds, between 1e-6 and 0.1 (e.g. 0.001)")
    if per_pitch not in (2, 4, 8, 16):
        raise SceneError(f"--per-pitch {per_pitch}: use 2, 4, 8 or 16 FEM presses per pitch")
    if not 0 <= checks <= 16:
        raise SceneError(f"--checks {checks}: the number of FEM presses between knots, 0 to 16")


def press_voltages(scene: Scene, x: float) -> np.ndarray:
    """Open-circuit voltages (n,) of the middle row's taxels, a taxel-wide flat probe at x (m from column 0)."""
    from taxel.analyses import solve_static
    a = scene.array
    pitch, row, n = a.taxel_width + a.gap, a.rows // 2, a.cols
    c = int(np.clip(np.round(x / pitch), 0, n - 1))
    s = scene.replace(**{"load.kind": "probe", "load.taxel": [row, c], "load.radius": a.taxel_width / 2,
                         "load.offset": [float(x - c * pitch), 0.0], "load.profile": "flat"})
    v = solve_static(s).voltages()
    return np.array([v[electrode_name(row, k)] for k in range(n)])


def influence_check(scene: Scene, infl, checks: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, G_fem, G_spline) at `checks` points halfway between knots, spread over the row's first half."""
    L = (scene.array.cols - 1) * infl.pitch
    mids = 0.5 * (infl.x[1:] + infl.x[:-1])
    mids = mids[mids <= L / 2 + 1e-12]
    if checks == 0 or len(mids) == 0:
        z = np.zeros((0, infl.n))
        return np.zeros(0), z, z
    x = mids[np.unique(np.round(np.linspace(0, len(mids) - 1, checks)).astype(int))]
    centre = infl.sensitivity * float(scene.load.force or 1.0)
    G_fem = np.array([press_voltages(scene, xi) / centre for xi in x])
    return x, G_fem, infl.at(x)


def _response(lam, r, D, s) -> np.ndarray:
    return (r[None, :] / (s[:, None] - lam[None, :])).sum(axis=1) + D


def _merge(lam, r, rtol: float = 1e-5):
    """Poles equal within rtol merged into one with the summed residue (exact for equal
    poles: every taxel's electrode has the same RC pole, and eig splits such a cluster
    into eigenvectors whose residues are large and cancel)."""
    order = np.argsort(lam.real + 1e-3j * lam.imag)
    lam, r = lam[order], r[order]
    out_l, out_r = [lam[0]], [r[0]]
    for l_, r_ in zip(lam[1:], r[1:]):
        if abs(l_ - out_l[-1]) <= rtol * abs(l_):
            out_r[-1] += r_
        else:
            out_l.append(l_)
            out_r.append(r_)
    return np.array(out_l), np.array(out_r)


def truncate(A, B, C, D, band, tol: float = 3e-3, points: int = 300):
    """A SISO state space cut to its dominant modes (module docstring): (A, B, C, D) real,
    and the measured error max |h - h_full| / max |h_full| on `points` log-spaced
    frequencies over `band`."""
    lam, W = np.linalg.eig(A)
    r = (C @ W)[0] * np.linalg.solve(W, B)[:, 0]          # residues
    lam, r = _merge(lam, r)
    s = 2j * np.pi * np.geomspace(band[0], band[1], points)
    H = _response(lam, r, D[0, 0], s)
    scale = np.abs(H).max()
    drop_err = (r[None, :] * s[:, None] / (lam[None, :] * (s[:, None] - lam[None, :])))   # dropping i, static kept
    upper = lam.imag >= 0                                  # a conjugate pair counted once
    order = np.argsort(np.abs(drop_err).max(axis=0) / np.where(lam.imag > 0, 0.5, 1.0))
    order = [i for i in order if upper[i]]
    total, dropped = np.zeros(len(s), complex), []
    for i in order:
        members = [i] + ([int(np.argmin(np.abs(lam - lam[i].conj())))] if lam[i].imag > 0 else [])
        trial = total + drop_err[:, members].sum(axis=1)
        if np.abs(trial).max() > tol * scale:
            break
        total, dropped = trial, dropped + members
    keep = np.setdiff1d(np.arange(len(lam)), dropped)
    d = float((D[0, 0] - (r[dropped] / lam[dropped]).sum()).real)
    blocks, Bs, Cs = [], [], []
    for i in keep:
        if lam[i].imag < 0:
            continue
        if lam[i].imag > 0:
            sg, w = lam[i].real, lam[i].imag
            blocks.append(np.array([[sg, -w], [w, sg]]))
            Bs += [1.0, 0.0]
            Cs += [2 * r[i].real, -2 * r[i].imag]
        else:
            blocks.append(np.array([[lam[i].real]]))
            Bs.append(1.0)
            Cs.append(r[i].real)
    from scipy.linalg import block_diag
    Ar = block_diag(*blocks) if blocks else np.zeros((0, 0))
    Br, Cr, Dr = np.array(Bs)[:, None], np.array(Cs)[None, :], np.array([[d]])
    Hr = (Cr @ np.linalg.solve(s[:, None, None] * np.eye(len(Br)) - Ar, Br[None]))[:, 0, 0] + d
    return Ar, Br, Cr, Dr, float(np.abs(Hr - H).max() / scale)


def reference(scene: Scene) -> Scene:
    """The scene pressing its middle taxel's footprint (the reduced model's input)."""
    m = scene.array.rows // 2
    return scene.replace(**{"load.kind": "taxel", "load.taxel": [m, m], "load.force": 1.0})


def build(scene: Scene, dt: float = 1e-3, per_pitch: int = 8, checks: int = 4, rig=None) -> SkinModel:
    """The skin of a scene (module docstring)."""
    check(scene, dt, per_pitch, checks)
    a = scene.array
    m = a.cols // 2
    ref = reference(scene)
    if rig is not None:          # the rig's conditioning of the reference taxel's channel is the skin's chain
        ref = with_readout(ref, noise_chain(ref, rig, electrode_name(*ref.load.taxel)).readout)
    infl = influence_mod.influence(ref, per_pitch=per_pitch)
    spline = CubicSpline(infl.x, infl.G, axis=0)
    S = np.asarray(infl.sensitivity, float)
    gain = np.outer(S[:a.rows], S) / S[m] ** 2
    xc, G_fem, G_spl = influence_check(ref, infl, checks)
    err = float(np.max(np.abs(G_fem - G_spl))) if len(xc) else float("nan")
    rm = reduced.cached(ref, inputs="probe", output="readout")
    i, j = rm.pressed()
    ss = rm.state_space()
    A, B, C, D, cut = truncate(ss.A, ss.B[:, [j]], ss.C[[i], :], ss.D[[i]][:, [j]], (0.01, 0.5 / dt))
    Ad, Bd, Cd, Dd, _ = signal.cont2discrete((A, B, C, D), dt, method="foh")
    nr = noise_budget(ref, rig, band=(ref.analysis.f_min, max(0.5 / dt, 2 * ref.analysis.f_min)))
    # the runtime quantizes with the ADC itself: its quantisation is not also added as a noise source
    sources = {k: v for k, v in nr.psd.items() if not (rig is not None and k.startswith("ADC"))}
    adc = None
    if rig is not None:
        adc = {"bits": int(rig.adc.bits), "lo": float(rig.adc.range[0]), "hi": float(rig.adc.range[1]),
               "gain": float(next((c.volts_per_si for c in rig.ordered() if c.name == nr.electrode), 1.0)),
               "offset": float(rig.adc.offset)}
    data = to_data(scene)
    prov = {"scene": data, "scene_name": scene.name,
            "scene_sha256": hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest(),
            "taxel_version": _version(), "code_version": code_version(),
            "built": datetime.now(timezone.utc).isoformat(timespec="seconds"), "per_pitch": per_pitch,
            "rig": getattr(rig, "name", None), "fem_presses": int(infl.solves) + len(xc)}
    return SkinModel(
        rows=a.rows, cols=a.cols, pitch=float(infl.pitch), taxel_width=float(a.taxel_width), margin=float(a.margin),
        knots=np.asarray(infl.x, float), coef=np.asarray(spline.c, float), gain=gain, sensitivity=float(S[m]),
        dt=float(dt), Ad=Ad, Bd=Bd, Cd=Cd, Dd=Dd, A=A, B=B, C=C, D=D,
        noise_freqs=np.asarray(nr.freqs, float), noise_psd=np.array([np.asarray(v, float) for v in sources.values()]),
        noise_sources=list(sources), saturation=float(nr.saturation_output), adc=adc, influence_error=err,
        check_x=xc, check_G_fem=G_fem, check_G_spline=G_spl, reduction_error=float(rm.measured_error) + cut,
        readout=rm.readout_label, provenance=prov)
