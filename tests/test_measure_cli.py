"""`taxel measure`: the simulator served on a loopback port and captured; a good rig
file round-trips. Bad rig files and bad input files (one line, exit 2, nothing
written) are rows of test_bad_input.py."""

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from measure_util import rig, rig_dict, rig_toml

from taxel.cli import main
from taxel.studies.bench import folder as F
from taxel.studies.bench.capture import capture
from waits import CEILING

BENCH = Path(__file__).parents[1] / "studies" / "bench" / "builtin" / "thesis-bench.toml"


@pytest.mark.slow      # 26 s wall: the simulator in its own process over TCP; the pty loop stays in the fast tier
def test_simulate_on_loopback_port_then_capture(tmp_path):
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}
    cmd = [sys.executable, "-m", "taxel.cli", "measure", "simulate", "thesis-bench", "--scene", "thesis-pzt-3x3-2d",
           "--input", "presses", "--seconds", "1.5", "--port", "socket://127.0.0.1:0", "--no-crosstalk",
           "--corrupt", "0.001", "--truth", str(tmp_path / "truth"), "--linger", "0.5"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        url = None
        end = time.monotonic() + CEILING    # the simulator's first line; a ceiling for a hang
        while url is None and time.monotonic() < end:
            line = proc.stdout.readline()
            if line.startswith("serving on "):
                url = line.split()[2]
        assert url and url.startswith("socket://127.0.0.1:")
        from taxel.studies.bench.rig import load_rig, parse_rig
        r = load_rig("thesis-bench")
        r = parse_rig({**r.model_dump(), "port": {**r.port.model_dump(), "url": url}}, si_numbers=True)
        res = capture(r, tmp_path / "m", seconds=CEILING)   # ends when the port vanishes
        proc.wait(timeout=CEILING)
    finally:
        proc.kill()
        proc.wait()
    assert res.ended == "port vanished"
    truth = np.load(tmp_path / "truth" / "truth.npz")
    sent = {(int(s), *map(int, c)) for s, c in zip(truth["seq"], truth["counts"])}
    m = F.read(tmp_path / "m")
    got = [(int(s), *map(int, c)) for s, c in zip(m.seq, m.counts)]
    intact = [(int(s), *map(int, c)) for s, c, ok in zip(truth["seq"], truth["counts"], truth["intact"]) if ok]
    assert all(g in sent for g in got) and set(intact) <= set(got)
    assert m.stats["crc_failures"] + m.stats["cobs_failures"] + m.stats["length_failures"] > 0
    assert m.stats["frames_lost"] == len(truth["seq"]) - len(got)


def test_good_rig_file_round_trip(tmp_path):
    (tmp_path / "rig.toml").write_text(rig_toml(rig_dict()))
    from taxel.studies.bench.rig import load_rig
    assert load_rig(tmp_path / "rig.toml") == rig()
    assert load_rig(BENCH).n == 10


def test_simulate_on_a_pty_in_ascii_then_capture(tmp_path):
    """The CLI simulator on a pseudo-terminal, taxel-ascii, no corruption: every frame arrives."""
    (tmp_path / "rig.toml").write_text(rig_toml(rig_dict(protocol="taxel-ascii")))
    cmd = [sys.executable, "-m", "taxel.cli", "measure", "simulate", str(tmp_path / "rig.toml"), "--scene",
           "thesis-pzt-3x3-2d", "--input", "impulse", "--seconds", "0.8", "--pty", "--no-crosstalk",
           "--delay", "1.0", "--linger", "0.3", "--seq0", "65400", "--truth", str(tmp_path / "truth")]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        url = None
        end = time.monotonic() + CEILING    # the simulator's first line; a ceiling for a hang
        while url is None and time.monotonic() < end:
            line = proc.stdout.readline()
            if line.startswith("serving on "):
                url = line.split()[2]
        assert url and url.startswith("/dev/")
        res = capture(rig(url, "taxel-ascii"), tmp_path / "m", seconds=CEILING)   # ends when the port vanishes
        proc.wait(timeout=CEILING)
    finally:
        proc.kill()
        proc.wait()
    assert res.ended == "port vanished"
    truth = np.load(tmp_path / "truth" / "truth.npz")
    m = F.read(tmp_path / "m")
    assert np.array_equal(m.counts, truth["counts"]) and np.array_equal(m.seq, truth["seq"])
    assert m.stats["crc_failures"] == 0 and m.stats["frames_lost"] == 0 and m.stats["resyncs"] == 0


def test_simulate_between_out_of_range_and_a_bad_press_point(tmp_path, capsys):
    assert main(["measure", "simulate", str(BENCH), "--scene", "thesis-pzt-3x3-2d", "--input", "presses",
                 "--between", "1.5", "--to", str(tmp_path / "s.bin")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--between" in err and not (tmp_path / "s.bin").exists()
    from taxel.studies.bench.folder import MeasurementError
    from taxel.studies.measured.localize import read_presses
    (tmp_path / "p.json").write_text('[{"t": 1.0, "position": [0, 1], "xy_mm": [3.0, "x"]}]')
    with pytest.raises(MeasurementError, match="press 0 needs t"):
        read_presses(tmp_path / "p.json")
    (tmp_path / "p.json").write_text('[{"t": 1.0, "position": [0, 1], "xy_mm": [3.5, 0.2]}]')
    (p,) = read_presses(tmp_path / "p.json")
    assert p.xy_mm == (3.5, 0.2) and not p.on_taxel(7.0) and p.on_taxel(None)


def test_travel_channel_takes_a_length_sensitivity():
    """A travel channel in V/mm; the ones in V/N or without a sensitivity are rows of
    test_bad_input.py."""
    from taxel.studies.bench.rig import load_rig
    d = rig_dict()
    d["channels"].append({"index": 10, "name": "travel", "sensitivity": "1 V/mm"})
    assert parse_ok(d).ordered()[10].volts_per_si == pytest.approx(1000.0)
    assert load_rig("thesis-bench-travel").n == 11


def parse_ok(d):
    from taxel.studies.bench.rig import parse_rig
    return parse_rig(d)
