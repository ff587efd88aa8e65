"""taxel: the open design tool for piezoelectric tactile sensors.

The Python API (taxel.api): `load`, `solve`, `run_study`, `optimize`, `report`, `work_precision`.
They are imported on first use, so `import taxel.units` stays light.
"""

from __future__ import annotations

__all__ = ["load", "solve", "run_study", "optimize", "report", "work_precision"]


def __getattr__(name):
    if name in __all__:
        from taxel import api
        return getattr(api, name)
    raise AttributeError(f"module 'taxel' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + __all__)
