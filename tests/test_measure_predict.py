"""The design metric localization_error (taxel.analyses.surface.localization) in an optimization."""

import os

import numpy as np
import pytest

import taxel
from taxel.cli import main
from taxel.optimize.spec import load_optimization, optimize
from taxel.studies.store import Store

PROBLEM = """
base = "thesis-pzt-3x3-2d"
noise = "1 mV"
[variables]
gap = {path = "array.gap", min = "1.5 mm", max = "5 mm", start = "4.5 mm"}
[objective]
minimize = "localization_error"
[algorithm]
global = "none"
local = "COBYLA"
max_evaluations = 7
xtol = 0.05
"""


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    def new(name):
        d = tmp_path / name
        monkeypatch.setenv("XDG_CACHE_HOME", str(d))
        return d
    new("cache-0")
    return new


@pytest.mark.slow      # 26 s of CPU: an optimization of the localization error
def test_localization_error_optimization_and_its_store(tmp_path, fresh_cache):
    """The predicted position error has an interior optimum in the gap (0.064 mm at 1.5 mm,
    0.044 at 3 mm, 0.13 at 5 mm: a narrow gap blurs the neighbours' slopes, a wide one
    leaves presses in the gap far from every taxel); COBYLA from 4.5 mm goes most of the way
    in 7 evaluations. A rerun, with the influence cache gone, solves nothing new: every
    press position is a point of OUT/influence."""
    path = tmp_path / "opt.toml"
    path.write_text(PROBLEM)
    out = tmp_path / "out"
    p = load_optimization(path, out)
    r = optimize(p)
    start = next(h for h in r.history if np.allclose(h["x"], p.x0))
    assert r.metrics["localization_error"] < 0.5 * start["metrics"]["localization_error"]
    assert 2.0 < r.x[0] < 4.0 and 2e-5 < r.metrics["localization_error"] < 8e-5
    n = len(Store(out / "influence").rows())
    assert n >= 9 * (r.nfev - 1)                       # 9 press positions per design (mirror symmetry)
    fresh_cache("cache-1")
    again = optimize(load_optimization(path, out))
    assert len(Store(out / "influence").rows()) == n
    np.testing.assert_allclose(again.x, r.x)
    # the metric of the optimum, recomputed without the store or any cache by plain static solves
    fresh_cache("cache-2")
    from taxel.analyses.surface.localization import localization_error
    scene = taxel.load("thesis-pzt-3x3-2d").replace(**{"array.gap": float(r.x[0]) * 1e-3})
    direct = localization_error(scene, 1e-3)
    assert direct.solves == 9
    assert direct.rms_m == pytest.approx(r.metrics["localization_error"], rel=1e-6)


def test_localization_error_scales_with_noise_and_bad_noise_is_refused(tmp_path, capsys, fresh_cache):
    from taxel.analyses.surface.localization import localization_error
    scene = taxel.load("thesis-pzt-3x3-2d")
    a, b = localization_error(scene, 1e-3), localization_error(scene, 3e-3)
    assert b.solves == 0 and b.rms_m == pytest.approx(3 * a.rms_m, rel=1e-9)       # sigma (J^T J)^-1/2
    path = tmp_path / "bad.toml"
    path.write_text(PROBLEM.replace('noise = "1 mV"', 'noise = "-1 mV"'))
    assert main(["optimize", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "noise" in err
    assert not os.path.exists(tmp_path / "o" / "optimum.json")
