"""taxel.measure, the flat API: end to end on the simulated rig, and every result through its folder.

Each result is written with to_folder and read back with read(folder); its record()
must come back the same (floats within 1e-9: a complex FRF is stored as magnitude and
phase), and its summary() must be the same lines.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import taxel.measure as tm

SCENE = "thesis-pzt-3x3-2d"


def same(a, b, path="record"):
    """Nested records equal; floats to 1e-9 relative, NaN and None alike (a JSON null)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), f"{path}: keys {set(a) ^ set(b)}"
        for k in a:
            same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, (list, tuple)):
        assert isinstance(b, (list, tuple)) and len(a) == len(b), f"{path}: lengths differ"
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]")
    elif isinstance(a, float) or isinstance(b, float):
        if a is None or b is None or math.isnan(a) or math.isnan(b):
            assert (a is None or math.isnan(a)) and (b is None or math.isnan(b)), f"{path}: {a} != {b}"
        else:
            assert a == pytest.approx(b, rel=1e-9, abs=1e-12), f"{path}: {a} != {b}"
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


@pytest.fixture(scope="module")
def bench():
    return tm.load_rig("thesis-bench")


def measured(bench, tmp_path, input, seconds, **settings):
    sim = tm.simulate(bench, SCENE, input, seconds, crosstalk=False, **settings)
    sim.to_folder(tmp_path / f"{input}-sim")
    return sim, tm.import_file(tmp_path / f"{input}-sim" / "stream.bin", bench, tmp_path / input)


def test_simulate_import_analyze_localize_and_read_back(bench, tmp_path):
    sim, m = measured(bench, tmp_path, "presses", 10, seed=2)
    assert len(m) == 20000 and m.stats["crc_failures"] == 0 and m.stats["frames_lost"] == 0
    assert np.array_equal(m.counts, sim.truth.frames.counts)        # the bytes decoded are the frames sent

    a = tm.analyze(m.folder)
    assert a.kind == "presses" and a.linearity
    written = a.to_folder()
    assert {p.name for p in written} == {"analysis.json", "analysis-peaks.csv"}
    back = tm.Analysis.read(m.folder)
    assert back.record() == a.record() and back.summary() == a.summary()

    loc = tm.localize(m.folder, tmp_path / "presses-sim" / "truth.json")
    loc.to_folder(m.folder)
    assert loc.correct_rate == 1.0 and loc.matched == len(sim.truth.params["presses"])
    back = tm.Localization.read(m.folder)
    assert back.record() == loc.record() and back.summary() == loc.summary()

    # the measurement folder: read, copied, exported to CSV and imported again
    again = tm.read(m.folder)
    assert again.record() == m.record() and again.summary() == m.summary()
    copy = tm.Measurement.read(m.to_folder(tmp_path / "copy"))
    assert np.array_equal(copy.values, m.values) and copy.stats == m.stats
    ex = tm.export_csv(m.folder, tmp_path / "m.csv")
    assert ex.rows == len(m) and ex.summary() == [f"{len(m)} rows written to {tmp_path / 'm.csv'}"]
    from_csv = tm.import_file(ex.path, bench, tmp_path / "from-csv")
    assert np.array_equal(from_csv.values, m.values) and np.array_equal(from_csv.seq, m.seq)


def test_simulation_round_trips_through_its_folder(bench, tmp_path):
    sim = tm.simulate(bench, SCENE, "impulse", 3, corrupt=0.01, crosstalk=False, seed=3)
    assert sim.wire.flips + sim.wire.drops > 0 and not sim.wire.intact.all()
    back = tm.Simulation.read(sim.to_folder(tmp_path / "sim"))
    assert back.record() == sim.record() and back.summary() == sim.summary()
    assert back.wire.data == sim.wire.data and np.array_equal(back.wire.intact, sim.wire.intact)
    for k in ("t", "force", "charge", "clean_volts"):
        assert np.array_equal(getattr(back.truth, k), getattr(sim.truth, k)), k
    assert np.array_equal(back.truth.frames.counts, sim.truth.frames.counts)
    assert back.rig == sim.rig


def test_step_and_chirp_analyses_and_the_calibration_round_trip(bench, tmp_path):
    _, step = measured(bench, tmp_path, "step", 4, seed=1)
    a = tm.analyze(step.folder, SCENE)
    assert a.steps and a.C_p_F > 0
    a.to_folder(tmp_path / "step-analysis")                         # any folder, not only the measurement's
    back = tm.Analysis.read(tmp_path / "step-analysis")
    same(back.record(), a.record())
    assert isinstance(back.steps[0].tau_ci95_s, tuple) and back.summary()[1:] == a.summary()[1:]

    _, chirp = measured(bench, tmp_path, "chirp", 10, seed=4)
    a = tm.analyze(chirp.folder, SCENE, fem=False)
    assert set(a.frf.models) == {"lumped"}
    a.to_folder()
    back = tm.Analysis.read(chirp.folder)
    same(back.record(), a.record())
    assert np.allclose(back.frf.H1, a.frf.H1, rtol=1e-9) and np.allclose(back.frf.models["lumped"],
                                                                           a.frf.models["lumped"], rtol=1e-9)
    assert back.summary() == a.summary()

    cal = tm.calibrate(chirp.folder, SCENE)
    paths = cal.to_folder()
    assert {p.name for p in paths} == {"calibration.json", "calibrated-scene.toml"}
    back = tm.FolderCalibration.read(chirp.folder)
    assert back.record() == cal.record() and back.summary() == cal.summary() and back.scene_text == cal.scene_text


def test_reading_a_folder_without_the_result_is_one_line(tmp_path):
    for cls in (tm.Analysis, tm.Localization, tm.FolderCalibration, tm.Simulation, tm.Measurement, tm.Validation):
        with pytest.raises(tm.MeasurementError) as e:
            cls.read(tmp_path)
        assert "\n" not in str(e.value) and str(tmp_path) in str(e.value)
    with pytest.raises(ValueError, match="input 'ramp'"):
        tm.simulate("thesis-bench", SCENE, "ramp")
