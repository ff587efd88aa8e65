"""Helpers shared by the measure tests: small rigs and simulated streams."""

from __future__ import annotations

import json

import numpy as np

from taxel.studies.bench import wire as W
from taxel.studies.bench.protocol import Frames, encode_frames
from taxel.studies.bench.rig import Rig, parse_rig


def rig_dict(url="loop://", protocol="taxel-cobs", rows=3, cols=3, rate="2 kHz"):
    chans = [{"index": r * cols + c, "name": f"taxel_{r}_{c}", "gain": 1.0} for r in range(rows) for c in range(cols)]
    chans.append({"index": rows * cols, "name": "force", "sensitivity": "0.5 V/N"})
    return {"name": "test", "port": {"url": url, "baud": 115200, "protocol": protocol},
            "sampling": {"rate": rate}, "adc": {"bits": 16, "range": ["-10 V", "10 V"]},
            "channels": chans, "conditioning": {"circuit": "charge_amplifier", "C_f": "820 pF", "R_f": "10 MOhm",
                                                "notch": True}}


def rig_toml(d: dict) -> str:
    """A rig file's TOML text from its dict (as `rig_dict` gives)."""
    lines = [f'name = "{d["name"]}"', "[port]"] + [f"{k} = {json.dumps(v)}" for k, v in d["port"].items()]
    lines += ["[sampling]"] + [f"{k} = {json.dumps(v)}" for k, v in d["sampling"].items()]
    for c in d["channels"]:
        lines += ["[[channels]]"] + [f"{k} = {json.dumps(v)}" for k, v in c.items()]
    lines += ["[conditioning]"] + [f"{k} = {json.dumps(v)}" for k, v in d.get("conditioning", {}).items()
                                   if not isinstance(v, dict)]
    for name, sub in d.get("conditioning", {}).items():
        if isinstance(sub, dict):
            lines += [f"[conditioning.{name}]"] + [f"{k} = {json.dumps(v)}" for k, v in sub.items()]
    if "probe" in d:
        lines += ["[probe]"] + [f"{k} = {json.dumps(v)}" for k, v in d["probe"].items()]
    return "\n".join(lines) + "\n"


def rig(url="loop://", protocol="taxel-cobs", **kw) -> Rig:
    return parse_rig(rig_dict(url, protocol, **kw))


def random_frames(n_frames: int, n: int = 10, seq0: int = 0, t0: int = 0, seed: int = 0) -> Frames:
    rng = np.random.default_rng(seed)
    k = np.arange(n_frames, dtype=np.int64)
    return Frames(((seq0 + k) % 65536).astype(np.uint16), ((t0 + 500 * k) % 2 ** 32).astype(np.uint32),
                  rng.integers(-2 ** 31, 2 ** 31, (n_frames, n)).astype(np.int32))


def wire_of(frames: Frames, protocol="taxel-cobs", corrupt=0.0, seed=1) -> W.Wire:
    return W.corrupt(encode_frames(frames, protocol), corrupt, np.random.default_rng(seed))


def write_lvm(path, names, t, values, decimal=".", sep="\t", segments=1):
    """A LabVIEW Measurement file (LVM 2.0 layout: file header, then per segment
    a header, the X_Value/channel heading, the rows), as LabVIEW's Write To
    Measurement File writes it with one X column."""
    def num(x):
        return f"{x:.9g}".replace(".", decimal)
    head = ["LabVIEW Measurement\t", "Writer_Version\t2", "Reader_Version\t2",
            f"Separator\t{'Tab' if sep == chr(9) else 'Comma'}", f"Decimal_Separator\t{decimal}",
            "Multi_Headings\tNo", "X_Columns\tOne", "Time_Pref\tRelative", "Operator\ttaxel",
            "Date\t2026/11/22", "Time\t12:00:00.000", "***End_of_Header***", ""]
    lines = list(head)
    bounds = np.linspace(0, len(t), segments + 1).astype(int)
    for a, b in zip(bounds[:-1], bounds[1:]):
        lines += [sep.join(["Channels", str(len(names))] + [""] * (len(names) - 1)),
                  sep.join(["Samples"] + [str(b - a)] * len(names)),
                  sep.join(["Date"] + ["2026/11/22"] * len(names)),
                  sep.join(["Time"] + ["12:00:00.000"] * len(names)),
                  sep.join(["X_Dimension"] + ["Time"] * len(names)),
                  sep.join(["X0"] + [num(t[a])] * len(names)),
                  sep.join(["Delta_X"] + [num(t[1] - t[0])] * len(names)),
                  "***End_of_Header***",
                  sep.join(["X_Value"] + list(names) + ["Comment"])]
        lines += [sep.join([num(t[i])] + [num(v) for v in values[i]]) for i in range(a, b)]
        lines.append("")
    from pathlib import Path
    Path(path).write_text("\r\n".join(lines) + "\r\n", encoding="latin-1")
