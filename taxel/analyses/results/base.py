"""What every analysis result shares: the one protocol, and the error estimate.

The one result protocol every analysis result follows (static, frequency,
transient, lumped), in the spirit of scipy.optimize's OptimizeResult:

- `record()`: a JSON-ready dict, SI units, unit-suffixed keys, with "kind" and "format";
- `summary()`: lines for a person (`str(result)` joins them);
- `to_folder(dir)`: writes the result's folder, as `taxel solve --out` leaves it:
  result.json, scene.json, the result's CSV, its figures and summary.txt;
- `error`: the ErrorEstimate, or None (the record's "error_note" says why);
- `outputs()`: the named scalar outputs studies, optimization and reports use;
- `success` and `stop`: whether the solve reached its load and, where it did not (a
  static solve that stopped short), what was asked, what was reached and why.

`taxel.analyses.read(folder)` reads a folder's result.json back into the same type.

Error estimate: `ErrorEstimate`, one `OutputError` per output, and the names
of the outputs it covers.

Writing a result folder: the CSV and scene files, `result.json` with its kind and
format version, and `summary.txt`; each result's `to_folder` writes its whole folder
with these and its figures (results.figures). taxel.analyses.output_folder makes the
folder whole or not at all.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol, runtime_checkable

from taxel.scene import Scene
from taxel.schema import electrode_name, to_data

OUTPUT_NAMES = {"sensitivity": "pressed-taxel voltage per newton", "crosstalk": "crosstalk",
                "charge_sensitivity": "pressed-taxel short-circuit charge per newton",
                "readout_sensitivity": "readout output per newton, largest over the sweep"}

# why a result has no error estimate, per analysis kind
NOT_ESTIMATED = {"static": "not estimated (taxel solve --estimate)",
                 "frequency": "not estimated (taxel solve --estimate)",
                 "transient": "not estimated (no error estimate for a transient)",
                 "lumped": "not estimated (the lumped model has no error estimate)",
                 "noise": "not estimated (a noise budget's transfer function is the frequency analysis's)"}


@dataclass
class OutputError:
    """The estimated relative error of one output, split into its parts (each a
    relative error >= 0, or None when that part was not estimated)."""

    value: float                          # the output itself (SI: V/N, ratio, C/N)
    discretisation: float | None = None   # against the same model on a converged mesh
    model_form: float | None = None       # 2D / axisymmetric against 3D
    material: float | None = None         # linear silicone against Yeoh

    @property
    def total(self) -> float:
        """The parts added (a bound: they may partly cancel)."""
        return sum(x for x in (self.discretisation, self.model_form, self.material) if x is not None)

    def record(self) -> dict:
        return {"value": self.value, "discretisation": self.discretisation, "model_form": self.model_form,
                "material": self.material, "total": self.total}

    @classmethod
    def from_record(cls, rec: dict) -> OutputError:
        return cls(rec["value"], rec.get("discretisation"), rec.get("model_form"), rec.get("material"))


@dataclass
class ErrorEstimate:
    """A result's estimated error on each output (taxel.analyses.accuracy.error_estimate), how
    each part was found, and what the estimate cost."""

    outputs: dict[str, OutputError]
    how: list[str] = field(default_factory=list)
    seconds: float = 0.0
    # how the discretisation part was found ("three nested meshes", "two nested meshes,
    # widened", "coarser mesh, widened", "cheapest 3D mesh, measured") and the order used
    method: str = ""
    order: float | None = None

    def within(self, tolerance: float, names=None) -> bool:
        return all(self.outputs[k].total <= tolerance for k in (names or self.outputs) if k in self.outputs)

    def record(self) -> dict:
        return {"outputs": {k: e.record() for k, e in self.outputs.items()}, "how": self.how,
                "seconds": self.seconds, "method": self.method, "order": self.order}

    @classmethod
    def from_record(cls, rec: dict) -> ErrorEstimate:
        """The estimate of a result.json."""
        outs = {k: OutputError.from_record(v) for k, v in rec["outputs"].items()}
        return cls(outs, list(rec.get("how", [])), float(rec.get("seconds", 0.0)), rec.get("method", ""),
                   rec.get("order"))

    def lines(self) -> list[str]:
        def pct(x):
            return "-" if x is None else f"{100 * x:.2g} %"
        out = [f"{'estimated error':<46}{'discretisation':>15}{'model form':>12}{'material':>10}{'total':>10}"]
        for k, e in self.outputs.items():
            out.append(f"{OUTPUT_NAMES.get(k, k):<46}{pct(e.discretisation):>15}{pct(e.model_form):>12}"
                       f"{pct(e.material):>10}{pct(e.total):>10}")
        if self.method:
            out.append(f"  discretisation by {self.method}" + ("" if self.order is None else f", order {self.order:.3g}"))
        return out + [f"  {h}" for h in self.how] + [f"  (the estimate took {self.seconds:.2f} s)"]


def error_record(error: ErrorEstimate | None, kind: str) -> dict:
    """The "error_estimate" and "error_note" keys of a record: the estimate, or None
    and the reason there is none."""
    return {"error_estimate": None if error is None else error.record(),
            "error_note": "" if error is not None else NOT_ESTIMATED[kind]}


def error_lines(error: ErrorEstimate | None, kind: str) -> list[str]:
    """The summary lines of the estimate, or the one line saying why there is none."""
    return error.lines() if error is not None else [f"error: {NOT_ESTIMATED[kind]}"]


def read_error(rec: dict) -> ErrorEstimate | None:
    """The ErrorEstimate of a record, or None."""
    e = rec.get("error_estimate")
    return None if e is None else ErrorEstimate.from_record(e)


KINDS = ("static", "frequency", "transient", "lumped", "noise")
MEMBERS = ("record", "summary", "to_folder", "error", "outputs")


@runtime_checkable
class AnalysisResult(Protocol):
    """What every analysis result offers (see the module docstring)."""

    scene: Scene
    error: ErrorEstimate | None
    kind: str
    success: bool

    def record(self) -> dict: ...

    def summary(self) -> list[str]: ...

    def to_folder(self, out) -> list[Path]: ...

    def outputs(self) -> dict[str, float]: ...


def pressed_name(scene: Scene, names) -> str | None:
    """The electrode of the pressed taxel when the load presses one of `names`."""
    if scene.array is None or scene.load.kind not in ("taxel", "probe"):
        return None
    name = electrode_name(scene.load.taxel[0], scene.load.taxel[1])
    return name if name in names else None


# result.json's layout version: 1 adds "kind", "format", "outputs" and "error_note"
# (a static result.json without them is format 0, read as static)
FORMAT = 1


def write_csv(path: Path, header, columns) -> Path:
    """A CSV of equally long columns, 9 significant digits."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for row in zip(*columns):
            w.writerow([f"{v:.9g}" for v in row])
    return path


def write_scene(out: Path, scene: Scene) -> Path:
    """scene.json: the validated scene with units, readable by taxel.scene.parse."""
    path = Path(out) / "scene.json"
    path.write_text(json.dumps(to_data(scene), indent=1))
    return path


def write_result(out, record: dict, scene: Scene) -> list[Path]:
    """Make `out` and write the two files every result folder holds: result.json (a
    result's `record()`) and scene.json. Returns their paths."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "result.json"
    path.write_text(json.dumps(record, indent=1))
    return [write_scene(out, scene), path]


def write_summary(out, lines: list[str]) -> Path:
    """summary.txt: a result's summary lines, as `taxel solve` prints them."""
    path = Path(out) / "summary.txt"
    path.write_text("\n".join(lines) + "\n")
    return path
