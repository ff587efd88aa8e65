"""Noise outputs as design outputs (the quasi-static budget against the FEM sweep) and
robust design (percentiles and yield over a tolerance sample; a reproducible optimum)."""

import numpy as np
import pytest

from taxel.optimize.robust import Robust, robust_metrics
from taxel.optimize.spec import OptimizeError, load_optimization, optimize
from taxel.studies.requirements import parse_requirement

HEAD = '''name = "r"
base = "thesis-pzt-3x3-2d"
[variables]
gap = {path = "array.gap", min = "2 mm", max = "4 mm", start = "3 mm"}
'''
ROBUST = '''[robust]
percentile = 5
samples = 4
seed = 3
[[robust.parameters]]
path = "array.silicone_above"
tolerance = "0.1 mm"
distribution = "uniform"
[[robust.parameters]]
path = "array.gap"
tolerance = "0.2 mm"
'''


def write(tmp_path, text, name="r.toml"):
    f = tmp_path / name
    f.write_text(text)
    return f


@pytest.mark.parametrize("band", [(1.0, 100.0), (20.0, 200.0), (1.0, 300.0)])   # the last: the default band
def test_quasi_static_noise_matches_the_fem_sweep_below_resonance(band):
    """The design outputs' cheap route (one static solve: C_p = Q_sc / V_oc, the circuit's
    H(f) of that charge source) against taxel.analyses.solves.noise's FEM frequency sweep on the
    thesis PZT taxel, charge amplifier and notch, in bands below the silicone's resonance."""
    from taxel import api
    from taxel.analyses import solve_static
    from taxel.analyses.solves.noise import noise, quasi_static_noise
    sc = api.load("thesis-pzt-frequency")
    o = solve_static(sc.replace(**{"analysis.type": "static"})).outputs()
    q = quasi_static_noise(sc, o["sensitivity"], o["charge_sensitivity"], band=band)
    f = noise(sc, band=band)
    assert q.band_sensitivity == pytest.approx(f.band_sensitivity, rel=0.03)
    assert q.noise_rms == pytest.approx(f.noise_rms, rel=0.03)
    assert q.min_detectable_force == pytest.approx(f.min_detectable_force, rel=0.03)
    assert q.shares()["amplifier e_n"] == pytest.approx(f.shares()["amplifier e_n"], abs=0.02)


def test_robust_metrics_of_a_known_spread():
    """A part's 'sensitivity' = its silicone_above in mm, uniform 1 +- 0.1 mm: the 5th
    percentile is 0.91 and the yield of sensitivity >= 0.95 is 75 %."""
    rb = Robust.model_validate({"percentile": 5, "samples": 1024, "seed": 0, "parameters": [
        {"path": "array.silicone_above", "tolerance": "0.1 mm", "distribution": "uniform"}]})
    data = {"array": {"silicone_above": "1 mm"}}

    def evaluate(part, params):
        return {"sensitivity": params["silicone_above"], "crosstalk": None}
    m = robust_metrics(rb, {"sensitivity": (">=", parse_requirement("sensitivity", ">= 0.95").bound)}, data, evaluate)
    assert m["robust_sensitivity"] == pytest.approx(0.91, abs=2e-3)
    assert m["yield"] == pytest.approx(0.75, abs=3 / 1024)
    assert m["robust_crosstalk"] is None


def test_noise_and_robust_metrics_of_one_design(tmp_path):
    """The optimizer's noise metrics equal the quasi-static budget of the design's static
    solve; its robust metrics come from parts stored beside the design."""
    from taxel.analyses import solve_static
    from taxel.analyses.solves.noise import quasi_static_noise
    from taxel.scene import parse
    from taxel.studies.store import Store
    f = write(tmp_path, HEAD + '[objective]\nmaximize = "robust_sensitivity"\n[requirements]\n'
              'min_detectable_force = "<= 1 mN"\nyield = ">= 0.5"\ncrosstalk = "<= 10 %"\n'
              '[resolution]\nband = ["2 Hz", "80 Hz"]\n' + ROBUST)
    p = load_optimization(f, tmp_path / "out")
    p.base["mesh"]["size"] = "1 mm"
    m = p.evaluate(p.x0)
    scene = parse({**p.scene_data(p.x0), "name": "d"})
    o = solve_static(scene).outputs()
    q = quasi_static_noise(scene, o["sensitivity"], o["charge_sensitivity"], band=(2.0, 80.0))
    assert m["min_detectable_force"] == pytest.approx(q.min_detectable_force, rel=1e-9)
    assert m["snr"] == pytest.approx(q.snr_at(1.0), rel=1e-9)
    assert m["robust_sensitivity"] <= m["sensitivity"] * 1.05
    assert 0.0 <= m["yield"] <= 1.0
    store = Store(tmp_path / "out")
    try:
        assert len(store.rows()) == 1 + 4
    finally:
        store.close()


@pytest.mark.slow      # 10 s of CPU: two robust optimizations
def test_robust_optimum_is_reproducible(tmp_path):
    """Two runs from empty stores (the same seed) give the same optimum."""
    text = HEAD + '[objective]\nmaximize = "robust_sensitivity"\n[requirements]\nyield = ">= 0.5"\n' \
        'crosstalk = "<= 8 %"\n[algorithm]\nglobal = "none"\nlocal = "COBYLA"\n' \
        'max_evaluations = 4\n' + ROBUST
    results = []
    for k in range(2):
        p = load_optimization(write(tmp_path, text), tmp_path / f"out{k}")
        p.base["mesh"]["size"] = "1.5 mm"
        results.append(optimize(p))
    a, b = results
    assert np.array_equal(a.x, b.x)
    assert a.metrics == b.metrics
    assert a.nfev == b.nfev


@pytest.mark.parametrize("extra, match", [
    ('[objective]\nmaximize = "robust_sensitivity"\n', r"robust_sensitivity needs a \[robust\] table"),
    ('[objective]\nmaximize = "sensitivity"\n[requirements]\nyield = ">= 0.9"\n' + ROBUST,
     r"yield needs a part's requirement under \[requirements\]"),
    ('[objective]\nmaximize = "sensitivity"\n[requirements]\ncrosstalk = "< 2 %"\n', "requirements.crosstalk"),
    ('[objective]\nmaximize = "sensitivity"\n[requirements]\nyield = ">= 0.9"\n', "yield needs a .robust. table"),
    ('[objective]\nmaximize = "robust_sensitivity"\n' + ROBUST.replace('"0.1 mm"', '"-1 mm"'),
     "robust.parameters 'silicone_above': the tolerance must be positive"),
    ('[objective]\nmaximize = "robust_sensitivity"\n' + ROBUST.replace('"array.gap"', '"arr.gap"'),
     "unknown scene path 'arr.gap'"),
    ('[objective]\nmaximize = "robust_sensitivity"\n' + ROBUST.replace("percentile = 5", "percentile = 100"),
     "percentile"),
    ('[objective]\nminimize = "min_detectable_force"\n[resolution]\nband = ["100 Hz", "1 Hz"]\n',
     "resolution.band"),
    ('[objective]\nminimize = "min_detectable_force"\n[resolution]\nrig = "no-such-rig"\n', "resolution.rig"),
])
def test_bad_robust_and_noise_tables_give_one_line(tmp_path, extra, match):
    with pytest.raises(OptimizeError, match=match) as exc:
        load_optimization(write(tmp_path, HEAD + extra))
    assert "\n" not in str(exc.value)
