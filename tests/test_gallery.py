"""Every gallery script (docs/gallery/plot_*.py) runs here, and its numbers are checked.

As scikit-fem's tests/test_examples.py does for its examples: each script is run
in-process (`runpy`, matplotlib's Agg backend, `plt.show` a no-op, the working
folder and `tempfile`'s folder in the test's tmp_path) and the test asserts on the
module-level names it leaves. The expected values are closed forms (a capacitor's
charge, an RC decay, the ADC's quantisation noise, frames = rate x duration), the
physics the script's text states (the 2D sections bracket 3D, 2D overstates
crosstalk) or the numbers the documentation states with their source (the 3x3
array's 0.812 V/N and 7.5 % crosstalk and 2.33 % in 3D in
docs/guide/meshes-and-accuracy.md; the single taxel's converged 3D -0.8545 V/N in
docs/benchmarks.md). Tolerances are those of the discretisation, not of the solver.
The scripts that take more than a few seconds are marked slow.
"""

from __future__ import annotations

import math
import runpy
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

GALLERY = Path(__file__).resolve().parents[1] / "docs" / "gallery"
TESTED = {"plot_taxel_2d", "plot_taxel_models", "plot_crosstalk_3x3", "plot_frequency_response",
          "plot_step_response", "plot_noise_budget", "plot_press_probe", "plot_reduced_model",
          "plot_study_fig_2_5", "plot_explorer", "plot_measurement_loop", "plot_front", "plot_work_precision",
          "plot_user_design", "plot_skin_mujoco"}

# the thesis 3x3 PZT array (1 mm silicone above and below, 3 mm gap), docs/guide/meshes-and-accuracy.md
ARRAY_2D_SENSITIVITY, ARRAY_2D_CROSSTALK, ARRAY_3D_CROSSTALK = 0.812, 0.075, 0.0233
SINGLE_3D_SENSITIVITY = -0.8545          # the single PZT taxel in 3D, docs/benchmarks.md


@pytest.fixture
def run(tmp_path, monkeypatch):
    """run("plot_x") -> the script's module globals."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    monkeypatch.setattr(plt, "show", lambda *a, **k: None)

    def go(name):
        try:
            return runpy.run_path(str(GALLERY / f"{name}.py"), run_name="__main__")
        finally:
            plt.close("all")
    return go


def test_every_gallery_script_has_a_test():
    assert {p.stem for p in GALLERY.glob("plot_*.py")} == TESTED


def capacitance_closed_form(width=4e-3, thickness=0.127e-3, depth=4e-3):
    """A PSI-5H4E plate poled through its thickness, clamped across the depth (plane
    strain) and free in the section's plane: C = (eps33^T - d32^2 / s22^E) A / t."""
    from taxel.fem.constitution import get
    s, d, eps_t = get("PSI-5H4E").strain_charge()
    return (eps_t[2, 2] - d[2, 1] ** 2 / s[1, 1]) * width * depth / thickness


def test_taxel_2d(run):
    g = run("plot_taxel_2d")
    result = g["result"]
    out, taxel = result.outputs(), result.electrodes["taxel_0_0"]
    # PZT pressed from above: a negative open-circuit voltage of about 0.86 V per newton (1 N on the taxel)
    assert out["sensitivity"] == pytest.approx(-0.8647, rel=2e-3)
    assert taxel.voltage == out["sensitivity"] and result.applied_force == pytest.approx(1.0)
    # the taxel is a capacitor: C_p is the parallel plate's, with the plane-strain permittivity
    assert taxel.capacitance == pytest.approx(capacitance_closed_form(), rel=1e-4)
    # and the short-circuit charge is the open-circuit voltage times C_p; the ground takes the opposite
    assert out["charge_sensitivity"] == pytest.approx(-taxel.capacitance * taxel.voltage, rel=1e-6)
    assert result.electrodes["ground"].short_circuit_charge == pytest.approx(-out["charge_sensitivity"], rel=1e-9)
    # the floating top electrode is one potential: the plotted profile ends at the taxel's voltage
    phi = g["fields"].phi[g["centre"]][g["order"]]
    assert phi[-1] == pytest.approx(taxel.voltage, rel=1e-9) and abs(phi[0]) < abs(taxel.voltage)


def test_taxel_models(run):
    g = run("plot_taxel_models")
    s = {k: abs(v) for k, v in g["sensitivity"].items()}
    assert all(v < 0 for v in g["sensitivity"].values())
    # the 2D sections bracket 3D: plane strain too stiff across the depth, plane stress too soft
    assert s["plane_stress"] < s["3d"] < s["plane_strain"]
    assert s["plane_strain"] == pytest.approx(0.8647, rel=2e-3)          # the scene of plot_taxel_2d
    # the coarse 3D model is within 1 % of the converged 3D value; the round taxel of the same area too
    assert s["3d"] == pytest.approx(abs(SINGLE_3D_SENSITIVITY), rel=1e-2)
    assert s["axisymmetric"] == pytest.approx(abs(SINGLE_3D_SENSITIVITY), rel=1e-2)
    assert s["plane_stress"] < 0.5 * s["3d"]


@pytest.mark.slow
def test_crosstalk_3x3(run):
    g = run("plot_crosstalk_3x3")
    section, full = g["section"], g["full"]
    v2 = section.voltages()
    # crosstalk: the largest neighbour voltage over the pressed taxel's, in absolute value
    assert section.crosstalk == pytest.approx(max(abs(v2["taxel_1_0"]), abs(v2["taxel_1_2"])) / abs(v2["taxel_1_1"]),
                                              rel=1e-12)
    assert abs(v2["taxel_1_1"]) == pytest.approx(ARRAY_2D_SENSITIVITY, rel=2e-3)
    assert section.crosstalk == pytest.approx(ARRAY_2D_CROSSTALK, abs=0.001)
    assert v2["taxel_1_0"] == pytest.approx(v2["taxel_1_2"], rel=1e-2)   # the section is symmetric
    # neighbours of opposite sign to the pressed taxel (the silicone bulges up around the press)
    assert v2["taxel_1_0"] > 0 > v2["taxel_1_1"]
    # 3D: a quarter model by symmetry, so the nine voltages mirror exactly; far less crosstalk than 2D
    grid = g["grid"]
    np.testing.assert_allclose(grid, grid[::-1], rtol=1e-9)
    np.testing.assert_allclose(grid, grid[:, ::-1], rtol=1e-9)
    assert full.crosstalk == pytest.approx(ARRAY_3D_CROSSTALK, abs=0.005)
    assert full.crosstalk < section.crosstalk / 2


def test_frequency_response(run):
    g = run("plot_frequency_response")
    sweep = g["sweep"]
    H = np.abs(sweep.output[:, 0])
    assert sweep.output.shape == (60, 1) and sweep.freqs[0] == 1 and sweep.freqs[-1] == pytest.approx(1000)
    # well below the charge amplifier's corner 1/(2 pi R_f C_f) = 19 Hz the output is the taxel's
    # short-circuit charge through R_f: |H| = q w R_f / sqrt(1 + (w R_f C_f)^2), q from a static solve;
    # 5 %: the silicone at 1 Hz is stiffer than at rest (its relaxation law)
    import taxel
    q = taxel.solve(sweep.scene.replace(**{"analysis.type": "static"})).outputs()["charge_sensitivity"]
    r = sweep.scene.readout
    w = 2 * np.pi * sweep.freqs[0]
    assert H[0] == pytest.approx(abs(q) * w * r.R_f / math.hypot(1, w * r.R_f * r.C_f), rel=0.05)
    # the reduced sweep was checked against direct solves to the scene's tolerance
    assert sweep.measured_error < 1e-3


def test_step_response(run):
    g = run("plot_step_response")
    step = g["step"]
    v = step.output[:, 0]
    assert step.force.max() == pytest.approx(0.5) and step.t[-1] == pytest.approx(2.0)
    # at the top of the 5 ms rise the taxel holds its open-circuit voltage, 0.5 N x 0.865 V/N
    assert v.min() == pytest.approx(-0.5 * 0.8647, rel=1e-2)
    # then it discharges through R: first order, tau = R C_p (C_p the parallel plate's); 3 %: the
    # silicone's slow relaxation adds to the decay
    tail = step.t > 0.5
    slope = np.polyfit(step.t[tail], np.log(np.abs(v[tail])), 1)[0]
    assert -1 / slope == pytest.approx(step.scene.readout.R * capacitance_closed_form(), rel=0.03)
    assert v[-1] == pytest.approx(v.min() * math.exp(-(2.0 - step.t[np.argmin(v)]) / 1.72), rel=0.03)


def test_noise_budget(run):
    g = run("plot_noise_budget")
    res = g["res"]
    var = res.variance()
    # the ADC's quantisation: white, LSB^2 / 12 over the Nyquist band, LSB = 20 V / 2^16, here the
    # default band 1-300 Hz of 0-1000
    lsb = 20.0 / 2 ** 16
    assert res.band == (1.0, 300.0)
    assert var["ADC quantisation"] == pytest.approx(lsb ** 2 / 12 * (299 / 1000), rel=1e-3)
    # the hum left after the notch dominates this bench; the smallest force seen is about a millinewton
    assert res.shares()["hum residual"] > 0.9
    assert res.noise_rms == pytest.approx(math.sqrt(sum(var.values())))
    assert res.min_detectable_force == pytest.approx(1.478e-3, rel=0.02)     # 1.222 mN over 1-1000 Hz
    assert res.saturation_by == "ADC" and res.saturation_output == pytest.approx(10.0)


def test_press_probe(run):
    g = run("plot_press_probe")
    result, press = g["result"], g["press"]
    force, travel, volts = g["force"], g["travel"], g["volts"]
    # pressed to the force asked (0.5 N), every converged state on the way
    assert result.applied_force == pytest.approx(0.5, rel=2e-3)
    assert np.all(np.diff(travel) > 0) and np.all(np.diff(force) > 0) and np.all(np.diff(volts) < 0)
    # the voltage per newton of a press: about the patch load's 0.86 V/N (the contact covers the taxel's middle)
    assert volts[-1] / 1e3 / force[-1] == pytest.approx(-0.8647, rel=0.25)
    # the largest pressure exceeds the mean over the contact; the contact is narrower than the probe
    assert press["max_pressure_Pa"] > result.applied_force / press["contact_area_m2"]
    assert 0 < press["contact_half_width_m"] < 2e-3
    assert press["penetration_m"] < 1e-3 * press["travel_m"]


@pytest.mark.slow
def test_reduced_model(run):
    g = run("plot_reduced_model")
    H, Hd, f, f_check = g["H"], g["Hd"], g["f"], g["f_check"]
    # the reduced FRF at the check frequencies is the direct FEM solve's
    Hr = np.array([np.interp(f_check, f, H[:, i, j].real) + 1j * np.interp(f_check, f, H[:, i, j].imag)
                   for i in range(3) for j in range(3)])
    Hd_flat = np.array([Hd[:, i, j] for i in range(3) for j in range(3)])
    assert np.abs(Hr - Hd_flat).max() < 0.02 * np.abs(Hd_flat).max()
    # above the R C_p corner (0.09 Hz) the middle taxel reads its open-circuit voltage per newton (2D: 0.812 V/N)
    k = np.argmin(np.abs(f - 10))
    assert abs(H[k, 1, 1]) == pytest.approx(ARRAY_2D_SENSITIVITY, rel=0.03)
    # a 1 N step on the middle taxel: the peak is its open-circuit voltage, then it decays through 500 Mohm
    y = g["y"]
    assert np.abs(y[:, 1]).max() == pytest.approx(ARRAY_2D_SENSITIVITY, rel=0.03)
    assert abs(y[-1, 1]) < abs(y[:, 1]).max()


def test_study_fig_2_5(run):
    g = run("plot_study_fig_2_5")
    study = g["run"]
    assert (study.total, study.done, study.failed) == (12, 12, 0)
    for piezo in ("PZT", "PVDF"):
        rows = sorted((r for r in study.rows if r["piezo"] == piezo),
                      key=lambda r: float(r["silicone_thickness"].split()[0]))
        v = [abs(r["pressed_voltage"]) for r in rows]
        assert len(v) == 6
        # Fig. 2.5: the pressed taxel's voltage rises with the silicone around it
        assert all(b > a for a, b in zip(v, v[1:])), (piezo, v)
        assert all(r["sensitivity"] == r["pressed_voltage"] for r in rows)    # at 1 N: volts per newton
    # PZT at 1 mm above and below, in plane stress: the plane-stress value of plot_taxel_models
    pzt_1mm = next(r for r in study.rows if r["piezo"] == "PZT" and r["silicone_thickness"] == "1 mm")
    assert pzt_1mm["pressed_voltage"] == pytest.approx(-0.3387, rel=2e-3)


def test_explorer(run):
    g = run("plot_explorer")
    # there and back: each design solved once, read from the store the second time
    assert len(g["first"]) == len(g["thickness"]) == 7 and len(g["again"]) == 7
    volts, t = np.abs(g["volts"]), g["thickness"]
    # more silicone above: a larger voltage (as in Fig. 2.5), up to 1.5 mm; it levels off beyond
    assert np.all(np.diff(volts[t <= 1.5]) > 0) and volts.max() < 1.25 * volts[t == 1.0][0]
    # at 1 mm (the built-in scene) the answer is plot_taxel_2d's
    assert volts[t == 1.0][0] == pytest.approx(0.8647, rel=2e-3)


def test_measurement_loop(run):
    g = run("plot_measurement_loop")
    m, fit = g["m"], g["fit"]
    # 2 s at 2 kHz through the loop: every frame arrives, none corrupt
    assert len(m.t_us) == 4000 and m.stats["crc_failures"] == m.stats["frames_lost"] == 0
    (step,) = fit.steps
    # the charge amplifier's step decays with tau = R_f C_f = 10 Mohm x 820 pF = 8.2 ms
    assert step.tau_s == pytest.approx(10e6 * 820e-12, rel=0.1)
    assert step.tau_ci95_s[0] < step.tau_s < step.tau_ci95_s[1]
    assert step.step_N == pytest.approx(1.0, rel=1e-2)


@pytest.mark.slow
def test_skin_mujoco(run):
    g = run("plot_skin_mujoco")
    t, force, volts, SEG = g["t"], g["force"], g["volts"], g["SEG"]
    assert np.all(np.isfinite(volts)) and np.all(force >= 0)
    # the flat probe (first press) on the middle taxel: MuJoCo's contact force reaches its
    # 1 N, and the middle taxel answers most
    first = t < SEG
    assert force[first].max() == pytest.approx(1.0, rel=0.05)
    peak = np.abs(volts[first]).max(axis=0)
    assert np.unravel_index(peak.argmax(), peak.shape) == (1, 1)
    # a piezo taxel reports the force's change: the held press decays through the readout's
    # high-pass (tau = R C_p, about 2 s here), so the release swings the voltage past zero by
    # what decayed while it was held (1 - exp(-0.33 s / 2 s), about 15 % of the peak)
    v = volts[first, 1, 1]
    assert abs(v.min()) == pytest.approx(peak[1, 1]) and 0.05 * peak[1, 1] < v.max() < 0.3 * peak[1, 1]
    # the last press: the probe dragged along +x slides at MuJoCo's friction 0.3, and the tangential
    # load's onset (before the probe has moved) changes the taxels on either side with opposite signs
    shear, last = g["shear"], t > 4 * SEG
    drag = last & (shear > 0.1)
    assert np.median(shear[drag] / force[drag]) == pytest.approx(0.3, rel=0.05)
    a, b = np.argmin(abs(t - (4 * SEG + 0.24))), np.argmin(abs(t - (4 * SEG + 0.27)))
    dv = volts[b, 1] - volts[a, 1]
    assert shear[a] < 0.01 < 0.1 < shear[b] and dv[0] * dv[2] < 0 and abs(dv[0]) == pytest.approx(abs(dv[2]), rel=0.3)


@pytest.mark.slow
def test_front(run):
    g = run("plot_front")
    front = g["front"]
    assert len(g["points_2d"]) == len(front.runs) >= 2
    for (c2, s2), (c3, s3) in zip(g["points_2d"], g["points_3d"]):
        # the 2D section overstates crosstalk about three times; the sensitivity is within 10 %
        assert 2 < c2 / c3 < 5 and s3 == pytest.approx(s2, rel=0.1)
    # along the front, more sensitivity costs more crosstalk
    pts = sorted(g["points_2d"])
    assert all(b[1] > a[1] for a, b in zip(pts, pts[1:]))


@pytest.mark.slow
def test_user_design(run):
    """A user's own design (their silicone, a 2x2 PVDF array of 5 mm taxels, a charge
    amplifier, a minimum-detectable-force requirement) through the answer: their
    reference design named as theirs, a recommendation for their front, the readout's
    numbers (the charge amplifier's gain |Q_sc| / C_f far above the open-circuit V/N
    of a 100 pF feedback on a PVDF taxel's few-hundred-pF capacitance), and the
    binding requirement when the minimum detectable force asked for is out of reach."""
    g = run("plot_user_design")
    a, rec = g["answer"], g["recommended"]
    assert a.reference_name == "your reference design" and a.recommended is not None
    assert "thesis" not in a.trade and "thesis" not in g["strict"].trade
    for row in g["requirement_rows"](a):
        assert row[2] not in ("—", "not evaluated") and row[2].startswith("+"), row      # recommended: met
    assert rec.values["pitch"] <= 9e-3 and rec.values["total_thickness"] <= 2.6e-3
    # the recommended design has the smallest minimum detectable force of the designs meeting the limits
    ok = [r for r in g["front"].front_rows if r["gap (mm)"] + 5 <= 9]
    assert rec.values["min_detectable_force"] == pytest.approx(min(r["min_detectable_force"] for r in ok))
    assert g["readout_V_per_N"] != pytest.approx(g["open_circuit_V_per_N"], rel=0.05)
    s = g["strict"]
    assert s.recommended is None and s.binding[0] == "min_detectable_force" and "binds" in s.trade


@pytest.mark.slow
def test_work_precision(run):
    g = run("plot_work_precision")
    timed, reference = g["timed"], g["reference"]
    assert reference == pytest.approx(abs(SINGLE_3D_SENSITIVITY), rel=1e-3)
    s = {model: np.array([r[1] for r in rows]) for model, rows in timed.items()}
    # every model and mesh within 5 % of the 3D reference; the 2D ones within 2 % at every mesh:
    # plane strain above it (too stiff across the depth), the round taxel of the same area close to it
    assert all(np.all(np.abs(v / reference - 1) < 0.05) for v in s.values()), s
    assert np.all(s["plane strain"] > reference) and np.all(s["plane strain"] < 1.02 * reference)
    assert np.all(np.abs(s["axisymmetric"] / reference - 1) < 0.01)
