"""The study store: one SQLite row per design point, keyed by what the result depends on.

Each design point is a pure function of its scene: its key is the SHA-256 of the
validated scene (canonical JSON) and of the code version (a hash of the sources
a result depends on). Results live in an SQLite database in the study folder
(`results.sqlite`): one row per key, written in one transaction when the point
finishes, so an interrupted run (Ctrl-C, kill -9, power loss) loses at most the
points in flight and never stores one twice; a rerun skips every finished point.
Failed points are stored with their error. `Store.get_or_compute` is the one
cached evaluation every caller uses.
"""

from __future__ import annotations

import errno
import hashlib
import json
import sqlite3
import time
from functools import cache
from pathlib import Path

from taxel.analyses.results.outputs import table
from taxel.analyses.solves.version import code_version as _code_version
from taxel.scene import SceneError, canonical, parse
from taxel.studies.evaluate import evaluate_safely

@cache
def code_version() -> str:
    """Hash of the sources a result depends on: the scene schema, the analyses,
    the FEM and the meshing (taxel.analyses.solves.version), and this evaluation."""
    return _code_version(Path(__file__).parent / "evaluate.py")


def point_key(scene_data: dict) -> str:
    """The key of a design point (raises SceneError for an invalid scene)."""
    scene = parse({**scene_data, "name": "point"})
    return hashlib.sha256((canonical(scene) + code_version()).encode()).hexdigest()


class StoreError(ValueError):
    """A store that cannot be read; one line naming the file and how to recover."""


class StoreFull(OSError):
    """No space left for the store: the points already stored are intact (each is one
    SQLite transaction); free space and run again to resume."""

    def __init__(self, path: Path):
        super().__init__(errno.ENOSPC, "no space left on the device for the results store; the points "
                         "already stored are intact: free space and run again to resume", str(path))


def _full(exc: sqlite3.Error) -> bool:
    return isinstance(exc, sqlite3.OperationalError) and "full" in str(exc).lower()


class Store:
    """The study's SQLite database: one row per design point key. A corrupt file
    (a garbage header, a garbage or truncated page) is refused on opening, by
    SQLite's own quick_check, with one line that says how to recover."""

    def __init__(self, folder: Path):
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        self.path = folder / "results.sqlite"
        try:
            self.db = sqlite3.connect(self.path, timeout=30)
            check = self.db.execute("PRAGMA quick_check").fetchone()[0]
            if check != "ok":
                raise sqlite3.DatabaseError(check)
            self.db.execute("PRAGMA journal_mode=WAL")
            self.db.execute("PRAGMA synchronous=FULL")
            self.db.execute("""CREATE TABLE IF NOT EXISTS points (
                key TEXT PRIMARY KEY, params TEXT NOT NULL, status TEXT NOT NULL,
                result TEXT, error TEXT, seconds REAL, finished REAL)""")
            self.db.commit()
            cols = [r[1] for r in self.db.execute("PRAGMA table_info(points)")]
            if cols[:3] != ["key", "params", "status"]:
                raise sqlite3.DatabaseError("not a taxel results store")
        except sqlite3.DatabaseError as exc:
            if _full(exc):
                raise StoreFull(self.path) from None
            raise StoreError(f"{self.path}: the results store is corrupt or not a taxel store ({exc}); "
                             f"move it aside (mv {self.path} {self.path}.bad) and rerun") from None

    def status(self) -> dict[str, str]:
        return dict(self.db.execute("SELECT key, status FROM points"))

    def put(self, key, params, status, result=None, error=None, seconds=0.0):
        try:
            with self.db:                 # one transaction: a point is stored whole or not at all
                self.db.execute("INSERT OR REPLACE INTO points VALUES (?, ?, ?, ?, ?, ?, ?)",
                                (key, json.dumps(params), status, json.dumps(result) if result is not None else None,
                                 error, seconds, time.time()))
        except sqlite3.OperationalError as exc:
            if _full(exc):                # rolled back: the store holds every earlier point, whole
                raise StoreFull(self.path) from None
            raise

    def rows(self, keys=None):
        cur = self.db.execute("SELECT key, params, status, result, error, seconds FROM points")
        out = []
        for key, params, status, result, error, seconds in cur:
            if keys is None or key in keys:
                out.append({"key": key, "params": json.loads(params), "status": status,
                            "result": json.loads(result) if result else None, "error": error,
                            "seconds": seconds})
        return out

    def get(self, key) -> dict | None:
        """The stored row of a key, or None."""
        rows = self.rows({key})
        return rows[0] if rows else None

    def get_or_compute(self, scene_data: dict, outputs: tuple[str, ...], params=None):
        """(status, result, error) of a design point: from the store if it was solved
        before, else evaluated now and stored (a stored failure is retried). An
        invalid scene is 'failed' with its one-line error, and not stored."""
        try:
            key = point_key(scene_data)
        except SceneError as exc:
            return "failed", None, f"SceneError: {exc}"
        row = self.get(key)
        if row is not None and row["status"] == "done":
            return "done", row["result"], None
        status, result, error = evaluate_safely(scene_data, outputs)
        self.put(key, params if params is not None else {}, status, result, error,
                 (result or {}).get("seconds", 0.0))
        return status, result, error

    def close(self):
        self.db.close()


def tidy_rows(out: Path) -> list[dict]:
    """One flat row per point: parameters, status, the outputs per taxel
    (voltage_<taxel>, short_circuit_charge_<taxel>), then the named outputs: pressed_voltage (V)
    and sensitivity (V/N) of the pressed taxel, crosstalk, max_strain, the seconds, and
    the charge sensitivity and, when the scene names a readout, the readout's numbers
    (readout_sensitivity, readout_crosstalk, min_detectable_force, force_range). Rows stored by an older release (no "outputs") read the same."""
    store = Store(out)
    rows = []
    for r in store.rows():
        row = {}
        for k, v in r["params"].items():
            if isinstance(v, dict) and "label" in v:
                v = v["label"]
            elif isinstance(v, dict):                 # an unlabelled table: "key=value; ..."
                v = "; ".join(f"{a}={b}" for a, b in v.items())
            row[k] = v
        row["status"] = r["status"]
        res = r["result"] or {}
        for name in ("voltage", "short_circuit_charge"):
            for taxel, val in (res.get(name) or {}).items():
                row[f"{name}_{taxel}"] = val
        named = res.get("outputs") or {}
        if res.get("pressed") and res.get("voltage"):     # rows stored before "outputs" have only these
            row["pressed_voltage"] = named.get("pressed_voltage", res["voltage"].get(res["pressed"]))
            if "sensitivity" in named:
                row["sensitivity"] = named["sensitivity"]
            elif res.get("force"):
                row["sensitivity"] = res["voltage"].get(res["pressed"]) / abs(res["force"])
        for name in ("crosstalk", "max_strain", "seconds"):
            if name in res:
                row[name] = res[name]
        for name in ("charge_sensitivity", *table("readout")):   # with a [readout]: its numbers beside
            if named.get(name) is not None:                       # the open circuit's (analyses.solves.at_readout)
                row[name] = named[name]
        if "requested_load" in res:       # stopped short (studies.evaluate): the outputs are at this load
            row["stopped_at"] = res["force"]
            if res.get("stop"):           # and why (rows stored before it have no stop)
                row["stop"] = res["stop"]
        row["error"] = r["error"] or ""
        rows.append(row)
    store.close()
    return rows


def write_rows(rows: list[dict], path) -> None:
    """A CSV of dict rows; columns in first-seen order."""
    import csv
    cols = []
    for r in rows:
        cols += [k for k in r if k not in cols]
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=cols)
        w.writeheader()
        w.writerows(rows)
