"""Faults in measured data: a measurement.h5 cut short or corrupted (rebuilt from
raw.bin; every command that reads it says so in one line), a rig file that
contradicts the stream (refused at the first frames, nothing kept), and a disk
that fills during a capture (one line; every byte written to raw.bin intact; the
folder rebuilds once space is freed).

Each capture is real: the simulator's player streams over a loopback socket into
`taxel measure capture` (pyserial's socket:// port). Waits are event-driven (bytes
appear in raw.bin, the process exits) with generous ceilings only a hung capture
reaches.
"""

from __future__ import annotations

import subprocess
import sys
import time

import numpy as np
import pytest
from measure_util import random_frames, rig, wire_of
from faults_util import fill, small_disk  # noqa: F401  (the small tmpfs fixture)
from test_measure_capture import _rig_file
from waits import CEILING, poll_until               # reached only by a capture that hangs

from taxel.cli import main
from taxel.studies.bench import folder as F
from taxel.studies.bench.capture import capture
from taxel.studies.bench.stream_check import FIRST_FRAMES, StreamMismatch
from taxel.studies.bench.wire import Player

RATE = 2000.0


def _captured(tmp_path, n=3000):
    frames = random_frames(n)
    with Player.tcp(wire_of(frames), None, linger=0.1) as player:    # all at once
        capture(rig(player.url), tmp_path / "m", seconds=CEILING)
    return frames, tmp_path / "m"


def _cut(path):
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def _flip_data(path):
    """Corrupt bytes inside the datasets' chunks, past the metadata: the file still opens."""
    b = bytearray(path.read_bytes())
    for i in range(len(b) - 4096, len(b) - 64, 97):
        b[i] ^= 0x5A
    path.write_bytes(bytes(b))


def _zero(path):
    path.write_bytes(b"\0" * path.stat().st_size)


COMMANDS = [["measure", "analyze", "m"], ["measure", "export", "m", "--csv", "x.csv"],
            ["measure", "localize", "m", "--presses", "p.json"],
            ["measure", "calibrate", "m", "--scene", "thesis-pzt-3x3-2d"]]


@pytest.mark.parametrize("damage", [_cut, _flip_data, _zero], ids=["truncated", "corrupted-data", "zeroed"])
def test_a_damaged_hdf5_is_one_line_for_every_reader_and_rebuild_recovers_it(tmp_path, damage, monkeypatch,
                                                                              capsys):
    frames, folder = _captured(tmp_path)
    damage(folder / "measurement.h5")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "p.json").write_text("[]")
    for argv in COMMANDS:
        capsys.readouterr()
        code = main(argv)
        err = capsys.readouterr().err.strip().splitlines()
        assert code == 2 and len(err) == 1, (argv, err)
        assert "measurement.h5" in err[0] and "taxel measure rebuild" in err[0], err
        assert not (tmp_path / "x.csv").exists()
    assert main(["measure", "rebuild", "m"]) == 0
    m = F.read(folder)
    assert np.array_equal(m.counts, frames.counts) and np.array_equal(m.seq, frames.seq)
    assert m.stats["crc_failures"] == 0


@pytest.mark.parametrize("stream, words", [
    (dict(protocol="taxel-ascii", n=10), ('port.protocol = "taxel-ascii"',)),
    (dict(protocol="taxel-cobs", n=5), ("5 channels", "[[channels]]", "lists 10")),
    (dict(protocol="taxel-ascii", n=4), ("taxel-ascii", "4 channels")),
])
def test_a_rig_file_that_contradicts_the_stream_is_one_line_at_the_first_frames(tmp_path, stream, words, capsys,
                                                                                  monkeypatch):
    frames = random_frames(120_000, n=stream["n"])                      # 60 s at 2 kHz
    monkeypatch.chdir(tmp_path)
    with Player.tcp(wire_of(frames, stream["protocol"]), RATE, linger=1) as player:
        rig_file = _rig_file(tmp_path, player.url)                     # taxel-cobs, 10 channels
        t0 = time.monotonic()
        code = main(["measure", "capture", str(rig_file), "--out", "m", "--quiet"])
        seconds = time.monotonic() - t0
    err = [x for x in capsys.readouterr().err.splitlines() if x.startswith("taxel:")]
    assert code == 2 and len(err) == 1, err
    assert "contradicts the rig file" in err[0] and all(w in err[0] for w in words), err[0]
    assert not (tmp_path / "m").exists()
    # at the first frames: long before the 60 s stream ends (a capture that read on would take 60 s;
    # the refusal takes well under a second here, so 60 s holds on a busy machine too)
    assert seconds < len(frames) / RATE and len(frames) > FIRST_FRAMES


def test_the_check_passes_a_stream_that_starts_mid_frame(tmp_path):
    frames = random_frames(600)
    wire = wire_of(frames)
    with Player.tcp(wire, RATE, linger=0.1) as player:
        res = capture(rig(player.url), tmp_path / "m", seconds=CEILING)
    assert res.stats["frames"] == len(frames)
    with pytest.raises(StreamMismatch):      # and the same rig on garbage is refused
        with Player.tcp(wire_of(random_frames(600, n=3)), RATE, linger=0.1) as player:
            capture(rig(player.url), tmp_path / "m2", seconds=CEILING)
    assert not (tmp_path / "m2").exists()


def _wait_for_bytes(path, proc):
    poll_until(lambda: path.exists() and path.stat().st_size > 0, f"bytes in {path}", proc)


@pytest.mark.slow
def test_a_full_disk_during_a_capture_is_one_line_and_every_received_byte_is_kept(tmp_path, small_disk):  # noqa: F811
    frames = random_frames(int(20 * RATE))                  # 20 s of stream: the disk fills long before
    wire = wire_of(frames)
    out = small_disk / "m"
    with Player.tcp(wire, RATE, linger=1) as player:
        proc = subprocess.Popen([sys.executable, "-m", "taxel.cli", "measure", "capture",
                                 str(_rig_file(tmp_path, player.url)), "--out", str(out), "--quiet"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        _wait_for_bytes(out / "raw.bin", proc)
        filler = fill(small_disk)
        _, err = proc.communicate(timeout=CEILING)
    lines = [x for x in err.splitlines() if x.startswith("taxel:")]
    assert proc.returncode == 1 and len(lines) == 1 and "Traceback" not in err, err
    assert "no space left" in lines[0] and "taxel measure rebuild" in lines[0]
    raw = (out / "raw.bin").read_bytes()
    assert 0 < len(raw) < len(wire.data)
    assert raw == wire.data[:len(raw)]                       # every byte written is intact, in order
    filler.unlink()                                          # space freed: the folder rebuilds
    assert main(["measure", "rebuild", str(out)]) == 0
    m = F.read(out)
    k = len(m)
    assert 0 < k and np.array_equal(m.counts, frames.counts[:k]) and m.stats["crc_failures"] == 0
