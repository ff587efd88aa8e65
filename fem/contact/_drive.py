"""A press driven to its indenter's target (fem.contact.Press: travel or force, through
intermediate targets), returning the final Solution: the entry point of fem.contact."""

from __future__ import annotations

from taxel.fem.assembly import Indenter, System
from taxel.fem.static import Solution

from ._press import Press
from ._records import Options, PressError


def press(sy: System, ind: Indenter, method="auto", opts: Options | None = None,
          path: list[float] | None = None) -> Solution:
    """Press to the indenter's travel or force (through the intermediate targets of
    `path`, N or m alike), and return the final Solution with `.contact`. Where the press
    stops, its PressError carries the Solution of the last converged state."""
    pr = Press(sy, ind, method, opts)
    try:
        if ind.travel is not None:
            for d in list(path or []) + [ind.travel]:
                pr.travel(d)
            pr.res.message = f"travel {1e3 * ind.travel:.4g} mm: {pr.res.points[-1].force:.4g} N"
        else:
            for F in list(path or []) + [ind.force]:
                pr.force(F)
    except PressError as exc:
        if pr.res.points:               # the last converged state (a failed trial restores it)
            exc.solution = pr.solution()
        raise
    return pr.solution()
