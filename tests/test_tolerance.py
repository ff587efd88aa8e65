"""Tolerance studies: SALib's Sobol' indices on the Ishigami function, the yield of a
case with a known answer, the surrogate's held-out error, and a small FEM tolerance study."""

import numpy as np
import pytest
from scipy.stats import norm

from taxel.studies.requirements import parse_requirement
from taxel.studies.tolerance import Spread, meets, sample, spread
from taxel.studies.yield_analysis import analyze, fit_surrogate, sobol_indices, yield_of

# Ishigami (a = 7, b = 0.1) on [-pi, pi]^3: S1 = (0.3139, 0.4424, 0), ST = (0.5576, 0.4424, 0.2437)
S1 = (0.313905, 0.442411, 0.0)
ST = (0.557589, 0.442411, 0.243684)


def test_sobol_indices_of_ishigami_within_their_intervals():
    from SALib.test_functions import Ishigami
    spreads = [Spread(f"x{i}", 0.0, "", "uniform", np.pi) for i in range(1, 4)]
    idx = sobol_indices(spreads, Ishigami.evaluate, n=4096, seed=1)
    for j, s in enumerate(spreads):
        i = idx[s.name]
        assert abs(i["S1"] - S1[j]) <= i["S1_conf"] + 1e-3, (s.name, i)
        assert abs(i["ST"] - ST[j]) <= i["ST_conf"] + 1e-3, (s.name, i)
        assert i["S1_conf"] < 0.1


def test_yield_of_a_linear_output_of_a_normal_input():
    """y = 2 x - 1 with x ~ N(1, 0.1) (tolerance 0.3 = 3 sigma): P(y >= 0.9) = Phi((1 - 0.9) / 0.2)."""
    s = spread("x", 1.0, 0.3, "normal")
    x = sample([s], 2048, seed=0)[:, 0]
    r = parse_requirement("y", ">= 0.9")
    ok = meets(2 * x - 1, r.op, r.bound)
    exact = norm.cdf((1.0 - 0.9) / 0.2)
    y = yield_of(ok)
    assert y["low"] <= exact <= y["high"]
    assert y["yield"] == pytest.approx(exact, abs=3 * np.sqrt(exact * (1 - exact) / 2048))


def test_requirements_read_units_and_percent():
    r = parse_requirement("crosstalk", "<= 2 %")
    assert (r.op, r.bound) == ("<=", pytest.approx(0.02))
    r = parse_requirement("sensitivity", ">= 700 mV/N")
    assert (r.op, r.bound) == (">=", pytest.approx(0.7))
    with pytest.raises(ValueError, match="requirements.sensitivity"):
        parse_requirement("sensitivity", "> 0.7 V/N")


def test_surrogate_is_exact_on_a_quadratic_and_sobol_of_additive_linear():
    """A quadratic output is fitted to round-off (held-out error ~ 0); for y = a x1 + b x2 of
    independent normals S1 = ST = a^2 s1^2 / (a^2 s1^2 + b^2 s2^2)."""
    sp = [spread("a", "1 mm", "0.3 mm", "normal"), spread("b", "2 mm", "10 %", "uniform")]
    x = sample(sp, 64, seed=2)
    sur = fit_surrogate(sp, x, 3 * x[:, 0] ** 2 - x[:, 0] * x[:, 1] + x[:, 1])
    assert sur.validation_error < 1e-10
    res = analyze("lin", sp, x, {"y": 2 * x[:, 0] + 5 * x[:, 1]}, {"y": ">= 0"})
    va, vb = (2 * sp[0].sigma) ** 2, (5 * sp[1].sigma) ** 2
    i = res.sobol["y"]["a"]
    assert abs(i["S1"] - va / (va + vb)) <= i["S1_conf"] + 1e-3
    assert res.yields()["all"]["yield"] == 1.0


def test_tolerance_study_on_the_fem(tmp_path):
    """A tolerance study of the thesis PZT row (2D) on the store: sensitivity spread, yield, Sobol'."""
    from taxel.studies.execute import run
    from taxel.studies.spec import load_study
    from taxel.studies.store import Store
    from taxel.studies.yield_analysis import from_study
    f = tmp_path / "tol.toml"
    f.write_text('''
name = "tol"
base = "thesis-pzt-3x3-2d"
sampling = "tolerance"
samples = 16
seed = 1
outputs = ["voltage", "crosstalk"]
[overrides]
"mesh.size" = "1 mm"
[requirements]
crosstalk = "<= 30 %"
[[parameters]]
path = "array.silicone_above"
tolerance = "0.1 mm"
distribution = "uniform"
[[parameters]]
path = "array.gap"
tolerance = "0.2 mm"
''')
    st = load_study(f)
    pts = st.points()
    assert len(pts) == 16 and all(p["silicone_above"].endswith(" mm") for p in pts)
    summ = run(st, tmp_path / "out", workers=1, progress=False)
    assert summ.failed == 0
    store = Store(tmp_path / "out")
    try:
        res = from_study(st, store)
    finally:
        store.close()
    assert np.all(np.isfinite(res.values["sensitivity"]))
    assert "all" in res.yields()
    d = res.distribution("sensitivity")
    assert d["p05"] <= d["p50"] <= d["p95"]
    assert set(res.sobol["sensitivity"]) == {"silicone_above", "gap"}
    res.to_folder(tmp_path / "res")
    assert (tmp_path / "res" / "tolerance.json").is_file()
