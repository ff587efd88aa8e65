"""Export a measurement folder to CSV: one row per accepted frame, in stream order,
columns seq,t_us,<channel names>; seq and t_us as received, the channels in SI
(V out of each taxel's conditioning, N for the force) or in ADC counts (raw)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from taxel.studies.measure.folder import MeasurementError, read


def export_csv(folder: str | Path, path: str | Path, raw: bool = False) -> int:
    """Write the CSV; returns the number of rows."""
    m = read(folder)
    if raw and m.counts is None:
        raise MeasurementError(f"{folder}: imported from an analog file, it has no ADC counts; export without --raw")
    values = m.counts if raw else m.values
    header = ",".join(["seq", "t_us"] + m.rig.names)
    fmt = ["%d", "%d"] + (["%d"] if raw else ["%.17g"]) * m.rig.n
    table = np.column_stack([m.seq.astype(np.int64), m.t_us.astype(np.int64), values]) if raw else None
    path = Path(path)
    try:
        with open(path, "w", newline="") as f:
            f.write(header + "\n")
            if raw:
                np.savetxt(f, table, fmt=",".join(fmt))
            else:
                for s, t, row in zip(m.seq, m.t_us, values):
                    f.write(f"{s},{t}," + ",".join(repr(float(v)) for v in row) + "\n")
    except OSError as exc:
        raise MeasurementError(f"--csv {path}: cannot write it ({exc.strerror or exc})") from None
    return len(m)
