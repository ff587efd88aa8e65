r"""A skin file from the FEM: `build(scene)` (taxel skin SCENE -o skin.npz).

Physics. The taxel array is linear (small strain, linear piezoelectricity, a linear
readout), so a force f(t) at a surface point p reaches taxel k through the FEM's path
from p to k. The skin factors that path as v_k(t) = h(s) [sum_d W_kd(p) f_d(t)], the
spatial factor W the static FEM's influence (taxel.skin.spatial: from a 3D scene its
surface map, normal and shear, non-separable; from a 2D section the separable
normal-only influence of taxel.analyses.surface.influence, pressed by a taxel-wide
flat probe every pitch / per_pitch, with `checks` FEM presses between knots measuring
its interpolation) and the temporal factor h the reference (middle) taxel's own
dynamics through its readout, the reduced FEM model of `taxel reduce` (of the 2D
section for a 3D scene; inputs: that taxel's load; the causal loss law kept). The
factoring is exact at low frequency (the quasi-static influence) and for presses on
the reference taxel; it assumes the other paths share h's frequency dependence, which
the pad's resonances (from 585 Hz in the coarse thesis 3 x 3 section) break at fast
edges between taxels (benchmarks/skin_accuracy.py measures it). The linear silicone
only: the surface map has no probe correction for a Yeoh silicone yet (issue 54).

h, the pressed path through the scene's readout chain, is taxel.skin.readout's (for a
3D scene with its circuit on the 3D reference electrode's capacitance: the section's is
1 / 1.23 of it on the thesis PZT; its sweep target corrected alike): the
path up to the chain's per-electrode stages cut to its dominant modes, the stages
(charge amplifier, notch) multiplied in as poles and residues, every pole mapped to
e^(l dt), first-order hold; its error against the solver's sweep of the same path
(`dynamics_error`) and the band where it holds 1 % and 1 degree (`band`) are stored. Noise: the scene's chain
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

from taxel.scene import Scene, SceneError
from taxel.schema import electrode_name, to_data
from taxel.analyses.surface import influence as influence_mod
from taxel.analyses.solves import reduced
from taxel.analyses.solves.noise import chain as noise_chain
from taxel.analyses.solves.noise import noise as noise_budget
from taxel.analyses.solves.noise import with_readout
from taxel.analyses.solves.version import code_version
from taxel.skin import readout as readout_mod
from taxel.skin import spatial
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
    if a.rows != a.cols and scene.model.type != "3d":
        raise SceneError(f"array.rows = {a.rows}, array.cols = {a.cols}: a skin from a 2D section is separable and "
                         "alike in both directions; use a square array (rows = cols) or model.type = '3d'")
    if a.rows < 2:
        raise SceneError("array.rows = 1: a skin needs at least 2 x 2 taxels")
    if scene.load.kind == "probe" and scene.load.contact:
        raise SceneError("load.contact = true: the skin is the linear sensor; use load.kind = 'taxel'")
    if scene.model.silicone == "yeoh":
        raise SceneError("model.silicone = 'yeoh': the skin is the linear sensor (the surface map has no probe "
                         "correction for Yeoh yet); use model.silicone = 'linear'")
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
    pitch, row, n = a.pitch, a.rows // 2, a.cols
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


def reference(scene: Scene) -> Scene:
    """The scene pressing its middle taxel's footprint (the reduced model's input)."""
    m = scene.array.rows // 2
    return scene.replace(**{"load.kind": "taxel", "load.taxel": [m, m], "load.force": 1.0})


def build(scene: Scene, dt: float = 1e-3, per_pitch: int = 8, checks: int = 4, rig=None,
          surface_map=None) -> SkinModel:
    """The skin of a scene (module docstring). A 3D scene: the spatial model from its surface
    map (`surface_map`, else built: one 3D solve per electrode class), h from its 2D section."""
    check(scene, dt, per_pitch, checks)
    a = scene.array
    m = a.cols // 2
    three_d = scene.model.type == "3d"
    section = scene.replace(**{"model.type": "plane_strain"}) if three_d else scene
    ref = reference(section)
    if rig is not None:          # the rig's conditioning of the reference taxel's channel is the skin's chain
        ref = with_readout(ref, noise_chain(ref, rig, electrode_name(*ref.load.taxel)).readout)
    rm = reduced.cached(ref, inputs="probe", output="readout")
    C_p = None
    if three_d:                  # the 3D map, and the 3D reference electrode's capacitance for the circuit
        from taxel.analyses.surface import surface_map as smap
        mp = surface_map if surface_map is not None else smap.build(scene)
        k = mp.index(electrode_name(a.rows - 1 - m, m))
        C_p = float(mp.capacitance[k, k])
    h, cut, electrical = readout_mod.path(rm, (0.01, 0.5 / dt), C_p=C_p)
    A, B, C, D = h.state_space()
    disc = readout_mod.discretize(h, dt, lambda f: readout_mod.sweep(rm, f) * electrical.frf_hz(f))
    Ad, Bd, Cd, Dd = disc.state_space()
    pitch = a.pitch
    if three_d:
        from taxel.fem import dynamics
        V, Ci = dynamics.ports(rm.red, [1e-3])
        i, _ = rm.pressed()
        voltage = rm.readout.circuit == "open"
        per_newton = float(V[0, i, 0].real) if voltage else float((-np.linalg.solve(Ci[0], V[0])[i, 0]).real)
        sp = spatial.from_map(mp, a.rows, a.cols, pitch, a.taxel_width, per_newton, voltage)
        ref_q = spatial.footprint_average(mp, electrode_name(a.rows - 1 - m, m), a.taxel_width / 2)
        S_ref = float(-(-np.linalg.solve(mp.capacitance, ref_q[:, 2]))[mp.index(electrode_name(a.rows - 1 - m, m))])
    else:
        infl = influence_mod.influence(ref, per_pitch=per_pitch)
        xc, G_fem, _ = influence_check(ref, infl, checks)
        sp = spatial.separable(a.rows, a.cols, float(infl.pitch), infl, per_pitch, xc, G_fem)
        S_ref = float(np.asarray(infl.sensitivity, float)[m])
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
            "rig": getattr(rig, "name", None), "fem_solves": sp.solves + len(sp.check_points) * (not three_d)}
    return SkinModel(
        rows=a.rows, cols=a.cols, pitch=float(pitch), taxel_width=float(a.taxel_width), margin=float(a.margin),
        grid_x=sp.grid_x, grid_y=sp.grid_y, influence=sp.W, spatial=sp.label, sensitivity=S_ref,
        dt=float(dt), Ad=Ad, Bd=Bd, Cd=Cd, Dd=Dd, A=A, B=B, C=C, D=D,
        noise_freqs=np.asarray(nr.freqs, float), noise_psd=np.array([np.asarray(v, float) for v in sources.values()]),
        noise_sources=list(sources), saturation=float(nr.saturation_output), adc=adc, influence_error=sp.error,
        check_points=sp.check_points, check_fem=sp.check_source,
        check_model=spatial.bilinear(sp.grid_x, sp.grid_y, sp.W, sp.check_points)[..., 2] if len(sp.check_points)
        else np.zeros((0, a.rows * a.cols)),
        reduction_error=float(rm.measured_error) + cut, dynamics_error=disc.error + float(rm.measured_error),
        band=disc.band, readout=rm.readout_label, provenance=prov)
