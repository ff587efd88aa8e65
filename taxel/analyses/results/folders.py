"""Writing a result folder: whole or not at all (`output_folder`), the CSV and
scene files, `result.json` with its kind and format version, and `summary.txt`.
Each result's `to_folder` writes its whole folder with these (and its figures,
results.figures and results.fields)."""

from __future__ import annotations

import contextlib
import csv
import json
import shutil
import tempfile
from pathlib import Path

from taxel.scene import Scene
from taxel.schema import to_data

# result.json's layout version: 1 adds "kind", "format", "outputs" and "error_note"
# (a static result.json without them is format 0, read as static)
FORMAT = 1


@contextlib.contextmanager
def output_folder(path, replace: bool = False):
    """A folder written whole or not at all: the work goes to a temporary sibling
    that is renamed to `path` at the end and removed on failure, together with any
    parent folders made for it. An existing folder is updated in place, or, with
    `replace`, swapped for the new one only when it is complete.
    Raises ValueError (one line) when `path` cannot be a folder."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{path}: exists and is not a folder; choose another output folder")
    if path.is_dir() and not replace:
        yield path
        return
    made = [p for p in reversed(path.parents) if not p.exists()]
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", dir=path.parent))
    except OSError as exc:
        for p in reversed(made):
            shutil.rmtree(p, ignore_errors=True)
        raise ValueError(f"{path}: cannot create the output folder ({exc.strerror or exc}); "
                         "choose a writable place") from None
    try:
        yield tmp
        if path.is_dir():
            old = Path(tempfile.mkdtemp(prefix=f".{path.name}.old.", dir=path.parent))
            path.rename(old / path.name)
            tmp.rename(path)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(path)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        for p in reversed(made):
            shutil.rmtree(p, ignore_errors=True)
        raise


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
