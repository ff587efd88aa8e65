"""The code version of a result: a hash of the sources it depends on (the FEM, the
meshing, the analyses and the scene schema). Caches of computed results key on it
(taxel.analyses.solves.reduced.cached; studies.store.code_version adds the study's own
evaluation)."""

from __future__ import annotations

import hashlib
from functools import cache
from pathlib import Path


@cache
def source_hash() -> "hashlib._Hash":
    import taxel.analyses
    import taxel.fem
    import taxel.meshing
    import taxel.scene
    import taxel.scene_tables
    h = hashlib.sha256()
    for mod in (taxel.fem, taxel.meshing, taxel.analyses):
        for f in sorted(Path(mod.__path__[0]).rglob("*.py")):
            h.update(f.read_bytes())
    h.update(Path(taxel.scene.__file__).read_bytes())
    h.update(Path(taxel.scene_tables.__file__).read_bytes())
    return h


def code_version(*extra: Path) -> str:
    """16 hex digits of the SHA-256 of the sources (and of the files `extra`)."""
    h = source_hash().copy()
    for f in extra:
        h.update(Path(f).read_bytes())
    return h.hexdigest()[:16]
