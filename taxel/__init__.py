"""taxel: the open design tool for piezoelectric tactile sensors.

The public API, whatever subpackages have been imported:

- functions: `load`, `solve`, `lumped`, `mesh`, `read`, `run_study`, `run_optimization`,
  `report`, `work_precision`, `reduce`, `build_skin`, `serve_explorer` (taxel.api) and the
  measurement API `taxel.measure`;
- types: `Scene`, the result types (`StaticResult`, `FrequencyResult`,
  `TransientResult`, `LumpedResult`) and the error types (`SceneError`,
  `StudyError`, `OptimizeError`).

Everything is imported on first use, so `import taxel` (and `taxel --help`) stays
light. No public name is also a subpackage's (`taxel.optimize`, `taxel.skin` and
`taxel.explore` are the subpackages; tests/test_glossary.py checks it).
"""

from __future__ import annotations

import importlib

# name -> the module that defines it
_PUBLIC = {
    "load": "taxel.api", "solve": "taxel.api", "read": "taxel.api", "run_study": "taxel.api",
    "run_optimization": "taxel.api", "report": "taxel.api", "work_precision": "taxel.api",
    "serve_explorer": "taxel.api", "lumped": "taxel.api", "mesh": "taxel.api",
    "reduce": "taxel.api", "build_skin": "taxel.api",
    "Scene": "taxel.scene", "SceneError": "taxel.scene",
    "StaticResult": "taxel.analyses", "FrequencyResult": "taxel.analyses",
    "TransientResult": "taxel.analyses", "LumpedResult": "taxel.analyses",
    "StudyError": "taxel.studies.spec", "OptimizeError": "taxel.optimize.spec",
}

__all__ = sorted(_PUBLIC) + ["measure"]


def __getattr__(name):
    if name in _PUBLIC:
        value = getattr(importlib.import_module(_PUBLIC[name]), name)
        globals()[name] = value
        return value
    if name == "measure":
        return importlib.import_module("taxel.measure")
    raise AttributeError(f"module 'taxel' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
