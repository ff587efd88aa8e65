"""`taxel measure`: the simulator served on a loopback port and captured; bad rig
files and bad input files give one line, exit 2, and write nothing."""

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from measure_util import rig, rig_dict

from taxel.cli import main
from taxel.studies.bench import folder as F
from taxel.studies.bench.capture import capture
from waits import CEILING

BENCH = Path(__file__).parents[1] / "studies" / "bench" / "builtin" / "thesis-bench.toml"


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


def _toml(d: dict) -> str:
    import json
    lines = [f'name = "{d["name"]}"', "[port]"] + [f"{k} = {json.dumps(v)}" for k, v in d["port"].items()]
    lines += ["[sampling]"] + [f"{k} = {json.dumps(v)}" for k, v in d["sampling"].items()]
    for c in d["channels"]:
        lines += ["[[channels]]"] + [f"{k} = {json.dumps(v)}" for k, v in c.items()]
    lines += ["[conditioning]"] + [f"{k} = {json.dumps(v)}" for k, v in d.get("conditioning", {}).items()
                                   if not isinstance(v, dict)]
    for name, sub in d.get("conditioning", {}).items():
        if isinstance(sub, dict):
            lines += [f"[conditioning.{name}]"] + [f"{k} = {json.dumps(v)}" for k, v in sub.items()]
    return "\n".join(lines) + "\n"


def _bad_rigs():
    d = rig_dict()
    yield "unknown channel", {**d, "channels": d["channels"][:-1] + [{"index": 9, "name": "pressure"}]}, "unknown channel"
    yield "missing unit", {**d, "channels": d["channels"][:-1] + [{"index": 9, "name": "force", "sensitivity": 0.5}]}, \
        "missing unit"
    yield "baud 0", {**d, "port": {**d["port"], "baud": 0}}, "port.baud"
    dup = [dict(c) for c in d["channels"]]
    dup[1]["index"] = 0
    yield "duplicate index", {**d, "channels": dup}, "duplicate channel index 0"
    yield "unknown conditioning channel", {**d, "conditioning": {**d["conditioning"], "taxel_5_5": {"R_f": "1 MOhm"}}}, \
        "conditioning.taxel_5_5: unknown channel"
    yield "rate without unit", {**d, "sampling": {"rate": 2000}}, "sampling.rate: missing unit"
    yield "unknown key", {**d, "port": {**d["port"], "speed": 9600}}, "unknown key 'port.speed'"


@pytest.mark.parametrize("case,data,msg", list(_bad_rigs()), ids=[c for c, _, _ in _bad_rigs()])
def test_bad_rig_files(tmp_path, capsys, case, data, msg):
    path = tmp_path / "rig.toml"
    path.write_text(_toml(data))
    assert main(["measure", "capture", str(path), "--seconds", "1", "--out", str(tmp_path / "m")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("taxel: error: ") and msg in err, err
    assert str(path) in err
    assert sorted(os.listdir(tmp_path)) == ["rig.toml"]


def test_good_rig_file_round_trip(tmp_path):
    (tmp_path / "rig.toml").write_text(_toml(rig_dict()))
    from taxel.studies.bench.rig import load_rig
    assert load_rig(tmp_path / "rig.toml") == rig()
    assert load_rig(BENCH).n == 10


def _bad_inputs(tmp_path):
    r = tmp_path / "rig.toml"
    r.write_text(_toml(rig_dict()))
    (tmp_path / "short.csv").write_text("seq,t_us,taxel_0_0\n0,0,1.0\n")
    (tmp_path / "text.csv").write_text("seq,t_us," + ",".join(rig().names) + "\n0,0," + ",".join(["x"] * 10) + "\n")
    (tmp_path / "not.lvm").write_text("hello\n")
    (tmp_path / "junk.tdms").write_bytes(b"TDSm garbage" * 10)
    (tmp_path / "fake.tdms").write_bytes(b"PK\x03\x04 a zip file")
    (tmp_path / "noise.bin").write_bytes(bytes(range(1, 256)) * 4)
    (tmp_path / "data.xyz").write_text("1,2\n")
    return [("short.csv", "no column for channel 'taxel_0_1'"), ("text.csv", "not a number"),
            ("not.lvm", "not a LabVIEW LVM file"), ("junk.tdms", "not a readable TDMS file"),
            ("fake.tdms", "not a TDMS file"),
            ("noise.bin", "no valid taxel-cobs frame"), ("data.xyz", "unknown file type"),
            ("missing.csv", "no such file")]


def test_bad_input_files(tmp_path, capsys):
    for name, msg in _bad_inputs(tmp_path):
        before = sorted(os.listdir(tmp_path))
        code = main(["measure", "import", str(tmp_path / name), "--rig", str(tmp_path / "rig.toml"),
                     "--out", str(tmp_path / "m")])
        err = capsys.readouterr().err.strip()
        assert code == 2 and len(err.splitlines()) == 1 and msg in err and name in err, (name, err)
        assert sorted(os.listdir(tmp_path)) == before, name


def test_export_of_a_folder_that_is_not_a_measurement(tmp_path, capsys):
    assert main(["measure", "export", str(tmp_path), "--csv", str(tmp_path / "x.csv")]) == 2
    err = capsys.readouterr().err
    assert "not a measurement folder" in err and not (tmp_path / "x.csv").exists()


def test_capture_into_a_non_empty_folder(tmp_path, capsys):
    (tmp_path / "m").mkdir()
    (tmp_path / "m" / "keep.txt").write_text("x")
    assert main(["measure", "capture", str(BENCH), "--out", str(tmp_path / "m")]) == 2
    assert "not empty" in capsys.readouterr().err
    assert os.listdir(tmp_path / "m") == ["keep.txt"]


def test_simulate_on_a_pty_in_ascii_then_capture(tmp_path):
    """The CLI simulator on a pseudo-terminal, taxel-ascii, no corruption: every frame arrives."""
    (tmp_path / "rig.toml").write_text(_toml(rig_dict(protocol="taxel-ascii")))
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


def test_travel_channel_takes_a_length_sensitivity(tmp_path, capsys):
    from taxel.studies.bench.rig import load_rig
    d = rig_dict()
    d["channels"].append({"index": 10, "name": "travel", "sensitivity": "1 V/mm"})
    assert parse_ok(d).ordered()[10].volts_per_si == pytest.approx(1000.0)
    for bad, words in (("0.5 V/N", "travel sensitivity"), (None, "travel channel needs its sensitivity")):
        d["channels"][10] = {"index": 10, "name": "travel", **({"sensitivity": bad} if bad else {})}
        (tmp_path / "rig.toml").write_text(_toml(d))
        assert main(["measure", "capture", str(tmp_path / "rig.toml"), "--seconds", "1",
                     "--out", str(tmp_path / "m")]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and words in err, err
        assert not (tmp_path / "m").exists()
    assert load_rig("thesis-bench-travel").n == 11


def parse_ok(d):
    from taxel.studies.bench.rig import parse_rig
    return parse_rig(d)
