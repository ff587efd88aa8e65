"""Reading a result folder back: `read(folder)` turns its result.json (and
scene.json) into the result type that wrote it, holding the numbers but not the
mesh and fields (see each type's docstring)."""

from __future__ import annotations

import json
from pathlib import Path

from taxel.scene import SceneError, parse
from taxel.analyses.results.dynamic import FrequencyResult, LumpedResult, TransientResult
from taxel.analyses.results.folders import FORMAT
from taxel.analyses.results.noise import NoiseResult
from taxel.analyses.results.static import StaticResult

RESULT_TYPES = {"static": StaticResult, "frequency": FrequencyResult, "transient": TransientResult,
                "lumped": LumpedResult,
                "noise": NoiseResult}


class ResultError(ValueError):
    """A folder without a readable result; one line naming the file and the fix."""


def _json(path: Path) -> dict:
    if not path.is_file():
        raise ResultError(f"{path}: no such file; write the folder with taxel solve SCENE --out DIR "
                          "(or result.to_folder(DIR))")
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        raise ResultError(f"{path}: not readable JSON ({exc}); write the folder again") from None
    if not isinstance(data, dict):
        raise ResultError(f"{path}: not a JSON object; write the folder again")
    return data


def result_kind(folder) -> str | None:
    """The "kind" of the folder's result.json ("static", "frequency", "transient",
    "lumped"; an optimization's "optimum" or "front"), or None when it has none."""
    path = Path(folder) / "result.json"
    if not path.is_file():
        return None
    rec = _json(path)
    return rec.get("kind", "static" if "electrodes" in rec else None)


def read_record(folder) -> dict:
    """The folder's result.json, checked for its kind and format."""
    path = Path(folder) / "result.json"
    rec = _json(path)
    if "kind" not in rec:
        raise ResultError(f"{path}: no \"kind\": not a result taxel wrote; write the folder again")
    if rec["kind"] not in RESULT_TYPES:
        raise ResultError(f"{path}: kind = '{rec['kind']}' is not one of {', '.join(RESULT_TYPES)}")
    if rec.get("format", 0) > FORMAT:
        raise ResultError(f"{path}: format {rec['format']} is newer than this release reads ({FORMAT}); "
                          "update taxel")
    return rec


def read(folder) -> StaticResult | FrequencyResult | TransientResult | LumpedResult | NoiseResult:
    """The result a folder holds (result.json and scene.json), as the type that wrote
    it: the same `record()` and `outputs()`; no mesh, fields or port matrices.
    Raises ResultError (one line) for a folder without a readable result."""
    folder = Path(folder)
    rec = read_record(folder)
    try:
        scene = parse(_json(folder / "scene.json"))
    except SceneError as exc:
        raise ResultError(f"{folder / 'scene.json'}: {exc}") from None
    try:
        return RESULT_TYPES[rec["kind"]].from_record(scene, rec)
    except (KeyError, TypeError, ValueError) as exc:
        raise ResultError(f"{folder / 'result.json'}: a {rec['kind']} result without a readable "
                          f"{exc.args[0] if isinstance(exc, KeyError) else 'value'} ({exc}); write the folder "
                          "again") from None
