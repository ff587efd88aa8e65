"""The skin for learning (fast, no FEM): per-environment reset and randomization, and
noise with the scene's spectrum (not white)."""

import numpy as np
import pytest
from scipy import signal

from taxel.skin.runtime import Randomization, SkinRuntime
from test_skin import DT, S, TAU, first_order_skin


def test_reset_clears_only_the_environments_named():
    rt = SkinRuntime(first_order_skin(), envs=3)
    P, F = np.full((3, 1, 2), 7e-3), np.ones((3, 1))
    for _ in range(50):
        v = rt.step(P, F)
    rt.reset([1])
    after = rt.step(P, np.zeros((3, 1)))
    assert after[1, 1, 1] == 0.0 and after[0, 1, 1] > 0.5 * v[0, 1, 1] and after[2, 1, 1] == after[0, 1, 1]
    rt.reset(np.array([True, False, False]))
    assert rt.step(P, np.zeros((3, 1)))[0, 1, 1] == 0.0


def test_randomization_draws_gain_spread_and_time_constant_per_environment():
    E = 400
    rt = SkinRuntime(first_order_skin(), envs=E, seed=1, randomization=Randomization(gain=0.1, spread=0.05, tau=0.2))
    P, F = np.full((E, 1, 2), 7e-3), np.ones((E, 1))
    v = np.array([rt.step(P, F)[:, 1, 1] for _ in range(400)])          # a held 1 N press on taxel (1, 1)
    final = v[-1] / S                                                  # the gain's draws (h(0) = S)
    assert np.std(np.log(final)) == pytest.approx(np.hypot(0.1, 0.05), rel=0.15)
    # each environment's time constant: the step response's 63 % time, log-normal with sigma 0.2 about TAU
    t63 = (np.argmax(v >= 0.632 * v[-1], axis=0) + 0.5) * DT
    assert np.std(np.log(t63)) == pytest.approx(0.2, rel=0.2)
    assert np.exp(np.mean(np.log(t63))) == pytest.approx(TAU, rel=0.05)
    g_before = rt.g[5].copy()
    rt.reset([5])                                                      # drawn anew, only there
    assert not np.allclose(rt.g[5], g_before) and np.array_equal(rt.g[6], rt.g[6])


def test_noise_has_the_stored_spectrum():
    f = np.geomspace(1.0, 1000.0, 60)
    psd = 1e-8 * (1 + 30.0 / f)                                        # a 1/f corner at 30 Hz, then white
    rt = SkinRuntime(first_order_skin(noise_psd=psd, freqs=f), noise=True, seed=2)
    n = 2 ** 16
    v = rt.run(np.zeros((n, 1, 2)), np.zeros((n, 1)))[:, 1, 1]
    fw, Pw = signal.welch(v, fs=1 / DT, nperseg=1024)
    band = (fw > 5) & (fw < 400)
    ratio = Pw[band] / np.interp(fw[band], f, psd)
    assert np.median(np.abs(np.log(ratio))) < 0.1                   # the shape, not only the rms: within ~10 %
    assert Pw[(fw > 5) & (fw < 8)].mean() > 3 * Pw[(fw > 200) & (fw < 300)].mean()
