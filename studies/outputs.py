"""Writing a run's outputs into its folder: the scene (re-readable), tidy rows,
summaries. Shared by the command line and the main job."""

from __future__ import annotations

import csv
import json

from studies.scene import parse, to_data


def print_output(o, out=None):
    """Print a run's summary lines and files; keep the summary in the folder."""
    for line in o.summary:
        print(line)
    for f in o.files:
        print(f"wrote {f}")
    if out is not None:
        (out / "summary.txt").write_text("\n".join(o.summary) + "\n")


def write_scene(out, scene):
    """scene.json: the validated scene with units, readable by `studies.scene.parse`."""
    (out / "scene.json").write_text(json.dumps(to_data(scene), indent=1))


def write_rows(rows, path):
    """A CSV of dict rows; columns in first-seen order."""
    cols = []
    for r in rows:
        cols += [k for k in r if k not in cols]
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=cols)
        w.writeheader()
        w.writerows(rows)


def load_scene_data(data):
    """A validated scene from a scene dict (named "scene" unless it has a name)."""
    return parse({**data, "name": data.get("name", "scene")})
