"""The one result protocol every analysis result follows (static, frequency,
transient, lumped), in the spirit of scipy.optimize's OptimizeResult:

- `record()`: a JSON-ready dict, SI units, unit-suffixed keys, with "kind" and "format";
- `summary()`: lines for a person (`str(result)` joins them);
- `to_folder(dir)`: writes result.json, scene.json and the result's CSV;
- `error`: the ErrorEstimate, or None (the record's "error_note" says why);
- `outputs()`: the named scalar outputs studies, optimization and reports use.

`taxel.analyses.read(folder)` reads a folder's result.json back into the same type.
"""

from __future__ import annotations

from pathlib import Path
from typing import Protocol, runtime_checkable

from taxel.scene import Scene
from taxel.analyses.results.errors import ErrorEstimate
from taxel.schema import electrode_name

KINDS = ("static", "frequency", "transient", "lumped", "noise")
MEMBERS = ("record", "summary", "to_folder", "error", "outputs")


@runtime_checkable
class AnalysisResult(Protocol):
    """What every analysis result offers (see the module docstring)."""

    scene: Scene
    error: ErrorEstimate | None
    kind: str

    def record(self) -> dict: ...

    def summary(self) -> list[str]: ...

    def to_folder(self, out) -> list[Path]: ...

    def outputs(self) -> dict[str, float]: ...


def pressed_name(scene: Scene, names) -> str | None:
    """The electrode of the pressed taxel when the load presses one of `names`."""
    if scene.array is None or scene.load.kind not in ("taxel", "indenter"):
        return None
    name = electrode_name(scene.load.taxel[0], scene.load.taxel[1])
    return name if name in names else None
