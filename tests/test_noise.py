"""The noise budget (fem.readout, taxel.analyses.solves.noise): closed forms of the sources,
the simulated rig's drawn noise against the integrated PSD, the result protocol."""

import numpy as np
import pytest
from scipy import integrate
from scipy.constants import k as K_B

from taxel.fem.readout import Readout
from taxel.fem.readout import Amplifier, Chain, Converter, Hum, band_power, grid

T = 300.0
QUIET = Amplifier(e_n=0.0, i_n=0.0, temperature=T)


def _integral(fun, lo=1e-9, hi=1e15):
    """int_lo^hi fun(f) df in log f, by adaptive quadrature."""
    val, _ = integrate.quad(lambda x: np.exp(x) * fun(np.exp(x)), np.log(lo), np.log(hi), limit=400,
                            epsabs=0, epsrel=1e-10)
    return val


def test_kT_over_C_of_an_RC():
    """The thermal noise of R across a lossless C integrates to kT/C, whatever R."""
    C = 1e-9
    for R in (1e5, 5e8):
        ch = Chain(Readout("resistor", R=R), QUIET)
        var = _integral(lambda f: float(ch.psd(np.array([f]), C)["R"][0]))
        assert var == pytest.approx(K_B * T / C, rel=1e-6)


def test_resistor_thermal_noise_4kTR():
    """Below the RC corner the resistor's noise is its open-circuit 4kTR."""
    R, C = 1e6, 1e-12
    f = np.array([1e-6])               # w R C = 6e-12
    psd = Chain(Readout("resistor", R=R), QUIET).psd(f, C)["R"][0]
    assert psd == pytest.approx(4 * K_B * T * R, rel=1e-6)


def test_charge_amplifier_noise_gain():
    """Mid band (w R_f C_f >> 1, w R_i C << 1) the op-amp's e_n appears as (1 + C_p / C_f) e_n,
    and R_f's current noise as sqrt(4kT/R_f) / (w C_f)."""
    C_p, C_f, e_n = 4e-9, 820e-12, 18e-9
    r = Readout("charge_amplifier", C_f=C_f, R_f=1e15, R_i=1e-3, C_c=0.0)
    ch = Chain(r, Amplifier(e_n=e_n, i_n=0.0, temperature=T))
    f = np.array([1e3])
    psd = ch.psd(f, C_p)
    assert np.sqrt(psd["amplifier e_n"][0]) == pytest.approx((1 + C_p / C_f) * e_n, rel=1e-6)
    w = 2 * np.pi * f[0]
    assert psd["R_f"][0] == pytest.approx(4 * K_B * T / r.R_f / (w * C_f) ** 2, rel=1e-6)


def test_dielectric_loss_noise_is_4kTG():
    """Open circuit: the loss conductance G = w C tan(delta) across C gives 4kT G / |Y|^2 = 4kT tan(d) / (w C (1 + tan^2 d))."""
    C, tand = 2e-9, 0.02
    f = np.array([10.0, 100.0])
    w = 2 * np.pi * f
    psd = Chain(Readout("open"), QUIET).psd(f, C * (1 - 1j * tand))["dielectric loss"]
    np.testing.assert_allclose(psd, 4 * K_B * T * tand / (w * C * (1 + tand ** 2)), rtol=1e-9)


def test_quantisation_and_band_power():
    """Delta^2 / 12 spread over fs / 2: integrated over the whole Nyquist band it is Delta^2 / 12."""
    adc = Converter(bits=12, lo=-5, hi=5, rate=1000.0)
    f = grid((1e-3, 500.0), 4000)
    psd = Chain(Readout("open"), QUIET, adc).psd(f, 1e-9)["ADC quantisation"]
    assert band_power(f, psd, (1e-3, 500.0)) == pytest.approx(adc.lsb ** 2 / 12, rel=1e-5)


def _band_variance(x, rate, band):
    """The variance of x in a band, from its periodogram (one-sided)."""
    X = np.fft.rfft(x - x.mean())
    fr = np.fft.rfftfreq(len(x), 1 / rate)
    sel = (fr >= band[0]) & (fr <= band[1])
    return 2 * np.sum(np.abs(X[sel]) ** 2) / len(x) ** 2, int(sel.sum())


def test_simulated_rig_noise_matches_the_integrated_psd():
    """The simulated rig's drawn noise (white at the ADC, hum lines, quantisation; no force,
    no drift) in a band has the variance the PSD predicts. Sampling error: the random part's
    band variance is a sum of M periodogram bins, each exponential (chi^2, 2 dof), so its
    relative standard deviation is 1 / sqrt(M) (M = 3800 bins here: 1.6 %); the hum lines
    are whole periods in the record (no leakage). Accepted: 4 standard deviations."""
    from taxel.scene import load
    from taxel.studies.bench.rig import load_rig
    from taxel.studies.bench.signals import Settings, simulate
    rig = load_rig("thesis-bench")
    scene = load("thesis-pzt-single-2d")
    hum = (2e-3, 0.6e-3, 0.2e-3)
    s = Settings(input="step", seconds=10.0, amplitude=0.0, noise_V=3e-4, hum_V=hum, drift_V=0.0, seed=3)
    truth = simulate(rig, scene, s)
    volts = rig.counts_to_volts(truth.frames.counts[:, 0].astype(float))
    band = (20.0, 400.0)
    measured, M = _band_variance(volts, rig.sampling.rate, band)
    a = rig.adc
    ch = Chain(Readout("open"), Amplifier(e_n=0.0, i_n=0.0),
               Converter(a.bits, a.range[0], a.range[1], rig.sampling.rate), Hum(hum, 50.0))
    f = grid(band, 2000)
    random_part = band_power(f, ch.psd(f, 1e-9)["ADC quantisation"] + s.noise_V ** 2 / (rig.sampling.rate / 2), band)
    lines = sum(p for fl, p in ch.hum.lines(ch.readout) if band[0] <= fl <= band[1])
    sigma = random_part / np.sqrt(M)
    assert abs(measured - (random_part + lines)) < 4 * sigma, (measured, random_part + lines, sigma)
    # and the quantisation is seen: without it the prediction is off by more than 4 sigma
    assert abs(measured - (random_part - band_power(f, ch.psd(f, 1e-9)["ADC quantisation"], band) + lines)) \
        > 4 * sigma


def test_noise_budget_of_the_thesis_taxel_round_trips(tmp_path):
    """The lumped budget through the thesis bench: protocol, shares add to one, read back equal."""
    from taxel.analyses import read
    from taxel.analyses.solves.noise import noise
    from taxel.scene import load
    from taxel.studies.bench.rig import load_rig
    scene = load("thesis-pzt-frequency").replace(**{"readout.hum": ["5 mV", "1.5 mV", "0.5 mV"],
                                                     "readout.band": ["1 Hz", "5 kHz"]})
    res = noise(scene, load_rig("thesis-bench"), model="lumped")
    out = res.outputs()
    assert set(out) == {"min_detectable_force", "noise_rms", "snr", "dynamic_range"}
    assert sum(res.shares().values()) == pytest.approx(1.0)
    assert out["min_detectable_force"] == pytest.approx(out["noise_rms"] / res.band_sensitivity)
    assert res.band[1] == 1000.0                       # cut at the rig's Nyquist frequency
    res.to_folder(tmp_path / "n")
    back = read(tmp_path / "n")
    assert back.kind == "noise"
    for k, v in out.items():
        assert back.outputs()[k] == pytest.approx(v, rel=1e-12)
