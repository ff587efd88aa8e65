"""The skin's runtime and file (fast): a first-order skin with a closed-form step
response, superposition, the seeded noise, the file round trip, the light import,
and the CLI's bad input."""

import json
import subprocess
import sys

import numpy as np
import pytest
from scipy import signal
from scipy.interpolate import CubicSpline

from taxel.cli import main
from taxel.skin.model import SkinModel
from taxel.skin.runtime import SkinRuntime

TAU, S, DT = 0.05, 0.8, 1e-3


def first_order_skin(noise_psd=0.0, saturation=np.inf, adc=None) -> SkinModel:
    """A 3 x 3 skin whose h(s) = S / (1 + s tau) and whose influence is a tent of one pitch."""
    pitch = 7e-3
    x = np.linspace(-pitch, 3 * pitch, 33)
    G = np.stack([np.clip(1 - np.abs(x - c * pitch) / pitch, 0, None) for c in range(3)], axis=1)
    sp = CubicSpline(x, G, axis=0)
    A, B, C, D = np.array([[-1 / TAU]]), np.array([[1.0]]), np.array([[S / TAU]]), np.array([[0.0]])
    Ad, Bd, Cd, Dd, _ = signal.cont2discrete((A, B, C, D), DT, method="foh")
    f = np.geomspace(1, 1000, 50)
    return SkinModel(3, 3, pitch, 4e-3, 3e-3, x, sp.c, np.ones((3, 3)), S, DT, Ad, Bd, Cd, Dd, A, B, C, D,
                     f, np.full((1, 50), noise_psd), ["white"], saturation, adc, 0.0, np.zeros(0),
                     np.zeros((0, 3)), np.zeros((0, 3)), 0.0, "test", {"scene_name": "test"})


def test_step_response_is_the_closed_form():
    rt = SkinRuntime(first_order_skin())
    t = np.arange(0, 0.3, DT)
    F = np.minimum(t / 0.01, 1.0)                     # a ramp to 1 N over 10 ms, then held
    v = np.array([rt.step([[7e-3, 7e-3]], [f])[1, 1] for f in F])
    # exact response of S / (1 + s tau) to the ramp-and-hold (first-order hold is exact for it)
    exact = S * np.where(t <= 0.01, (t - TAU * (1 - np.exp(-t / TAU))) / 0.01,
                         1 - TAU / 0.01 * (np.exp(-(t - 0.01) / TAU) - np.exp(-t / TAU)))
    assert np.abs(v - exact).max() < 1e-9


def test_superposition_and_influence():
    rt = SkinRuntime(first_order_skin())
    a = rt.loads([[3.5e-3, 7e-3]], [2.0])
    b = rt.loads([[7e-3, 10e-3]], [1.0])
    both = rt.loads([[3.5e-3, 7e-3], [7e-3, 10e-3]], [2.0, 1.0])
    assert np.allclose(both, a + b)
    assert a.reshape(3, 3)[1] == pytest.approx([1.0, 1.0, 0.0])      # halfway: half of 2 N on each neighbour


def test_noise_is_seeded_and_has_the_band_rms():
    sk = first_order_skin(noise_psd=1e-8)
    v1 = SkinRuntime(sk, noise=True, seed=3).run(np.zeros((2000, 1, 2)), np.zeros((2000, 1)))
    v2 = SkinRuntime(sk, noise=True, seed=3).run(np.zeros((2000, 1, 2)), np.zeros((2000, 1)))
    assert np.array_equal(v1, v2)
    assert v1.std() == pytest.approx(np.sqrt(1e-8 * (500 - 1)), rel=0.05)


def test_saturation_and_adc():
    adc = {"bits": 8, "lo": -1.0, "hi": 1.0, "gain": 1.0, "offset": 0.0}
    rt = SkinRuntime(first_order_skin(saturation=0.5, adc=adc))
    v = rt.run(np.full((500, 1, 2), 7e-3), np.ones((500, 1)))
    assert v.max() == pytest.approx(0.5, abs=2 / 256)
    codes = (v + 1.0) / (2 / 256)                     # lo = -1 V, 8 bits over 2 V
    assert np.allclose(codes, np.round(codes)) and codes.min() >= 0 and codes.max() <= 255


def test_file_round_trip(tmp_path):
    sk = first_order_skin(adc={"bits": 16, "lo": -10.0, "hi": 10.0, "gain": 1.0, "offset": 0.0})
    back = SkinModel.load(sk.save(tmp_path / "skin.npz"))
    assert np.array_equal(back.Ad, sk.Ad) and np.array_equal(back.coef, sk.coef) and back.adc == sk.adc
    assert not np.isfinite(back.saturation)
    (tmp_path / "other.npz").write_bytes(b"not a file")
    with pytest.raises(ValueError, match="not a skin file"):
        SkinModel.load(tmp_path / "other.npz")


def test_runtime_refuses_another_step():
    with pytest.raises(ValueError, match="discretized at"):
        SkinRuntime(first_order_skin(), dt=2e-3)


def test_runtime_imports_numpy_only():
    code = ("import sys; from taxel.skin.runtime import SkinRuntime; import json; "
            "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
            "('gmsh', 'skfem', 'mujoco', 'scipy', 'pydantic', 'h5py', 'control') or m.startswith('taxel.fem') "
            "or m.startswith('taxel.analyses'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert json.loads(out) == []


@pytest.mark.parametrize("args, words", [
    (["skin", "thesis-pzt-3x3-2d", "-o", "skin.txt"], "use FILE.npz"),
    (["skin", "thesis-pzt-3x3-2d", "-o", "skin.npz", "--dt", "0"], "argument --dt: give a number > 0"),
    (["skin", "thesis-pzt-single-2d", "-o", "skin.npz"], "array.rows"),
    (["skin", "thesis-pzt-3x3-2d", "-o", "skin.npz", "--per-pitch", "3"], "--per-pitch 3"),
    (["skin", "thesis-pzt-3x3-2d", "-o", "skin.npz", "--presses", "3"], "--presses: not an option of taxel skin SCENE"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and "\n" not in err and "Traceback" not in err
    assert not list(tmp_path.iterdir())


def test_build_skin_is_the_function_and_taxel_skin_the_package():
    code = ("import taxel, taxel.skin.runtime, taxel.skin.model; import inspect; "
            "print(inspect.isfunction(taxel.build_skin), taxel.build_skin.__module__, inspect.ismodule(taxel.skin))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["True", "taxel.api", "True"]


def resonant_skin(Ad=None) -> SkinModel:
    """A 2 x 3 skin with unequal gains whose h(s) has a real pole and a resonance (complex
    poles: the diagonal form's conjugate pairs); or the given Ad (with Bd, Cd of ones)."""
    sk = first_order_skin()
    A, B, C, D = signal.tf2ss([0.3, 40.0, 9e4], np.polymul([1, 60.0, 9e4], [1, 25.0]))
    Ad, Bd, Cd, Dd, _ = (signal.cont2discrete((A, B, C, D), DT, method="foh") if Ad is None else
                         (Ad, np.ones((len(Ad), 1)), np.ones((1, len(Ad))), np.array([[0.1]]), None))
    sk.rows, sk.cols, sk.gain = 2, 3, np.array([[1.0, 0.9, 1.2], [0.8, 1.1, 1.0]])
    sk.Ad, sk.Bd, sk.Cd, sk.Dd, sk.A, sk.B, sk.C, sk.D = Ad, Bd, Cd, Dd, A, B, C, D
    return sk


def direct(sk, P, F) -> np.ndarray:
    """The skin by scipy alone: the loads from the scipy spline, each taxel through dlsim."""
    sp = CubicSpline(sk.knots, np.stack([np.clip(1 - np.abs(sk.knots - c * sk.pitch) / sk.pitch, 0, None)
                                         for c in range(3)], axis=1), axis=0)
    lo, hi = sk.knots[0], sk.knots[-1]
    gx, gy = sp(np.clip(P[..., 0], lo, hi))[..., :sk.cols], sp(np.clip(P[..., 1], lo, hi))[..., :sk.rows]
    U = np.einsum("km,kmr,kmc->krc", F, gy, gx) * sk.gain
    sys_ = (sk.Ad, sk.Bd, sk.Cd, sk.Dd, DT)
    V = np.stack([signal.dlsim(sys_, U[:, r, c])[1][:, 0] for r in range(sk.rows) for c in range(sk.cols)], axis=1)
    return V.reshape(len(F), sk.rows, sk.cols)


@pytest.mark.parametrize("Ad", [None, np.array([[0.9, 1.0], [0.0, 0.9]])], ids=["diagonal", "defective: dense"])
def test_step_run_and_envs_are_the_direct_simulation(Ad):
    sk = resonant_skin(Ad)
    rng = np.random.default_rng(4)
    P, F = rng.uniform(-9e-3, 23e-3, (300, 3, 2)), rng.uniform(0, 1, (300, 3))   # some points off the knots
    ref = direct(sk, P, F)
    rt = SkinRuntime(sk)
    assert rt.diagonal == (Ad is None)
    peak = np.abs(ref).max()
    assert np.abs(np.array([rt.step(p, f) for p, f in zip(P, F)]) - ref).max() < 1e-10 * peak
    rt = SkinRuntime(sk)
    run = np.concatenate([rt.run(P[:100], F[:100]), rt.run(P[100:], F[100:])])   # the state carries over
    assert np.abs(run - ref).max() < 1e-10 * peak
    envs = SkinRuntime(sk, envs=2, check=False)        # env 0 these contacts, env 1 half the forces
    both = np.array([envs.step(np.stack([p, p]), np.stack([f, f / 2])) for p, f in zip(P, F)])
    assert np.abs(both[:, 0] - ref).max() < 1e-10 * peak and np.abs(both[:, 1] - ref / 2).max() < 1e-10 * peak


def test_run_draws_the_noise_of_the_steps():
    sk = first_order_skin(noise_psd=1e-8)
    P, F = np.full((700, 1, 2), 7e-3), np.ones((700, 1))      # 700 steps: across blocks of 256 draws
    a = SkinRuntime(sk, noise=True, seed=5)
    b = SkinRuntime(sk, noise=True, seed=5).run(P, F)
    assert np.abs(np.array([a.step(p, f) for p, f in zip(P, F)]) - b).max() < 1e-12


@pytest.mark.parametrize("points, forces, words", [
    ([[7e-3, 7e-3]], [1.0, 2.0], "give points (m, 2) m and forces (m,) N"),
    ([7e-3, 7e-3], [1.0], "give points (m, 2) m"),
    ([[7e-3, 7e-3]], [np.nan], "not finite"),
])
def test_step_refuses_bad_contacts_in_one_line(points, forces, words):
    with pytest.raises(ValueError, match=r"^[^\n]*$") as err:
        SkinRuntime(first_order_skin()).step(points, forces)
    assert words in str(err.value)
