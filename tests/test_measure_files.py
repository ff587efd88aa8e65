"""Import, export and the simulator: raw dumps, CSV, TDMS (npTDMS), LVM; the simulated rig's physics."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from measure_util import random_frames, rig, wire_of, write_lvm

from taxel.studies.bench import folder as F
from taxel.studies.bench.export import export_csv
from taxel.studies.bench.importers import import_file
from waits import CEILING

EXAMPLE_LVM = Path(__file__).parents[1] / "docs" / "examples" / "thesis-bench-step.lvm"


def _small_counts(n_frames=500, seed=0):
    f = random_frames(n_frames, seed=seed)
    f.counts[:] = np.random.default_rng(seed).integers(-32768, 32768, f.counts.shape)
    return f


@pytest.mark.parametrize("protocol", ["taxel-cobs", "taxel-ascii"])
def test_raw_dump_import_export_and_csv_round_trip(tmp_path, protocol):
    r = rig(protocol=protocol)
    frames = _small_counts()
    (tmp_path / "dump.bin").write_bytes(wire_of(frames, protocol).data)
    m = import_file(tmp_path / "dump.bin", r, tmp_path / "m")
    assert np.array_equal(m.counts, frames.counts) and (tmp_path / "m" / "raw.bin").exists()
    assert export_csv(tmp_path / "m", tmp_path / "raw.csv", raw=True) == len(frames)
    rows = np.loadtxt(tmp_path / "raw.csv", delimiter=",", skiprows=1, dtype=np.int64)
    assert np.array_equal(rows[:, 0], frames.seq) and np.array_equal(rows[:, 2:], frames.counts)
    head = (tmp_path / "raw.csv").read_text().splitlines()[0]
    assert head == "seq,t_us," + ",".join(r.names)
    export_csv(tmp_path / "m", tmp_path / "si.csv")
    si = np.loadtxt(tmp_path / "si.csv", delimiter=",", skiprows=1)
    volts = frames.counts * (20.0 / 65536)
    assert np.allclose(si[:, 2:11], volts[:, :9], rtol=0, atol=1e-12)       # taxels: gain 1
    assert np.allclose(si[:, 11], volts[:, 9] / 0.5, rtol=0, atol=1e-12)   # force: 0.5 V/N
    back = import_file(tmp_path / "si.csv", r, tmp_path / "m2")              # CSV in SI, as exported
    assert np.array_equal(back.values, m.values) and np.array_equal(back.seq, m.seq)
    assert np.array_equal(back.t_us, m.t_us)
    with pytest.raises(F.MeasurementError, match="no ADC counts"):
        export_csv(tmp_path / "m2", tmp_path / "x.csv", raw=True)


def test_tdms_round_trip(tmp_path):
    from nptdms import ChannelObject, GroupObject, TdmsWriter
    r = rig()
    rng = np.random.default_rng(2)
    values = rng.standard_normal((300, r.n))
    with TdmsWriter(tmp_path / "bench.tdms") as w:
        w.write_segment([GroupObject("Bench")] + [
            ChannelObject("Bench", name, values[:, k], properties={"wf_increment": 5e-4, "unit_string": "V"})
            for k, name in enumerate(r.names)])
    m = import_file(tmp_path / "bench.tdms", r, tmp_path / "m")
    assert np.array_equal(m.values, values)
    assert np.array_equal(m.t_us, np.arange(300) * 500)
    assert m.stats["rate_Hz"] == pytest.approx(2000.0)


@pytest.mark.parametrize("decimal,sep,segments", [(".", "\t", 1), (",", "\t", 3), (".", ",", 2)])
def test_lvm_round_trip(tmp_path, decimal, sep, segments):
    r = rig()
    rng = np.random.default_rng(4)
    t = np.arange(240) * 5e-4
    values = np.round(rng.standard_normal((240, r.n)), 6)
    write_lvm(tmp_path / "bench.lvm", r.names, t, values, decimal, sep, segments)
    m = import_file(tmp_path / "bench.lvm", r, tmp_path / "m")
    assert np.allclose(m.values, values, rtol=1e-9, atol=0)
    assert np.array_equal(m.t_us, np.arange(240) * 500)


def test_shipped_lvm_example(tmp_path):
    m = import_file(EXAMPLE_LVM, rig(), tmp_path / "m")
    force = m.values[:, -1]
    assert len(m) == 400 and m.stats["rate_Hz"] == pytest.approx(2000.0, rel=1e-6)
    assert force[:100].mean() < 0.05 and force[-50:].mean() > 0.5          # a 1 N step at 0.1 s


@pytest.mark.slow      # 12 s wall: taxel measure simulate through the CLI
def test_simulate_cli_physics(tmp_path, monkeypatch):
    """The simulated rig through the CLI with the lumped model (--model lumped; the
    default, the reduced model, is tested in tests/test_reduced.py): the stream holds
    exactly the truth's frames, the pressed taxel answers through the charge
    amplifier, and its neighbours carry the FEM's crosstalk."""
    env = {**__import__("os").environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}
    cmd = [sys.executable, "-m", "taxel.cli", "measure", "simulate", "thesis-bench", "--scene", "thesis-pzt-3x3-2d",
           "--input", "step", "--to", str(tmp_path / "step.bin"), "--seconds", "1.5", "--model", "lumped"]
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=CEILING)
    assert p.returncode == 0, p.stderr
    truth = np.load(tmp_path / "step.truth" / "truth.npz")
    meta = json.loads((tmp_path / "step.truth" / "truth.json").read_text())
    p = subprocess.run([sys.executable, "-m", "taxel.cli", "measure", "import", str(tmp_path / "step.bin"),
                        "--rig", "thesis-bench", "--out", str(tmp_path / "m")], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    m = F.read(tmp_path / "m")
    assert np.array_equal(m.counts, truth["counts"]) and m.stats["frames_lost"] == 0
    clean = truth["clean_volts"]
    names = meta["channels"]
    c, nb = names.index("taxel_1_1"), names.index("taxel_1_2")
    k = int(np.argmax(np.abs(clean[:, c])))
    tax = meta["taxels"]["taxel_1_1"]
    # charge amplifier V/Q = -(1/C_f) s tau / (1 + s tau) (x the input pole and the notch, both 1 at DC):
    # a charge step Q leaves the area -Q tau / C_f under the output
    Q = meta["q_per_N_C"] * tax["gain_factor"] * 1.0
    area = clean[:, c].sum() / 2000.0
    assert area == pytest.approx(-Q * tax["tau_s"] / 820e-12, rel=0.02)
    assert tax["tau_s"] == pytest.approx(10e6 * 820e-12 * tax["tau_factor"], rel=1e-12)
    ratio = clean[k, nb] / clean[k, c] * (tax["gain_factor"] / meta["taxels"]["taxel_1_2"]["gain_factor"])
    taus = (tax["tau_s"], meta["taxels"]["taxel_1_2"]["tau_s"])
    areas = clean[:, nb].sum() / clean[:, c].sum() * tax["gain_factor"] / meta["taxels"]["taxel_1_2"]["gain_factor"]
    assert areas * taus[0] / taus[1] == pytest.approx(meta["crosstalk_W1"][1][2], rel=0.02)
    assert np.sign(ratio) == np.sign(meta["crosstalk_W1"][1][2])
    assert meta["crosstalk_W1"][1][2] == pytest.approx(0.061 / -0.809, rel=0.05)
    assert truth["force"][-1] == pytest.approx(1.0, rel=1e-3)
    assert np.abs(m.values[-200:, -1].mean() - 1.0) < 0.01                   # the load cell reads 1 N


def test_simulator_fem_transient_settles_on_the_static_fem_charge(tmp_path, monkeypatch):
    """--model fem: after a step, each modelled taxel's charge (over its gain factor)
    settles on the static FEM short-circuit charge (the causal loss law's slowest
    relaxation time is 1 / (2 pi 0.5 Hz) = 0.32 s: 3 s after the step is 9 of them);
    the lumped model's is about 4.5 x smaller."""
    import taxel
    from taxel.analyses import solve_static
    from taxel.studies.bench.rig import load_rig
    from taxel.studies.bench.signals import Settings, simulate
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    scene = taxel.load("thesis-pzt-3x3-2d")
    bench = load_rig("thesis-bench")
    fem = simulate(bench, scene, Settings(input="step", seconds=3.1, onset=0.1, model="fem"))
    static = solve_static(scene).electrodes
    for name in ("taxel_1_0", "taxel_1_1", "taxel_1_2"):
        k = bench.names.index(name)
        g = fem.params["taxels"][name]["gain_factor"]
        assert fem.charge[-1, k] / g == pytest.approx(static[name].short_circuit_charge, rel=2e-3)
    lumped = simulate(bench, scene, Settings(input="step", seconds=0.6, onset=0.1))
    k = bench.names.index("taxel_1_1")
    assert 3 < fem.charge[-1, k] / lumped.charge[-1, k] < 6
    with pytest.raises(ValueError, match="presses"):
        simulate(bench, scene, Settings(input="presses", seconds=1, model="fem"))
