"""The skin's runtime against the FEM (slow: FEM presses and transients on a coarse 2D mesh).

- the runtime vs the FEM transient (taxel.solve, analysis.type = "transient") of a
  taxel-wide flat probe at the middle taxel's centre for a step, an impulse and a chirp:
  max |v_runtime - v_FEM| over the row's taxels and time within 2 % of the FEM's peak
  (at dt = 0.25 ms: at 1 ms the FEM's own Newmark error at the step's 5 ms rise and the
  impulse's 10 ms half-sine is 2-3 %, measured);
- a chirp between two taxels (the crosstalk through the influence) within 2 %;
- the influence spline at points halfway between its knots vs FEM presses there.
"""

import numpy as np
import pytest

import taxel
from skin_transient import COARSE, fem_and_runtime
from taxel.skin.build import build, press_voltages
from taxel.skin.runtime import SkinRuntime

pytestmark = pytest.mark.slow

HISTORIES = {"step": {"analysis.duration": 0.2, "analysis.rise": 0.005},
             "impulse": {"analysis.duration": 0.1, "analysis.width": 0.01},
             "chirp": {"analysis.duration": 0.5, "analysis.f0": 0.0, "analysis.f1": 100.0}}


@pytest.fixture(scope="module")
def scene():
    return taxel.load("thesis-pzt-3x3-2d").replace(**COARSE)


@pytest.mark.parametrize("history", ["step", "impulse", "chirp"])
def test_runtime_matches_fem_transient_on_a_taxel(scene, history):
    sk = build(scene, dt=2.5e-4, checks=0)
    v, V = fem_and_runtime(scene, sk, sk.pitch, history, HISTORIES)
    assert np.abs(v - V).max() < 0.02 * np.abs(V).max()


def test_runtime_matches_fem_chirp_between_taxels(scene):
    sk = build(scene, dt=1e-3, checks=0)
    v, V = fem_and_runtime(scene, sk, 1.5 * sk.pitch, "chirp", HISTORIES)
    assert np.abs(v - V).max() < 0.02 * np.abs(V).max()


def test_influence_between_knots_matches_fem_presses(scene):
    sk = build(scene, dt=1e-3, checks=2)
    assert len(sk.check_x) == 2 and sk.influence_error == pytest.approx(
        np.abs(sk.check_G_fem - sk.check_G_spline).max())
    assert sk.influence_error < 0.01                  # of G's peak (1)
    # an independent FEM press a quarter of the way between two knots, through the runtime
    x = sk.knots[5] + 0.25 * (sk.knots[6] - sk.knots[5])
    ref = scene.replace(**{"load.kind": "taxel", "load.taxel": [1, 1], "load.force": 1.0})
    V = press_voltages(ref, x)                                 # open-circuit volts per newton
    rt = SkinRuntime(sk)
    u = rt.loads([[x, sk.pitch]], [1.0]).reshape(3, 3)[1]   # the force each taxel of the row sees
    assert np.abs(u * sk.sensitivity - V).max() < 0.01 * np.abs(V).max()


def test_a_rig_gives_its_chain_and_adc(scene):
    from taxel.studies.bench.rig import load_rig
    sk = taxel.build_skin(scene, dt=1e-3, checks=0, rig="thesis-bench")
    rig = load_rig("thesis-bench")
    assert sk.adc["bits"] == rig.adc.bits and sk.adc["lo"] == rig.adc.range[0]
    assert "charge-amplifier" in sk.readout                      # the rig's conditioning, not the scene's resistor
    assert not any(s.startswith("ADC") for s in sk.noise_sources)  # the runtime quantizes; not counted twice
    rt = SkinRuntime(sk)
    v = rt.run(np.tile([[sk.pitch, sk.pitch]], (50, 1, 1)), np.minimum(np.arange(50) / 10, 1.0)[:, None])
    lsb = (rig.adc.range[1] - rig.adc.range[0]) / 2 ** rig.adc.bits
    codes = (v * sk.adc["gain"] + sk.adc["offset"] - sk.adc["lo"]) / lsb
    assert np.allclose(codes, np.round(codes), atol=1e-6)
