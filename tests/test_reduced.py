"""The reduced-order model of a scene (taxel.analyses.solves.reduced, fem.dynamics,
fem.dynamics): against the direct FEM sweep, the FEM transient, and its
exports read back by python-control, scipy.signal and scipy.io."""

import numpy as np
import pytest

import taxel
from taxel.analyses.solves import reduced as R
from taxel.analyses.solves import reduced_export as X
from taxel.analyses import problem
from taxel.fem import dynamics
from taxel.fem import dynamics as fr

F_CHECK = np.geomspace(1.0, 2000.0, 9)


def direct_readout(model, dm, loads, freqs):
    """The direct FEM sweep of every input through the model's readout."""
    pairs = [fr.direct_ports(dm, loads, f) for f in freqs]
    V, Ci = np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])
    return R.port_readout(freqs, V, Ci, model.red.names, model.readout)


def rel(a, b):
    return np.abs(a - b).max() / np.abs(b).max()


@pytest.fixture(scope="module")
def array2d():
    scene = taxel.load("thesis-pzt-3x3-2d").replace(**{"readout.circuit": "resistor"})
    model = R.reduce(scene)
    dm = dynamics.model(problem(scene))
    loads, _ = R.taxel_loads(dm)
    return model, dm, loads


def near_resonances(model, n=3):
    """F_CHECK and the n frequencies either side of the pressed path's largest |FRF| on a fine grid."""
    f = np.geomspace(1.0, 2000.0, 400)
    i, j = model.pressed()
    k = int(np.argmax(np.abs(model.frf(f)[:, i, j])))
    return np.unique(np.concatenate([F_CHECK, f[max(k - n, 0):k + n + 1]]))


@pytest.mark.slow      # 17 s of CPU: every reduction path against a direct sweep
def test_3x3_2d_frf_all_paths_within_half_a_percent_of_the_direct_sweep(array2d):
    """Both the reduced second-order model (frf) and the exported real state space,
    on every path, over 1 Hz-2 kHz and at the resonance (the causal loss law of
    fem.constitution has an exact real realization)."""
    model, dm, loads = array2d
    assert model.input_names == [f"force:taxel_1_{c}" for c in range(3)]
    assert model.output_names == [f"voltage:taxel_1_{c}" for c in range(3)]
    f = near_resonances(model)
    H, Hs = model.frf(f), model.state_space().frf(f)
    Hd = direct_readout(model, dm, loads, f)
    assert H.shape == (len(f), 3, 3)
    peak = np.abs(Hd[:, 1, 1]).argmax()
    assert np.abs(Hd[peak, 1, 1]) > 3 * np.abs(Hd[0, 1, 1])       # the grid holds the resonance
    for i in range(3):                 # every path, relative to its own largest value
        for j in range(3):
            assert rel(H[:, i, j], Hd[:, i, j]) < 5e-3, (i, j)
            assert rel(Hs[:, i, j], Hd[:, i, j]) < 5e-3, (i, j)
    assert model.state_space().truncation_error < 2e-3
    # the row is symmetric about the middle taxel: below the resonances the two neighbours
    # read the same (the unstructured mesh is not exactly symmetric: within 1 %)
    low = f < 100
    assert rel(H[low, 0, 1], H[low, 2, 1]) < 1e-2 and rel(H[low, 1, 1], H[low, 0, 1]) > 5


@pytest.mark.slow      # the 3x3 array's reduced model (array2d: 12 s of CPU)
def test_taxel_load_vectors_carry_one_newton_each(array2d):
    _, dm, loads = array2d
    # static open-circuit response of the middle taxel's load equals the scene's own (same footprint)
    assert np.allclose(np.abs(loads).sum(axis=0) > 0, True)
    v_own = fr.direct_ports(dm, dm.F[:, None], 1.0)[0][:, 0]
    v_mid = fr.direct_ports(dm, loads[:, [1]], 1.0)[0][:, 0]
    assert rel(v_mid, v_own) < 1e-9


def test_state_space_equals_the_fem_for_viscous_damping():
    """Rayleigh damping alone (no material loss): the real state space reproduces the
    FEM sweep (resistor readout and the notch included)."""
    scene = taxel.load("thesis-pzt-single-2d").replace(**{
        "dynamics.silicone_loss": 0.0, "dynamics.piezo_loss": 0.0, "dynamics.dielectric_loss": 0.0,
        "dynamics.rayleigh_beta": 2e-5, "readout.circuit": "resistor", "readout.notch": True})
    model = R.reduce(scene, inputs="probe")
    dm = dynamics.model(problem(scene))
    Hd = direct_readout(model, dm, dm.F[:, None], F_CHECK)
    assert rel(model.frf(F_CHECK), Hd) < 1e-4
    assert rel(model.state_space().frf(F_CHECK), Hd) < 5e-3


def test_step_response_against_the_fem_transient():
    """A 5 ms ramp to 0.5 N through the 500 Mohm input; the FEM's Newmark at a step of
    1/40 of the first resonance's period (its period error is then below 0.1 %)."""
    scene = taxel.load("thesis-pzt-step").replace(**{"analysis.duration": "0.04 s", "analysis.dt": "0.025 ms"})
    fem = taxel.solve(scene)
    model = R.reduce(scene, inputs="probe")        # one causal loss law in both (fem.constitution)
    y = model.simulate(fem.t, fem.force)[:, 0]
    ref = fem.output[:, 0]
    assert np.abs(y - ref).max() < 1e-2 * np.abs(ref).max()


@pytest.mark.slow      # the 3x3 array's reduced model (array2d); test_cli_writes_npz_and_mat stays fast
def test_exports_read_back_give_the_same_frf(array2d, tmp_path):
    from scipy import signal
    model = array2d[0]
    ss = model.state_space()
    f = np.array([3.0, 120.0, 900.0])
    H = ss.frf(f)
    sysc = model.to_control()
    assert list(sysc.input_labels) == model.input_names and list(sysc.output_labels) == model.output_names
    Hc = np.moveaxis(sysc.frequency_response(2 * np.pi * f).complex, 2, 0)
    assert rel(Hc, H) < 1e-9
    # scipy.signal: the steady state of a simulated sine on the middle taxel (lsim)
    sys_s = model.to_scipy()
    f0, fs = 120.0, 40_000.0
    t = np.arange(0, 0.25, 1 / fs)
    u = np.zeros((len(t), 3))
    u[:, 1] = np.sin(2 * np.pi * f0 * t)
    _, y, _ = signal.lsim(sys_s, u, t)
    tail = t > 0.15
    basis = np.column_stack([np.sin(2 * np.pi * f0 * t[tail]), np.cos(2 * np.pi * f0 * t[tail])])
    coef = np.linalg.lstsq(basis, y[tail], rcond=None)[0]
    H_lsim = coef[0] + 1j * coef[1]
    assert rel(H_lsim, ss.frf([f0])[0, :, 1]) < 2e-2      # a still-decaying transient remains
    # MATLAB .mat
    m = X.load_mat(model.save_mat(tmp_path / "m.mat"))
    assert m["inputs"] == model.input_names and m["outputs"] == model.output_names
    from taxel.fem.dynamics import StateSpace
    assert rel(StateSpace(m["A"], m["B"], m["C"], m["D"]).frf(f), H) < 1e-12
    # the project's .npz, and a folder read back by taxel.read
    back = R.ReducedModel.load(model.save(tmp_path / "m.npz"))
    assert rel(back.frf(f), model.frf(f)) < 1e-12 and rel(back.state_space().frf(f), H) < 1e-12
    assert back.provenance["scene_sha256"] == model.provenance["scene_sha256"]
    model.to_folder(tmp_path / "folder")
    again = taxel.read(tmp_path / "folder")
    assert again.kind == "reduced" and again.outputs() == pytest.approx(model.outputs())


@pytest.mark.slow      # the 3x3 array's reduced model (array2d)
def test_simulate_equals_scipy_lsim(array2d):
    from scipy import signal
    ss = array2d[0].state_space()
    t = np.arange(0, 0.05, 1 / 2000)
    u = np.column_stack([np.sin(2 * np.pi * 37 * t), np.zeros_like(t), t * 10])
    y = ss.simulate(t, u)
    _, y_ref, _ = signal.lsim((ss.A, ss.B, ss.C, ss.D), u, t)
    assert rel(y, y_ref) < 1e-6


@pytest.mark.slow
def test_3d_single_taxel_coarse_frf_within_half_a_percent():
    scene = taxel.load("thesis-pzt-single-3d").replace(**{"mesh.size": "2 mm", "mesh.piezo_size": "1 mm",
                                                         "model.symmetry": "full"})
    model = R.reduce(scene)
    dm = dynamics.model(problem(scene))
    f = near_resonances(model, 2)
    Hd = direct_readout(model, dm, R.taxel_loads(dm)[0], f)
    assert rel(model.frf(f), Hd) < 5e-3
    assert rel(model.state_space().frf(f), Hd) < 5e-3


def test_bad_input_is_one_line(tmp_path, capsys):
    from taxel.cli import main
    with pytest.raises(taxel.SceneError, match="inputs = 'nonsense'"):
        R.reduce(taxel.load("thesis-pzt-single-2d"), inputs="nonsense")
    assert main(["reduce", "thesis-pzt-single-2d", "-o", str(tmp_path / "x.txt")]) == 2
    assert "use FILE.npz" in capsys.readouterr().err
    with pytest.raises(ValueError, match="not a reduced model file"):
        R.ReducedModel.load(tmp_path / "missing.npz")


def test_cli_writes_npz_and_mat(tmp_path, capsys):
    from taxel.cli import main
    assert main(["reduce", "thesis-pzt-single-2d", "-o", str(tmp_path / "m.mat")]) == 0
    out = capsys.readouterr().out
    assert "states" in out and "m.mat" in out
    m = X.load_mat(tmp_path / "m.mat")
    assert m["inputs"] == ["force:taxel_0_0"] and m["A"].shape[0] == m["A"].shape[1] > 0


def test_simulated_rig_on_the_reduced_model_has_the_fems_static_charge_and_crosstalk():
    from taxel.fem.dynamics import ports
    from taxel.studies.bench.rig import load_rig
    from taxel.studies.bench.signals import Settings, simulate
    scene = taxel.load("thesis-pzt-3x3-2d")
    truth = simulate(load_rig("thesis-bench"), scene, Settings(input="step", seconds=1.0, model="reduced",
                                                               gain_spread=0.0, tau_spread=0.0))
    rm = R.cached(scene, "taxels", "charge")
    V, Ci = ports(rm.red, [1e-3])
    Q_static = (-np.linalg.inv(Ci[0]) @ V[0]).real               # (outputs, inputs) C/N
    taxels = [tuple(p["taxel"]) for p in truth.params["taxels"].values()]
    settled = truth.charge[-1] / truth.force[-1]
    for k, (r, c) in enumerate(taxels):
        if r == 1:                                             # the modelled row: the FEM's own paths
            assert settled[k] == pytest.approx(Q_static[c, 1], rel=2e-2, abs=1e-3 * abs(Q_static[1, 1]))
    middle = taxels.index((1, 1))
    assert abs(settled[middle]) > 5 * np.abs(np.delete(settled, middle)).max()


@pytest.mark.slow   # a 10 s chirp simulated on the reduced model, then calibrated (about 13 s of CPU)
def test_calibrate_on_the_reduced_model_recovers_the_drawn_gain_and_time_constant(tmp_path):
    """A 10 s chirp on the rig whose taxel is the reduced model (thesis bench: charge
    amplifier and notch); `taxel measure calibrate --model reduced` from the stream."""
    from taxel.cli import main
    assert main(["measure", "simulate", "thesis-bench", "--scene", "thesis-pzt-3x3-2d", "--input", "chirp",
                 "--seconds", "10", "--seed", "4", "--to", str(tmp_path / "c.bin")]) == 0
    assert main(["measure", "import", str(tmp_path / "c.bin"), "--rig", "thesis-bench", "--out",
                 str(tmp_path / "m")]) == 0
    assert main(["measure", "calibrate", str(tmp_path / "m"), "--scene", "thesis-pzt-3x3-2d", "--model",
                 "reduced"]) == 0
    import json
    cal = json.loads((tmp_path / "m" / "calibration.json").read_text())
    truth = json.loads((tmp_path / "c.truth" / "truth.json").read_text())["taxels"][cal["taxel"]]
    assert cal["model"] == "reduced"
    assert cal["gain_ci95"][0] <= truth["gain_factor"] <= cal["gain_ci95"][1]
    assert cal["tau_scale_ci95"][0] <= truth["tau_factor"] <= cal["tau_scale_ci95"][1]
    assert cal["rms_after_all_pct"] < 5.0


@pytest.mark.slow
def test_physical_scales_identifiability_on_the_fem():
    """studies.measured.physical on the single 2D taxel through the thesis bench's chain:
    the piezo coefficient is a pure gain (sensitivity 1, the coupling matrix scaled;
    checked against a finite difference of the FRF), confounded with the taxel's gain
    (correlation -1), while the silicone's modulus and loss hardly move the chirp's FRF."""
    from taxel.studies.bench.rig import load_rig
    from taxel.studies.measured.physical import Physical, physical_identifiability
    scene = taxel.load("thesis-pzt-single-2d")
    readout = load_rig("thesis-bench").chains()["taxel_1_1"].readout()
    f = np.arange(5.0, 99.0, 4.0)
    f = f[np.abs(f - 50) >= 15]
    model = Physical(scene, readout)
    H0, H1 = model(f), model(f, piezo=1.01)
    assert np.abs(np.log(np.abs(H1 / H0)) / np.log(1.01) - 1).max() < 0.02
    idf = physical_identifiability(scene, readout, f, 0.01)
    i = {n: k for k, n in enumerate(idf.names)}
    assert abs(idf.correlation[i["piezo"], i["gain"]]) > 0.999
    assert idf.sensitivity[i["modulus"]] < 0.05 and idf.sensitivity[i["loss"]] < 0.05
    assert idf.sensitivity[i["R_f"]] > 0.5
