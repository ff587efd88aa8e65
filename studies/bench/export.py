"""Export a measurement folder to CSV: one row per accepted frame, in stream order,
columns seq,t_us,<channel names>; seq and t_us as received, the channels in SI
(V out of each taxel's conditioning, N for the force) or in ADC counts (raw)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from taxel.studies.bench.folder import MeasurementError, read


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


@dataclass
class CsvExport:
    """A measurement folder written as CSV (`export_csv`); `import_file` reads the CSV back."""

    folder: Path                       # the measurement folder exported
    path: Path                         # the CSV file
    rows: int
    raw: bool                          # ADC counts instead of SI values

    def record(self) -> dict:
        """JSON-ready: the folder, the file, the rows, counts or SI."""
        return {"folder": str(self.folder), "csv": str(self.path), "rows": self.rows, "raw": self.raw}

    def summary(self) -> list[str]:
        """For a person: the rows written and where."""
        return [f"{self.rows} rows written to {self.path}"]


def export(folder: str | Path, path: str | Path, raw: bool = False) -> CsvExport:
    """`export_csv` as a typed result."""
    return CsvExport(Path(folder), Path(path), export_csv(folder, path, raw=raw), raw)
