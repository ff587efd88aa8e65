"""The runtime's balanced cut of the readout's modes and its flush of an idle skin's
decayed state (fast): against scipy's simulation of the file's own Ad..Dd."""

import numpy as np
from scipy import signal

from taxel.skin.discrete import first_order_hold
from taxel.skin.readout import real_blocks
from taxel.skin.runtime import FLUSH_BELOW, SkinRuntime
from test_skin import DT, first_order_skin


def many_mode_skin():
    """The 3 x 3 tent skin with h(s) of 12 modes (4 real, 4 resonances 30-400 Hz), residues
    spread over seven decades: most of them cannot be seen at the output."""
    lam = np.array([-20.0, -300.0, -2e3, -9e3], complex)
    res = np.array([15.0, 40.0, 3e-3, 2e-4], complex)
    for f, z, r in ((30.0, 0.05, 20.0), (120.0, 0.03, 1e-2), (250.0, 0.02, 4e-4), (400.0, 0.04, 1e-5)):
        p = complex(2 * np.pi * f * (-z + 1j * np.sqrt(1 - z * z)))
        lam, res = np.append(lam, [p, p.conjugate()]), np.append(res, [r * (1 + 0.3j), r * (1 - 0.3j)])
    mu, w, D = first_order_hold(lam, res, 0.0, DT)
    sk = first_order_skin()
    sk.Ad, sk.Bd, sk.Cd, sk.Dd = real_blocks(mu, w, D)
    sk.A, sk.B, sk.C, sk.D = real_blocks(lam, res, 0.0)
    return sk


def test_the_cut_keeps_fewer_modes_and_the_files_response():
    sk = many_mode_skin()
    cut, full = SkinRuntime(sk), SkinRuntime(sk, order_tol=0.0)
    assert full._lam.shape[1] == 8 and cut._lam.shape[1] < full._lam.shape[1]
    assert 0 < cut.order_error <= 1e-6
    rng = np.random.default_rng(2)
    P, F = rng.uniform(0, 14e-3, (3000, 1, 2)), rng.uniform(0, 1, (3000, 1))
    F[1500:] = 0.0                                    # and a release: the cut's free response
    v = np.array([cut.step(p, f) for p, f in zip(P, F)])
    ref = full.run(P, F)                              # the file's modes, every one
    U = SkinRuntime(sk).loads(P, F)                   # each taxel's load, through scipy's dlsim of Ad..Dd
    V = np.stack([signal.dlsim((sk.Ad, sk.Bd, sk.Cd, sk.Dd, DT), U[:, r, c])[1][:, 0]
                  for r in range(3) for c in range(3)], axis=1).reshape(v.shape)
    peak = np.abs(V).max()
    assert np.abs(ref - V).max() < 1e-10 * peak
    assert np.abs(v - V).max() < 1e-5 * peak


def test_an_idle_skin_holds_no_subnormal_numbers():
    rt = SkinRuntime(first_order_skin())              # one pole at exp(-dt / tau) = 0.98: subnormal after 35 000-36 500 steps
    for _ in range(50):
        rt.step([[7e-3, 7e-3]], [1.0])
    for _ in range(36000):
        v = rt.step([[7e-3, 7e-3]], [0.0])
    parts = np.abs(rt._Z.view(float))
    assert not np.any((parts > 0) & (parts < FLUSH_BELOW)) and np.all(v == 0.0)
