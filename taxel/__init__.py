"""taxel: the open design tool for piezoelectric tactile sensors.

The public API, whatever subpackages have been imported:

- functions: `load`, `solve`, `lumped`, `mesh`, `read`, `run_study`, `optimize`, `report`,
  `work_precision` (taxel.api) and the measurement API `taxel.measure`;
- types: `Scene`, the result types (`StaticResult`, `FrequencyResult`,
  `TransientResult`, `LumpedResult`) and the error types (`SceneError`,
  `StudyError`, `OptimizeError`).

Everything is imported on first use, so `import taxel` (and `taxel --help`) stays
light. The subpackages `taxel.optimize` and `taxel.skin` share a name with the
functions `taxel.optimize` and `taxel.skin`: importing a subpackage does not replace
the function here (the module's attribute is guarded), so `taxel.optimize(...)` and
`taxel.skin(...)` work after any import.
"""

from __future__ import annotations

import importlib
import sys
import types

# name -> the module that defines it
_PUBLIC = {
    "load": "taxel.api", "solve": "taxel.api", "read": "taxel.api", "run_study": "taxel.api",
    "optimize": "taxel.api", "report": "taxel.api", "work_precision": "taxel.api",
    "explore": "taxel.api", "lumped": "taxel.api", "mesh": "taxel.api",
    "reduce": "taxel.api", "skin": "taxel.api",
    "Scene": "taxel.scene", "SceneError": "taxel.scene",
    "StaticResult": "taxel.analyses", "FrequencyResult": "taxel.analyses",
    "TransientResult": "taxel.analyses", "LumpedResult": "taxel.analyses",
    "StudyError": "taxel.studies.spec", "OptimizeError": "taxel.optimize.spec",
}

__all__ = sorted(_PUBLIC) + ["measure"]


def _guarded(name: str) -> property:
    """A public name that a subpackage of the same name cannot replace: the import
    system sets `taxel.optimize` to the subpackage when it loads it; that
    assignment is ignored."""
    def get(module):
        return getattr(importlib.import_module(_PUBLIC[name]), name)

    def set_(module, value):
        if not isinstance(value, types.ModuleType):
            raise AttributeError(f"taxel.{name} is part of the public API; it cannot be replaced")
    return property(get, set_)


class _Package(types.ModuleType):
    """The `taxel` module: public names resolve lazily; the one that a subpackage
    shares (`optimize`) is a guarded property."""

    optimize = _guarded("optimize")
    skin = _guarded("skin")

    def __getattr__(self, name):
        if name in _PUBLIC:
            value = getattr(importlib.import_module(_PUBLIC[name]), name)
            super().__setattr__(name, value)
            return value
        if name == "measure":
            return importlib.import_module("taxel.measure")
        raise AttributeError(f"module 'taxel' has no attribute {name!r}")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(__all__))


sys.modules[__name__].__class__ = _Package
