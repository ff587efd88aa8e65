"""Capture through the real pyserial path: a pseudo-terminal and a loopback TCP
socket fed by the simulator's player; kill -9, Ctrl-C and a vanished port."""

import json
import os
import signal
import subprocess
import sys

import numpy as np
import pytest
from measure_util import random_frames, rig, rig_dict, wire_of
from waits import CEILING, poll_until

from taxel.studies.bench import folder as F
from taxel.studies.bench.capture import PortError, capture, open_port
from taxel.studies.bench.wire import Player

RATE = 2000.0


def _check_all(res, frames):
    m = F.read(res.folder)
    assert m.seq.tolist() == frames.seq.tolist() and m.t_us.tolist() == frames.t_us.tolist()
    assert np.array_equal(m.counts, frames.counts)
    s = res.stats
    assert s["frames"] == len(frames)
    assert s["crc_failures"] == s["cobs_failures"] == s["length_failures"] == 0
    assert s["seq_gaps"] == s["frames_lost"] == s["resyncs"] == 0
    assert s["rate_Hz"] == pytest.approx(RATE, rel=1e-9)
    rebuilt = F.rebuild(res.folder)                     # raw.bin holds the same
    assert np.array_equal(rebuilt.counts, frames.counts)


@pytest.mark.parametrize("protocol", ["taxel-cobs", "taxel-ascii"])
def test_capture_pty_every_frame_with_wrap(tmp_path, protocol):
    frames = random_frames(2000, seq0=64800, t0=2 ** 32 - 300_000)      # 1 s; seq and t_us wrap
    with Player.pty(wire_of(frames, protocol), RATE, linger=30, start=False) as player:
        r = rig(player.url, protocol)
        port = open_port(r)                   # opening empties the input buffer: stream after it
        player.start()
        res = capture(r, tmp_path / "m", seconds=1.8, port=port)
    assert res.ended == "seconds"
    _check_all(res, frames)


def test_capture_socket_every_frame(tmp_path):
    frames = random_frames(2000)
    with Player.tcp(wire_of(frames), RATE, linger=30) as player:
        res = capture(rig(player.url), tmp_path / "m", seconds=1.8)
    _check_all(res, frames)


@pytest.mark.parametrize("kind", ["tcp", "pty"])
def test_port_vanishes_data_kept(tmp_path, kind):
    frames = random_frames(1000)
    player = Player.tcp(wire_of(frames), RATE, linger=0.3) if kind == "tcp" else \
        Player.pty(wire_of(frames), RATE, linger=0.3, start=False)
    with player:
        r = rig(player.url)
        port = open_port(r)
        player.start()
        res = capture(r, tmp_path / "m", seconds=20, port=port)
    assert res.ended == "port vanished" and "vanished" in res.message and "\n" not in res.message
    assert res.stats["seconds"] < 10
    m = F.read(tmp_path / "m")
    assert m.stats["status"] == "port vanished"
    assert len(m) == len(frames) and np.array_equal(m.counts, frames.counts)


def _interruptible():
    """In the child: SIGINT back to its default, as in a terminal. A test run started in the
    background by a non-interactive shell (nohup, &) inherits SIGINT ignored, and Python then
    installs no KeyboardInterrupt handler, so Ctrl-C would never reach the capture."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _cli(*args, **kw):
    return subprocess.Popen([sys.executable, "-m", "taxel.cli", "measure", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, preexec_fn=_interruptible, **kw)


def _rig_file(tmp_path, url):
    d = rig_dict(url)
    lines = [f'name = "{d["name"]}"', "[port]", f'url = "{url}"', "baud = 115200", 'protocol = "taxel-cobs"',
             "[sampling]", 'rate = "2 kHz"']
    for c in d["channels"]:
        lines += ["[[channels]]", f"index = {c['index']}", f'name = "{c["name"]}"']
        lines += [f'sensitivity = "{c["sensitivity"]}"'] if "sensitivity" in c else [f"gain = {c['gain']}"]
    p = tmp_path / "rig.toml"
    p.write_text("\n".join(lines) + "\n")
    return p


def test_cli_vanished_port_is_one_line(tmp_path):
    frames = random_frames(400)
    with Player.tcp(wire_of(frames), RATE, linger=0.2) as player:
        proc = _cli("capture", str(_rig_file(tmp_path, player.url)), "--out", str(tmp_path / "m"), "--quiet")
        out, err = proc.communicate(timeout=CEILING)
    assert proc.returncode == 1
    lines = [x for x in err.splitlines() if x.startswith("taxel:")]
    assert len(lines) == 1 and "vanished" in lines[0], err
    assert len(F.read(tmp_path / "m")) == len(frames)


def _wait_for_bytes(path, size=1, proc=None):
    """Event-driven: until `path` holds `size` bytes (or the capture `proc` ended)."""
    poll_until(lambda: path.exists() and path.stat().st_size >= size, f"{size} bytes in {path}", proc)


# 60 s of stream: a capture stopped once it holds a second of it (event-driven) ends well
# before the stream does, however slow the machine
LONG = int(60 * RATE)


def test_kill_9_then_rebuild(tmp_path):
    frames = random_frames(LONG)                         # killed once a second of it is in raw.bin
    wire = wire_of(frames)
    with Player.tcp(wire, RATE, linger=5) as player:
        proc = _cli("capture", str(_rig_file(tmp_path, player.url)), "--out", str(tmp_path / "m"), "--quiet")
        _wait_for_bytes(tmp_path / "m" / "raw.bin", len(wire.data) // 60, proc)
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=CEILING)
    folder = tmp_path / "m"
    assert (folder / "raw.bin").stat().st_size > 0
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["status"] == "capturing"               # it never finished
    try:
        before = F.read(folder)                            # the HDF5 as left by the kill (or rebuilt if damaged)
    except F.MeasurementError:
        before = None
    m = F.rebuild(folder)
    k = len(m)
    assert 0 < k < len(frames)
    assert np.array_equal(m.counts, frames.counts[:k]) and np.array_equal(m.seq, frames.seq[:k])
    assert m.stats["crc_failures"] == 0 and m.stats["seq_gaps"] == 0
    if before is not None:                                  # what was flushed is a prefix of what was received
        assert np.array_equal(before.counts, frames.counts[:len(before)])


def test_ctrl_c_stops_cleanly(tmp_path):
    frames = random_frames(LONG)                         # Ctrl-C once a second of it is in raw.bin
    wire = wire_of(frames)
    with Player.tcp(wire, RATE, linger=5) as player:
        proc = _cli("capture", str(_rig_file(tmp_path, player.url)), "--out", str(tmp_path / "m"), "--quiet")
        _wait_for_bytes(tmp_path / "m" / "raw.bin", len(wire.data) // 60, proc)
        proc.send_signal(signal.SIGINT)
        # the capture decodes what it holds and writes the HDF5 before it exits: seconds on a
        # busy machine (it once took more than 10 s); the ceiling only catches a hang
        out, err = proc.communicate(timeout=CEILING)
    assert proc.returncode == 0, err
    m = F.read(tmp_path / "m")
    assert m.stats["status"] == "interrupted" and 0 < len(m) < len(frames)
    assert m.stats["crc_failures"] == m.stats["cobs_failures"] == m.stats["resyncs"] == 0   # a cut frame
    assert m.stats["truncated_bytes"] < 52                                                # is not a failure
    assert np.array_equal(m.counts, frames.counts[:len(m)])
    assert np.array_equal(F.rebuild(tmp_path / "m").counts, m.counts)


def test_port_that_does_not_exist_writes_nothing(tmp_path):
    with pytest.raises(PortError, match="port.url = '/dev/nonexistent-taxel'"):
        capture(rig("/dev/nonexistent-taxel"), tmp_path / "m", seconds=1)
    assert not (tmp_path / "m").exists()
    proc = _cli("capture", str(_rig_file(tmp_path, "/dev/nonexistent-taxel")), "--out", str(tmp_path / "m2"))
    out, err = proc.communicate(timeout=CEILING)
    assert proc.returncode == 2 and len(err.strip().splitlines()) == 1 and "cannot open" in err
    assert not (tmp_path / "m2").exists()
    assert os.listdir(tmp_path) == ["rig.toml"]


def test_damaged_hdf5_points_to_rebuild(tmp_path):
    frames = random_frames(300)
    with Player.tcp(wire_of(frames), None, linger=0.1) as player:    # all at once
        res = capture(rig(player.url), tmp_path / "m", seconds=20)
    (tmp_path / "m" / "measurement.h5").write_bytes(b"\x89HDF\r\n\x1a\n" + b"\x00" * 100)   # a torn file
    with pytest.raises(F.MeasurementError, match="taxel measure rebuild"):
        F.read(tmp_path / "m")
    assert np.array_equal(F.rebuild(tmp_path / "m").counts, frames.counts)
    assert np.array_equal(F.read(tmp_path / "m").counts, frames.counts)
    assert res.stats["frames"] == len(frames)
