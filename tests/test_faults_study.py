"""Faults in the machinery a study relies on: a Dask worker killed by SIGKILL in
the middle of a point, the scheduler lost, the disk full under the store.

Each run is a real `taxel study run` in a subprocess; faults are injected from
outside (signals, a size-limited tmpfs). The counts that matter are read from
the store itself: every point is there exactly once (the key is the primary key;
`COUNT(*)` against `COUNT(DISTINCT key)` and the number of points), and the
stored results are right (the model is linear, so the pressed-taxel voltage per
newton is the same at every force: a lost, mixed up or half-written result would
break it). Waits are event-driven (a row appears in the store, the process
exits) with generous ceilings that only a hung run reaches.
"""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest
from faults_util import fill, small_disk  # noqa: F401  (the small tmpfs fixture)
from waits import CEILING, poll_until                 # a ceiling for a hang only: the waits are event-driven

psutil = pytest.importorskip("psutil")

FORCES = [f"{0.1 * (i + 1):.1f} N" for i in range(8)]
STUDY = ('base = "thesis-pzt-single-2d"\noutputs = ["voltage"]\n[overrides]\n"mesh.size" = "0.3 mm"\n'
         '[[parameters]]\npath = "load.force"\nvalues = [' + ", ".join(f'"{f}"' for f in FORCES) + "]\n")


def _env(**extra):
    env = {**os.environ, "MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", **extra}
    env.pop("TAXEL_DEBUG", None)
    return env


def _start(args, cwd, **env):
    return subprocess.Popen([sys.executable, "-m", "taxel.cli", *args], cwd=cwd, env=_env(**env),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _finish(proc):
    out, err = proc.communicate(timeout=CEILING)
    return proc.returncode, out, err


def _rows(folder: Path) -> tuple[int, int, list]:
    """(rows, distinct keys, [(force, status, voltage per newton or None)]) of a study store."""
    db = sqlite3.connect(folder / "results.sqlite", timeout=CEILING)   # the run may hold the write lock
    try:
        n, distinct = db.execute("SELECT COUNT(*), COUNT(DISTINCT key) FROM points").fetchone()
        import json
        rows = []
        for params, status, result in db.execute("SELECT params, status, result FROM points"):
            r = json.loads(result) if result else None
            rows.append((json.loads(params)["force"], status,
                         r["voltage"][r["pressed"]] / r["force"] if r else None))
        return n, distinct, rows
    except sqlite3.OperationalError:          # the table is not there yet
        return 0, 0, []
    finally:
        db.close()


def _wait_for(predicate, proc, what):
    """Poll until `predicate()` (event-driven: a row in the store); fail if the run ends first."""
    poll_until(predicate, what, proc)


def _workers(proc) -> list:
    """The Dask worker processes under a run: its leaf descendants other than the resource
    tracker (forked from the run, or from its fork server, which is not a leaf)."""
    out = []
    for p in psutil.Process(proc.pid).children(recursive=True):
        try:
            cmd = " ".join(p.cmdline())
        except psutil.Error:
            continue
        if "resource_tracker" in cmd or "semaphore_tracker" in cmd:
            continue
        if not p.children():
            out.append(p)
    return out


def _kill(p):
    """SIGKILL a worker process (it may have exited meanwhile)."""
    try:
        p.send_signal(signal.SIGKILL)
    except psutil.Error:
        pass


def _same_sensitivity(rows):
    """Every point of the linear study gives the same V/F, to the solve's accuracy: the
    direct solve refined to a 1e-13 relative residual (fem.linalg) leaves V/F at 0.1 N and
    0.3 N 1.0e-9 apart (measured, deterministic: the rounding of the right-hand side F b
    differs with F), so 1e-8 of it; a lost, duplicated or corrupted point is far off."""
    s = [r[2] for r in rows]
    assert all(v is not None for v in s)
    assert max(s) - min(s) <= 1e-8 * abs(s[0]), s


@pytest.fixture
def study(tmp_path):
    (tmp_path / "st.toml").write_text(STUDY)
    return tmp_path


@pytest.mark.slow
def test_a_worker_killed_mid_point_is_retried_and_nothing_is_lost_or_duplicated(study):
    proc = _start(["study", "run", "st.toml", "--out", "o", "--workers", "2", "--quiet"], study)
    _wait_for(lambda: (study / "o" / "results.sqlite").exists() and _rows(study / "o")[0] >= 1, proc,
              "a first stored point")
    victims = _workers(proc)
    assert victims, "no worker process found"
    _kill(victims[0])                                 # it is computing its next point
    code, out, err = _finish(proc)
    assert code == 0, err
    n, distinct, rows = _rows(study / "o")
    assert n == distinct == len(FORCES)
    assert sorted(r[0] for r in rows) == sorted(FORCES) and {r[1] for r in rows} == {"done"}
    _same_sensitivity(rows)


@pytest.mark.slow
def test_a_point_whose_worker_keeps_dying_is_recorded_failed_and_retried_later(study):
    # no second chance for a task whose worker died: the kill makes the point fail at once
    proc = _start(["study", "run", "st.toml", "--out", "o", "--workers", "2", "--quiet"], study,
                  DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES="0")
    _wait_for(lambda: (study / "o" / "results.sqlite").exists() and _rows(study / "o")[0] >= 1, proc,
              "a first stored point")
    t0 = time.monotonic()                 # kill the workers until a point has failed (one may be idle)
    while proc.poll() is None and not any(r[1] == "failed" for r in _rows(study / "o")[2]):
        for w in _workers(proc):
            _kill(w)
        assert time.monotonic() - t0 < CEILING, "no point failed"
        time.sleep(0.5)                   # a pause between kill rounds, not a wait: the loop ends on the event
    code, out, err = _finish(proc)
    n, distinct, rows = _rows(study / "o")
    assert n == distinct == len(FORCES), rows
    failed = [r for r in rows if r[1] == "failed"]
    assert code == 1 and failed, (code, err)
    assert "failed" in out
    db = sqlite3.connect(study / "o" / "results.sqlite")
    errors = [e for (e,) in db.execute("SELECT error FROM points WHERE status = 'failed'")]
    db.close()
    assert all(e.startswith("WorkerDied:") and "--retry-failed" in e for e in errors), errors
    proc = _start(["study", "run", "st.toml", "--out", "o", "--workers", "1", "--quiet", "--retry-failed"], study)
    code, out, err = _finish(proc)
    assert code == 0, err
    n, distinct, rows = _rows(study / "o")
    assert n == distinct == len(FORCES) and {r[1] for r in rows} == {"done"}
    _same_sensitivity(rows)


def _scheduler(tmp_path):
    sched_file = tmp_path / "scheduler.json"
    sched = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                              "--port", "0", "--no-dashboard", "--scheduler-file", str(sched_file)],
                             env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    import json

    def address_written():                 # written in one go, but read it only once complete
        try:
            return json.loads(sched_file.read_text())["address"]
        except (OSError, ValueError, KeyError):          # not there yet, or half written
            return None
    poll_until(address_written, "the scheduler's address", sched)
    address = address_written()
    worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1",
                               "--nworkers", "1", "--no-dashboard"], env=_env(), cwd=tmp_path,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return sched, worker, address


@pytest.mark.slow
def test_a_lost_scheduler_stops_the_run_with_one_line_and_a_rerun_resumes(study):
    sched, worker, address = _scheduler(study)
    try:
        proc = _start(["study", "run", "st.toml", "--out", "o", "--scheduler", address, "--quiet"], study)
        _wait_for(lambda: (study / "o" / "results.sqlite").exists() and _rows(study / "o")[0] >= 1, proc,
                  "a first stored point")
        sched.send_signal(signal.SIGKILL)
        code, out, err = _finish(proc)
    finally:
        for p in (sched, worker):
            p.kill()
            p.wait(timeout=CEILING)
    lines = err.strip().splitlines()
    assert code == 1 and len(lines) == 1, err
    assert lines[0].startswith("taxel: failed:") and "scheduler" in lines[0] and "again to resume" in lines[0]
    assert "Traceback" not in err
    n, distinct, before = _rows(study / "o")
    assert 1 <= n == distinct < len(FORCES) + 1
    proc = _start(["study", "run", "st.toml", "--out", "o", "--workers", "1", "--quiet"], study)
    code, out, err = _finish(proc)
    assert code == 0, err
    assert f"{n} cached" in out
    n, distinct, rows = _rows(study / "o")
    assert n == distinct == len(FORCES) and {r[1] for r in rows} == {"done"}
    _same_sensitivity(rows)


@pytest.mark.slow
def test_a_full_disk_under_the_store_is_one_line_keeps_every_point_and_a_rerun_completes(study, small_disk):  # noqa: F811 (the imported fixture)
    out = small_disk / "o"
    proc = _start(["study", "run", "st.toml", "--out", str(out), "--workers", "1", "--quiet"], study)
    _wait_for(lambda: (out / "results.sqlite").exists() and _rows(out)[0] >= 1, proc, "a first stored point")
    filler = fill(small_disk)
    code, _, err = _finish(proc)
    lines = err.strip().splitlines()
    assert code == 1 and len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith("taxel: failed:") and "no space left" in lines[0] and "again" in lines[0]
    n, distinct, rows = _rows(out)                   # read on the full disk: every stored point intact
    assert 1 <= n == distinct < len(FORCES)
    db = sqlite3.connect(out / "results.sqlite")
    assert db.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
    db.close()
    _same_sensitivity(rows)
    filler.unlink()                                  # space freed: the same command resumes
    proc = _start(["study", "run", "st.toml", "--out", str(out), "--workers", "1", "--quiet"], study)
    code, stdout, err = _finish(proc)
    assert code == 0, err
    assert f"{n} cached" in stdout
    n, distinct, rows = _rows(out)
    assert n == distinct == len(FORCES) and {r[1] for r in rows} == {"done"}
    _same_sensitivity(rows)
