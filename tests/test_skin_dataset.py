"""The skin dataset (fast, on the first-order skin of test_skin): the HDF5 round trip,
the same seed giving the same file, and the baseline recovering noise-free point presses."""

import numpy as np
import pytest

from taxel.cli import main
from taxel.skin import dataset
from test_skin import first_order_skin


def test_round_trip_and_seed(tmp_path):
    sk = first_order_skin(noise_psd=1e-10)
    a = dataset.read(dataset.write(sk, tmp_path / "a.h5", presses=8, seed=5, duration=0.1))
    b = dataset.read(dataset.write(sk, tmp_path / "b.h5", presses=8, seed=5, duration=0.1))
    c = dataset.read(dataset.write(sk, tmp_path / "c.h5", presses=8, seed=6, duration=0.1))
    assert a.voltage.shape == (8, 100, 3, 3) and a.attrs["format"] == dataset.FORMAT and a.attrs["seed"] == 5
    assert np.array_equal(a.voltage, b.voltage) and np.array_equal(a.position, b.position)
    assert list(a.probe) == list(b.probe) and not np.array_equal(a.position, c.position)
    assert np.array_equal(a.skin.Ad, sk.Ad) and np.array_equal(a.skin.influence, sk.influence)
    # the labels are the truth the voltages came from: re-run press 0 through the runtime, noise-free
    clean = dataset.read(dataset.write(sk, tmp_path / "d.h5", presses=8, seed=5, duration=0.1, noise=False))
    sigma = np.sqrt(1e-10 * (500 - 1))                 # the PSD over 1 Hz..Nyquist (taxel.skin.runtime)
    assert np.abs(clean.voltage - a.voltage).max() < 6 * sigma
    assert np.std(clean.voltage - a.voltage) == pytest.approx(sigma, rel=0.1)
    off, w = dataset.probe(clean.probe[0], clean.probe_size[0], clean.angle[0])
    from taxel.skin.runtime import SkinRuntime
    rt = SkinRuntime(sk)
    v = np.array([rt.step(clean.position[0] + off, f * w) for f in clean.force_history[0]])
    assert np.allclose(v, clean.voltage[0])


def test_baseline_recovers_clean_point_presses(tmp_path):
    sk = first_order_skin()
    d = dataset.read(dataset.write(sk, tmp_path / "a.h5", presses=24, seed=2, duration=0.1, noise=False))
    b = dataset.baseline(d)
    assert b["point"]["position_error_mm_p90"] < 0.05 and b["point"]["force_error_pc_median_abs"] < 0.5
    assert b["all"]["presses"] == 24


def test_dataset_bad_input(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    first_order_skin().save(tmp_path / "skin.npz")
    for args, words in ((["skin", "dataset", "-o", "d.h5"], "give the skin file"),
                        (["skin", "dataset", "skin.npz", "-o", "d.csv"], "use FILE.h5"),
                        (["skin", "dataset", "skin.npz", "-o", "d.h5", "--presses", "0"], "argument --presses: give an integer >= 1"),
                        (["skin", "dataset", "skin.npz", "-o", "d.h5", "--dt", "0.002"], "--dt: not an option")):
        assert main(args) == 2
        err = capsys.readouterr().err.strip()
        assert words in err and "\n" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["skin.npz"]
