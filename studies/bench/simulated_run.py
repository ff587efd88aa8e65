"""A run of the simulated rig as one object: the rig, the simulator's truth and the
byte stream it sends (after any corruption), written to and read from a folder.

    DIR/truth.npz    the arrays: t, force_command, force, charge, clean_volts, seq, t_us, counts,
                     and the stream's intact (per frame) and frame_ends
    DIR/truth.json   the parameters (settings, per-taxel gain and time-constant factors, presses,
                     crosstalk, ...) and the corruption's counts
    DIR/rig.json     the rig simulated
    DIR/stream.bin   the bytes as sent (with `stream`)
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from taxel.scene import Scene
from taxel.studies.bench.folder import RIG, MeasurementError, read_rig
from taxel.studies.bench.protocol import Frames, encode_frames
from taxel.studies.bench.rig import Rig
from taxel.studies.bench.signals import Settings, Truth, save_truth, simulate
from taxel.studies.bench.wire import Wire, corrupt

STREAM = "stream.bin"
WIRE_KEYS = ("flips", "drops", "corrupt", "protocol")
ARRAYS = ("t", "force_command", "force", "charge", "clean_volts")


@dataclass
class Simulation:
    """The simulated rig's run (module docstring)."""

    rig: Rig
    truth: Truth
    wire: Wire
    corrupt: float = 0.0               # the probability each byte was flipped or dropped

    def extra(self) -> dict:
        """The stream's part of the truth (what save_truth adds beside the simulator's)."""
        return {"intact": self.wire.intact, "frame_ends": self.wire.ends, "flips": self.wire.flips,
                "drops": self.wire.drops, "corrupt": self.corrupt, "protocol": self.rig.port.protocol}

    def record(self) -> dict:
        """JSON-ready: the rig's name, the simulator's parameters (truth.json) and the stream's counts."""
        rec = {"rig": self.rig.name, **self.truth.params, "frames": len(self.truth.t), "bytes": len(self.wire.data),
               "flips": self.wire.flips, "drops": self.wire.drops, "intact": int(self.wire.intact.sum()),
               "corrupt": self.corrupt, "protocol": self.rig.port.protocol}
        return json.loads(json.dumps(rec))

    def summary(self) -> list[str]:
        """For a person: the frames and bytes sent and what the corruption did."""
        w = self.wire
        return [f"{len(self.truth.t)} frames ({len(w.data)} bytes, {w.flips} flipped, {w.drops} dropped, "
                f"{int(w.intact.sum())} intact)"]

    def to_folder(self, folder: str | Path, stream: bool = True) -> Path:
        """truth.npz, truth.json and rig.json in `folder`, and with `stream` the bytes in stream.bin."""
        folder = Path(folder)
        save_truth(self.truth, folder, self.extra())
        (folder / RIG).write_text(self.rig.model_dump_json(indent=1))
        if stream:
            (folder / STREAM).write_bytes(self.wire.data)
        return folder

    @classmethod
    def read(cls, folder: str | Path) -> Simulation:
        """A folder written by `to_folder` (one-line MeasurementError if it is not one)."""
        folder = Path(folder)
        rig = read_rig(folder)
        try:
            params = json.loads((folder / "truth.json").read_text())
            with np.load(folder / "truth.npz") as z:
                a = {k: z[k] for k in z.files}
        except (OSError, ValueError):
            raise MeasurementError(f"{folder}: no readable truth.json and truth.npz; this is not a simulation "
                                   "folder (write one with Simulation.to_folder)") from None
        w = {k: params.pop(k) for k in WIRE_KEYS if k in params}
        frames = Frames(a["seq"], a["t_us"], a["counts"])
        truth = Truth(*(a[k] for k in ARRAYS), frames, params)
        data = (folder / STREAM).read_bytes() if (folder / STREAM).exists() else b""
        ends = a.get("frame_ends", np.zeros(0, np.int64))
        intact = a.get("intact", np.zeros(0, bool))
        return cls(rig, truth, Wire(data, ends, intact, int(w.get("flips", 0)), int(w.get("drops", 0))),
                   float(w.get("corrupt", 0.0)))


def run(rig: Rig, scene: Scene, settings: Settings, corrupt_p: float = 0.0) -> Simulation:
    """Simulate the rig (studies.bench.signals) and encode its frames in the rig's protocol, each byte
    flipped or dropped with probability `corrupt_p` (studies.bench.wire.corrupt, seeded by settings.seed + 1)."""
    if not 0 <= corrupt_p < 1:
        raise ValueError(f"corrupt must be a probability in [0, 1), got {corrupt_p}")
    truth = simulate(rig, scene, settings)
    chunks = encode_frames(truth.frames, rig.port.protocol)
    return Simulation(rig, truth, corrupt(chunks, corrupt_p, np.random.default_rng(settings.seed + 1)), corrupt_p)
