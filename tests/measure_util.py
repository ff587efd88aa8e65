"""Helpers shared by the measure tests: small rigs and simulated streams."""

from __future__ import annotations

import numpy as np

from taxel.studies.measure import wire as W
from taxel.studies.measure.protocol import Frames, encode_frames
from taxel.studies.measure.rig import Rig, parse_rig


def rig_dict(url="loop://", protocol="taxel-cobs", rows=3, cols=3, rate="2 kHz"):
    chans = [{"index": r * cols + c, "name": f"taxel_{r}_{c}", "gain": 1.0} for r in range(rows) for c in range(cols)]
    chans.append({"index": rows * cols, "name": "force", "sensitivity": "0.5 V/N"})
    return {"name": "test", "port": {"url": url, "baud": 115200, "protocol": protocol},
            "sampling": {"rate": rate}, "adc": {"bits": 16, "range": ["-10 V", "10 V"]},
            "channels": chans, "conditioning": {"circuit": "charge_amplifier", "C_f": "820 pF", "R_f": "10 MOhm",
                                                "notch": True}}


def rig(url="loop://", protocol="taxel-cobs", **kw) -> Rig:
    return parse_rig(rig_dict(url, protocol, **kw))


def random_frames(n_frames: int, n: int = 10, seq0: int = 0, t0: int = 0, seed: int = 0) -> Frames:
    rng = np.random.default_rng(seed)
    k = np.arange(n_frames, dtype=np.int64)
    return Frames(((seq0 + k) % 65536).astype(np.uint16), ((t0 + 500 * k) % 2 ** 32).astype(np.uint32),
                  rng.integers(-2 ** 31, 2 ** 31, (n_frames, n)).astype(np.int32))


def wire_of(frames: Frames, protocol="taxel-cobs", corrupt=0.0, seed=1) -> W.Wire:
    return W.corrupt(encode_frames(frames, protocol), corrupt, np.random.default_rng(seed))
