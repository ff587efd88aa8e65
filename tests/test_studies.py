"""Parameter studies: resumable after kill -9, identical on Dask, cached by content,
and bad study files refused with one line."""

import os
import signal
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from taxel.scene import EXAMPLES
from taxel.schema import set_path
from taxel.units import magnitude
from taxel.studies.execute import run as run_study
from taxel.studies.spec import load_study
from taxel.studies.store import tidy_rows
from taxel.cli import main
from waits import CEILING, poll_until

SMALL = """
name = "small"
base = "{base}"
outputs = ["voltage", "short_circuit_charge", "max_strain"]

[overrides]
"mesh.size" = "1 mm"

[[parameters]]
path = ["array.silicone_above", "array.silicone_below"]
label = "silicone"
start = "0.5 mm"
stop = "2 mm"
step = "0.5 mm"

[[parameters]]
path = "load.force"
values = ["0.2 N", "0.4 N", "0.6 N"]
"""


def write_study(tmp_path, base="thesis-pzt-single-2d", extra="", name="s.toml"):
    p = tmp_path / name
    p.write_text(SMALL.format(base=base) + extra)
    return p


def results(folder):
    db = sqlite3.connect(Path(folder) / "results.sqlite")
    rows = db.execute("SELECT key, status, result FROM points ORDER BY key").fetchall()
    db.close()
    return rows


def count(folder):
    try:
        # waits out a run's write lock (event-driven; CEILING only catches a hang, as elsewhere)
        db = sqlite3.connect(Path(folder) / "results.sqlite", timeout=CEILING)
        n = db.execute("SELECT COUNT(*) FROM points").fetchone()[0]
        db.close()
        return n
    except sqlite3.Error:
        return 0


@pytest.mark.slow      # 4 s of CPU and three study processes
def test_kill_minus_nine_twice_then_resume_gives_every_point_once(tmp_path):
    study = write_study(tmp_path)
    ref = tmp_path / "ref"
    assert main(["study", "run", str(study), "--out", str(ref), "--workers", "1", "--quiet"]) == 0
    out = tmp_path / "killed"
    cmd = [sys.executable, "-m", "taxel.cli", "study", "run", str(study), "--out", str(out),
           "--workers", "1", "--quiet"]
    env = {**os.environ, "MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    for target in (3, 7):                      # kill after some points, twice
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                cwd=Path(__file__).parent.parent)
        poll_until(lambda: count(out) >= target, f"{target} stored points", proc)   # the row count
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        assert 0 < count(out) < 12
    assert main(["study", "run", str(study), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    got, want = results(out), results(ref)
    assert len(got) == len(want) == 12                      # every point exactly once (key is primary)
    assert [(k, s) for k, s, _ in got] == [(k, s) for k, s, _ in want]
    import json
    for (_, _, a), (_, _, b) in zip(got, want):
        ra, rb = json.loads(a), json.loads(b)
        assert ra["voltage"] == rb["voltage"] and ra["short_circuit_charge"] == rb["short_circuit_charge"]


@pytest.mark.slow      # 13 s wall: a local Dask cluster of two worker processes
def test_dask_two_workers_equal_in_process(tmp_path):
    """Two local Dask workers give the in-process results, run through the Python API
    from this long-lived test process while another of its threads holds a lock.
    Workers forked from such a process deadlocked in this suite (after the pty and
    render tests); with other threads running they now come from a clean fork
    server (studies.execute.start_method)."""
    import threading

    import taxel
    from taxel.studies.execute import start_method
    path = write_study(tmp_path)
    study = load_study(path)
    a = run_study(study, tmp_path / "one", workers=1, progress=False)
    held, stop = threading.Lock(), threading.Event()

    def holder():                      # a caller's thread holding a lock through the run
        with held:
            stop.wait(CEILING)
    t = threading.Thread(target=holder, daemon=True)
    t.start()
    try:
        assert start_method() == "forkserver"
        b = taxel.run_study(path, tmp_path / "dask", workers=2, progress=False)
    finally:
        stop.set()
        t.join()
    assert a.done == 12 and a.failed == 0 and b.done == 12 and b.failed == 0
    import json

    def physics(rows):
        return [(k, s, {n: v for n, v in json.loads(r).items() if n != "seconds"}) for k, s, r in rows]
    assert physics(results(tmp_path / "one")) == physics(results(tmp_path / "dask"))


def test_changing_the_base_invalidates_exactly_the_affected_points(tmp_path):
    base = tmp_path / "base.toml"
    base.write_text((EXAMPLES / "thesis-pzt-single-2d.toml").read_text())
    study_file = write_study(tmp_path, base=str(base))
    out = tmp_path / "out"
    first = run_study(load_study(study_file), out, workers=1, progress=False)
    assert first.done == 12
    again = run_study(load_study(study_file), out, workers=1, progress=False)
    assert again.done == 0 and again.cached == 12               # changing nothing reruns nothing
    # the base's force is overridden by the study: no point changes
    base.write_text(base.read_text().replace('force = "1 N"', 'force = "0.9 N"'))
    same = run_study(load_study(study_file), out, workers=1, progress=False)
    assert same.done == 0 and same.cached == 12
    # one more force value: exactly its 4 new points run
    study_file.write_text(study_file.read_text().replace('"0.6 N"]', '"0.6 N", "0.8 N"]'))
    grown = run_study(load_study(study_file), out, workers=1, progress=False)
    assert grown.done == 4 and grown.cached == 12
    # the margin changes every point
    base.write_text(base.read_text().replace('margin = "3 mm"', 'margin = "2.5 mm"'))
    changed = run_study(load_study(study_file), out, workers=1, progress=False)
    assert changed.done == 16 and changed.cached == 0


def test_a_failing_point_is_recorded_and_retried_on_request(tmp_path):
    """PVDF is not transversely isotropic: its axisymmetric points fail at assembly;
    they are stored with their error, the PZT points succeed, and only
    --retry-failed runs the failed ones again."""
    study_file = write_study(tmp_path, extra='[[parameters]]\npath = "array"\nlabel = "piezo"\n'
                             'values = [{piezo = "PSI-5H4E"}, {piezo = "PVDF", piezo_thickness = "52 um"}]\n')
    study_file.write_text(study_file.read_text().replace('"mesh.size" = "1 mm"',
                                                         '"mesh.size" = "1 mm"\n"model.type" = "axisymmetric"'))
    out = tmp_path / "out"
    summary = run_study(load_study(study_file), out, workers=1, progress=False)
    assert summary.failed == 12 and summary.done == 12
    rows = [r for r in tidy_rows(out) if r["status"] == "failed"]
    assert all("transversely isotropic" in r["error"] and "piezo=PVDF" in r["piezo"] for r in rows)
    again = run_study(load_study(study_file), out, workers=1, progress=False)
    assert again.done == 0 and again.failed == 0 and again.cached == 24
    retried = run_study(load_study(study_file), out, workers=1, retry_failed=True, progress=False)
    assert retried.failed == 12 and retried.cached == 12


def test_status_and_export(tmp_path, capsys):
    study = write_study(tmp_path)
    out = tmp_path / "out"
    assert main(["study", "run", str(study), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    assert main(["study", "status", str(out)]) == 0
    assert "12 done, 0 failed, 0 pending of 12" in capsys.readouterr().out
    csv = tmp_path / "r.csv"
    assert main(["study", "export", str(out), "--csv", str(csv)]) == 0
    lines = csv.read_text().splitlines()
    assert len(lines) == 13 and "pressed_voltage" in lines[0] and "sensitivity" in lines[0]
    assert (out / "plots" / "pressed_voltage-vs-silicone.png").stat().st_size > 1000


def test_latin_hypercube_is_seeded_and_stratified(tmp_path):
    p = tmp_path / "lhs.toml"
    p.write_text('base = "thesis-pzt-single-2d"\nsampling = "lhs"\nsamples = 8\nseed = 3\n'
                 '[[parameters]]\npath = "array.gap"\nstart = "1 mm"\nstop = "5 mm"\n'
                 '[[parameters]]\npath = "load.force"\nstart = "0.2 N"\nstop = "1 N"\n')
    a, b = load_study(p).points(), load_study(p).points()
    assert a == b and len(a) == 8
    gaps = sorted(magnitude(x["gap"]) for x in a)
    strata = [int((g - 1e-3) / (4e-3 / 8)) for g in gaps]
    assert strata == list(range(8))                 # one sample in each of the 8 strata


def test_a_root_parameter_merges_tables_deeply():
    data = {"model": {"type": "plane_strain", "silicone": "linear"}, "mesh": {"size": "0.5 mm", "order": 2}}
    set_path(data, "", {"model": {"type": "3d"}, "mesh": {"size": "1 mm"}})
    assert data == {"model": {"type": "3d", "silicone": "linear"}, "mesh": {"size": "1 mm", "order": 2}}


@pytest.mark.slow      # 14 s of CPU, 17 s wall: a study run beside another
def test_a_second_run_on_a_busy_folder_is_refused_and_the_lock_dies_with_the_first(tmp_path, capsys):
    """Two `taxel study run` on one folder: the second is refused at once (one line,
    exit 2) instead of computing every point again; once the first is killed
    (SIGKILL: no cleanup), the folder's lock is free and a rerun finishes it."""
    study = write_study(tmp_path, extra='[[parameters]]\npath = "array.gap"\nvalues = ["1 mm", "2 mm", "3 mm", '
                                        '"4 mm", "5 mm", "6 mm", "7 mm", "8 mm"]\n')
    out = tmp_path / "busy"
    cmd = [sys.executable, "-m", "taxel.cli", "study", "run", str(study), "--out", str(out), "--workers", "1",
           "--quiet"]
    env = {**os.environ, "MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        poll_until(lambda: count(out) >= 2, "2 stored points", proc)     # fails if the first run ended first
        assert proc.poll() is None, "the first run ended before the second could start"
        capsys.readouterr()
        code = main(["study", "run", str(study), "--out", str(out), "--workers", "1", "--quiet"])
        err = capsys.readouterr().err
        assert code == 2 and len(err.splitlines()) == 1 and "another study run" in err, err
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    assert main(["study", "run", str(study), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    assert count(out) == 96


def test_the_progress_bar_is_drawn_on_a_terminal_only(capsys):
    """A log (stderr not a terminal) gets no carriage-return bars: the main job's log has
    one line per stage."""
    from taxel.studies.execute import progress_bar
    bar = progress_bar(5, 1, True)
    bar.update(2)
    bar.close()
    assert bar.disable and "\r" not in capsys.readouterr().err
    assert progress_bar(5, 0, False).disable
