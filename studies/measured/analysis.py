"""`taxel measure analyze`: one measurement folder in, analysis.json (+ CSV) in it.

The record's kind (step, impulse, chirp, presses; studies.measured.events) decides
what is computed, each defined in its module:
  step     the first-order fit of every taxel that moved (studies.measured.step);
  presses  linearity of every taxel pressed at least three times;
  impulse  repeatability (both definitions) of the pressed taxel;
  chirp    H1 with coherence and the amplitude-spectrum ratio of the pressed taxel
           (the channel with the largest response), and with a scene the lumped
           model and the FEM (a frequency sweep, seconds in 2D) through the rig's
           readout chain with their RMS errors (studies.measured.frf).
A scene must describe the rig's array: every taxel_R_C channel inside its rows x cols.
Written: DIR/analysis.json, and DIR/analysis-frf.csv (chirp), DIR/analysis-peaks.csv
(presses, impulses). Nothing is written when the analysis fails.
"""

from __future__ import annotations

import csv
import io
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from taxel.studies.measured import events, frf, peaks
from taxel.studies.bench.folder import MeasurementError, read, write_json

JSON, FRF_CSV, PEAKS_CSV = "analysis.json", "analysis-frf.csv", "analysis-peaks.csv"


@dataclass
class Analysis:
    folder: Path
    kind: str
    scene: str | None
    steps: list[peaks.StepFit] = field(default_factory=list)
    linearity: list[peaks.Linearity] = field(default_factory=list)
    repeatability: list[peaks.Repeatability] = field(default_factory=list)
    frf: frf.FRF | None = None
    C_p_F: float | None = None

    def record(self) -> dict:
        return {"kind": self.kind, "scene": self.scene, "C_p_F": self.C_p_F,
                "step": [s.record() for s in self.steps],
                "linearity": [x.record() for x in self.linearity],
                "repeatability": [x.record() for x in self.repeatability],
                "frf": self.frf.record() if self.frf is not None else None}

    def summary(self) -> list[str]:
        lines = [f"{self.folder}: {self.kind}"]
        for s in self.steps:
            lines.append(f"  {s.taxel}: tau {s.tau_s:.4g} s (95 % {s.tau_ci95_s[0]:.4g}-{s.tau_ci95_s[1]:.4g})"
                         + (f", R_eff {s.R_eff_ohm:.4g} ohm" if s.R_eff_ohm else "")
                         + (f", R_f,eff {s.R_f_eff_ohm:.4g} ohm" if s.R_f_eff_ohm else ""))
        for x in self.linearity:
            lines.append(f"  {x.taxel}: {x.sensitivity_V_per_N:.4g} V/N, R = {x.r:.4f} over {x.n} presses")
        for x in self.repeatability:
            lines.append(f"  {x.taxel}: repeatability {x.by_spread_pct:.2f} % (1 - std/mean), "
                         f"{x.by_range_pct:.2f} % (1 - range/mean) over {x.n} impulses")
        if self.frf is not None:
            lines.append(f"  {self.frf.taxel}: H1 at {self.frf.freqs[1]:.3g} Hz resolution, coherence > 0.9 at "
                         f"{int(np.sum(self.frf.coherence > 0.9))} of {len(self.frf.freqs)} frequencies")
            for k in self.frf.models:
                e = frf.rms_error(self.frf, k)
                if e["rms_error_pct"] is not None:
                    lines.append(f"  {k} model: RMS error {e['rms_error_pct']:.2f} % over {e['band_Hz'][0]:g}-"
                                 f"{e['band_Hz'][1]:g} Hz (coherence > 0.9)")
        return lines

    def write(self) -> list[Path]:
        """analysis.json and the CSVs into the measurement folder (`to_folder`)."""
        return self.to_folder(self.folder)

    def to_folder(self, folder: str | Path | None = None) -> list[Path]:
        """analysis.json and the CSVs in `folder` (default: the measurement folder), each written whole
        (atomically) after everything was computed; returns the files written."""
        folder = Path(folder) if folder is not None else self.folder
        folder.mkdir(parents=True, exist_ok=True)
        written = [folder / JSON]
        files: dict[Path, str] = {}
        if self.frf is not None:
            files[folder / FRF_CSV] = _csv(self.frf.csv_header(), self.frf.csv_rows())
        rows = [[x.taxel, "presses", f, v] for x in self.linearity for f, v in zip(x.forces_N, x.peaks_V)]
        rows += [[x.taxel, "impulse", f, v] for x in self.repeatability for f, v in zip(x.forces_N, x.peaks_V)]
        if rows:
            files[folder / PEAKS_CSV] = _csv(["taxel", "event", "force_peak_N", "voltage_peak_V"], rows)
        for path, text in files.items():
            tmp = path.with_suffix(".tmp")
            tmp.write_text(text)
            tmp.replace(path)
            written.append(path)
        write_json(folder / JSON, self.record())
        return written

    @classmethod
    def read(cls, folder: str | Path) -> Analysis:
        """The analysis written in `folder` (analysis.json); one-line MeasurementError if there is none."""
        folder = Path(folder)
        try:
            rec = json.loads((folder / JSON).read_text())
        except (OSError, ValueError):
            raise MeasurementError(f"{folder}: no readable {JSON}; run 'taxel measure analyze {folder}' first") from None
        return cls(folder, rec["kind"], rec["scene"],
                   [peaks.StepFit(**{**s, "tau_ci95_s": tuple(s["tau_ci95_s"])}) for s in rec["step"]],
                   [peaks.Linearity(**x) for x in rec["linearity"]],
                   [peaks.Repeatability(**x) for x in rec["repeatability"]],
                   frf.FRF.from_record(rec["frf"]) if rec["frf"] is not None else None, rec["C_p_F"])


def _csv(header, rows) -> str:
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(header)
    w.writerows(rows)
    return buf.getvalue()


def check_scene(scene, rig, source: str = "scene") -> None:
    """The scene's array must hold every taxel channel of the rig (one-line MeasurementError)."""
    arr = scene.array
    if arr is None:
        raise MeasurementError(f"{source}: has no [array]; give a taxel-array scene matching the rig")
    for c in rig.ordered():
        if c.kind == "taxel" and not (c.taxel[0] < arr.rows and c.taxel[1] < arr.cols):
            raise MeasurementError(f"{source}: array.rows x array.cols is {arr.rows} x {arr.cols} but the rig has "
                                   f"channel {c.name}; give the scene of the measured array (or fix the rig's channels)")


def analyze_folder(folder, scene=None, scene_name: str | None = None, kind: str | None = None,
                   resolution: float = 1.0, fem: bool = True) -> Analysis:
    """The analysis of one measurement folder (module docstring); `scene` a taxel.scene.Scene or None."""
    m = read(folder)
    rec = events.record(m)
    if scene is not None:
        check_scene(scene, m.rig, scene_name or "scene")
    segs = events.segments(rec)
    kind = kind or events.kind_of(rec, segs)
    if kind not in events.KINDS:
        raise MeasurementError(f"--input {kind!r}: choose one of {', '.join(events.KINDS)}")
    lm = None
    if scene is not None:
        from taxel.analyses import lumped_model
        lm = lumped_model(scene)
    chains = m.rig.chains()
    out = Analysis(Path(folder), kind, scene_name, C_p_F=lm.C_p if lm is not None else None)
    if kind == "step":
        moved = _moved(rec)
        for k in moved:
            out.steps.append(peaks.fit_step(rec, k, chains[rec.names[k]], lm.C_p if lm is not None else None))
    elif kind == "presses":
        out.linearity = peaks.linearity(rec, segs)
    elif kind == "impulse":
        out.repeatability = peaks.repeatability(rec, segs)
    else:
        a, b = frf.chirp_span(rec)
        k = int(np.argmax(np.std(rec.volts[a:b], axis=0)))
        out.frf = frf.h1(rec, k, resolution)
        if lm is not None:
            out.frf.models["lumped"] = frf.lumped_frf(lm, chains[rec.names[k]].readout(), out.frf.freqs)
            coh = out.frf.freqs[out.frf.coherence > 0.9]
            if fem and len(coh):
                f = out.frf.freqs
                fem_H = np.full(len(f), np.nan, complex)
                upto = f <= coh.max()
                fem_H[upto] = frf.fem_frf(scene, chains[rec.names[k]].readout(), rec.taxels[k], f[upto])
                out.frf.models["fem"] = fem_H
    return out


def _moved(rec: events.Record) -> list[int]:
    """Taxel channels whose step response stands 20 x above their pre-step noise (the pressed one at least)."""
    segs = events.segments(rec, level=0.5)
    i0 = segs[0][0] if segs else len(rec.t) // 2
    pre = rec.volts[:max(2, i0 - int(0.02 * rec.rate))]
    post = rec.volts[i0:i0 + int(0.2 * rec.rate)]
    jump = np.abs(post - np.median(pre, axis=0)).max(axis=0)
    noise = np.std(pre, axis=0) + 1e-12
    best = int(np.argmax(jump))
    return sorted({best} | {k for k in range(len(jump)) if jump[k] > 20 * noise[k]})
