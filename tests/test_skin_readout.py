"""The skin's readout dynamics (taxel.skin.readout) against the solver's.

Fast: the per-electrode stages against fem.readout's closed forms (sign included), and
a held press through a lumped taxel's charge amplifier and resistor decaying with the
circuit's time constant. Slow: a 4 x 4 PVDF skin with a user's charge amplifier
(100 pF, 1 Gohm: tau 0.1 s) and with a 500 Mohm resistor, stepped by the runtime with
sampled sinusoids, against the solver's own frequency sweep of the same scene
(taxel.solve, analysis.type = "frequency"), 1 % and 1 degree from 1 Hz to the skin's
band; and a held press against the FEM transient (issue 55)."""

import numpy as np
import pytest

import taxel
from taxel.fem.dynamics import PortResponse
from taxel.fem.readout import Readout, readout
from taxel.schema import electrode_name
from taxel.skin import readout as sr
from taxel.skin.model import SkinModel
from taxel.skin.runtime import SkinRuntime

DT = 1e-3
CA = Readout("charge_amplifier", C_f=100e-12, R_f=1e9)


def test_stages_are_the_solvers_circuits():
    f = np.geomspace(0.1, 1e4, 40)
    w = 2 * np.pi * f
    Cp, q = 1.3e-9, -2.0e-11                                  # F; short-circuit charge per newton, C/N
    r = Readout("charge_amplifier", C_f=100e-12, R_f=1e9, notch=True)
    h = sr.Poles(np.zeros(0, complex), np.zeros(0, complex), q).times(sr.stages(r, Cp))
    V_oc = np.full((len(f), 1), -q / Cp)                      # Q_sc = -C V_oc
    want = readout(PortResponse(f, V_oc, np.full((len(f), 1, 1), 1 / Cp), ["t"], "closed form", 0.0), r)[:, 0]
    assert np.abs(h.frf(1j * w) - want).max() < 1e-9 * np.abs(want).max()


def _skin(h: sr.Poles) -> SkinModel:
    """A 2 x 2 skin whose every taxel has the readout dynamics h (W_z = -1 everywhere)."""
    d = sr.discretize(h, DT, h.frf_hz)
    Ad, Bd, Cd, Dd = d.state_space()
    A, B, C, D = h.state_space()
    g = np.array([-0.02, 0.0, 0.02])
    W = np.zeros((4, 3, 3, 3))
    W[:, 2] = -1.0
    f = np.geomspace(1, 1000, 5)
    return SkinModel(rows=2, cols=2, pitch=7e-3, taxel_width=4e-3, margin=3e-3, grid_x=g, grid_y=g, influence=W,
                     spatial="uniform", sensitivity=1.0, dt=DT, Ad=Ad, Bd=Bd, Cd=Cd, Dd=Dd, A=A, B=B, C=C, D=D,
                     noise_freqs=f, noise_psd=np.zeros((1, 5)), noise_sources=["none"], saturation=np.inf, adc=None,
                     influence_error=0.0, check_points=np.zeros((0, 2)), check_fem=np.zeros((0, 4)),
                     check_model=np.zeros((0, 4)), reduction_error=0.0, readout="test", dynamics_error=d.error,
                     band=d.band)


@pytest.mark.parametrize("circuit", ["charge_amplifier", "resistor"])
def test_a_held_press_decays_with_the_circuits_time_constant(circuit):
    q, Cp = -2.0e-11, 1.3e-9
    if circuit == "charge_amplifier":
        h = sr.Poles(np.zeros(0, complex), np.zeros(0, complex), q).times(sr.stages(CA, Cp))
        tau = CA.R_f * CA.C_f
    else:                                       # V / Q_sc = -s R / (1 + s R C): tau = R C
        R = 500e6
        h = sr.Poles.rational([-R * q, 0.0], [R * Cp, 1.0])
        tau = R * Cp
    sk = _skin(h)
    assert sk.band > 0.1 / DT and sk.dynamics_error < 0.01
    n = 1000
    F = np.minimum(np.arange(n) / 5, 1.0)                      # a 5 ms ramp to 1 N, held
    v = SkinRuntime(sk).run(np.zeros((n, 1, 2)), F[:, None])[:, 0, 0]
    t = np.arange(n) * DT
    late = t > 0.05
    slope = np.polyfit(t[late], np.log(np.abs(v[late])), 1)[0]
    assert slope == pytest.approx(-1 / tau, rel=1e-3)
    # the solver's sign: the charge amplifier gives -Q_sc / C_f, the resistor -Q_sc R s
    assert np.sign(v[10]) == np.sign(-q)


# --- the user's design of issue 55, against the solver (slow) ---

SCENE = {"array.rows": 4, "array.cols": 4, "mesh.size": "1 mm", "mesh.piezo_size": "0.2 mm"}
CIRCUITS = {"charge_amplifier": {"readout.circuit": "charge_amplifier", "readout.C_f": 100e-12, "readout.R_f": 1e9},
            "resistor": {"readout.circuit": "resistor", "readout.R": 500e6}}


@pytest.fixture(scope="module", params=list(CIRCUITS))
def built(request):
    from taxel.skin.build import build, reference
    s = taxel.load("thesis-pvdf-3x3-2d").replace(**SCENE, **CIRCUITS[request.param])
    return request.param, s, reference(s), build(s, dt=DT, checks=0)


@pytest.mark.slow
def test_the_skin_is_the_solvers_sweep(built):
    _, _, ref, sk = built
    assert sk.band >= 0.1 / DT
    fr = taxel.solve(ref.replace(**{"analysis.type": "frequency", "analysis.f_min": 1.0, "analysis.f_max": sk.band,
                                    "analysis.points": 10}))
    H = fr.output[:, fr.names.index(electrode_name(2, 2))]
    c = 2 * sk.pitch
    for f, want in zip(fr.freqs, H):
        n = int(max(3.0, 12 / f) / DT)
        t = np.arange(n) * DT
        v = SkinRuntime(sk).run(np.tile([[c, c]], (n, 1, 1)), np.sin(2 * np.pi * f * t)[:, None])[:, 2, 2]
        k = n // 2                                              # the steady state: the slowest pole has decayed
        got = np.linalg.lstsq(np.column_stack([np.sin(2 * np.pi * f * t[k:]), np.cos(2 * np.pi * f * t[k:])]),
                              v[k:], rcond=None)[0] @ [1, 1j]
        assert abs(abs(got / want) - 1) < 0.01, f
        assert abs(np.degrees(np.angle(got / want))) < 1.0, f


@pytest.mark.slow
def test_a_held_press_is_the_fem_transients(built):
    circuit, _, ref, sk = built
    tr = taxel.solve(ref.replace(**{"analysis.type": "transient", "analysis.input": "step", "analysis.dt": DT,
                                    "analysis.duration": 0.6 if circuit == "charge_amplifier" else 0.3,
                                    "analysis.rise": 0.005}))
    V = np.array(tr.output)[:, tr.names.index(electrode_name(2, 2))]
    c = 2 * sk.pitch
    v = SkinRuntime(sk).run(np.tile([[c, c]], (len(tr.t), 1, 1)), tr.force[:, None])[:, 2, 2]
    assert np.abs(v - V).max() < 0.03 * np.abs(V).max()         # the FEM's own Newmark error at dt = 1 ms: ~3 %
    assert np.abs(v[-1]) < 0.1 * np.abs(v).max()                # decayed: no rising output
