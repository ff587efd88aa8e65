"""The records of a press (fem.contact): its options, every converged state of the
load path, the result, and the error that names why a press stopped."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from ._geometry import ContactState
from taxel.fem.assembly import Indenter


# why a press stopped, as measured (fem.contact, fem.contact, fem.contact; docs/glossary.md)
StopCause = Literal[
    "non-finite",     # Newton or continuation reached a non-finite state
    "penalty",        # the contact penalty: too high (ill-conditioned solve) or too low (penetration)
    "inversion",      # every line-search step inverts silicone elements
    "stagnation",     # Newton stagnates on one active set (a kink, or an unstable state)
    "cycling",        # the contact active set cycles between two sets
    "iterations",     # Newton's iteration limit
    "multipliers",    # the augmented Lagrangian's multipliers do not settle
    "trials",         # force control: the target not reached in its trials, none of them failing
]


class PressError(RuntimeError):
    """A press stopped: `cause` the kind of stop it measured (StopCause), `summary` what
    stopped and at which travel, `detail` what it measured there ("" if nothing); the
    message is "summary (detail)". `.result` has the path so far (fem.contact.PressResult),
    `.solution` the Solution at its last converged state (fem.contact.press; None before one)."""

    def __init__(self, cause: StopCause, summary: str, result=None, detail: str = ""):
        super().__init__(f"{summary} ({detail})" if detail else summary)
        self.cause, self.summary, self.detail, self.result = cause, summary, detail, result
        self.solution = None


@dataclass
class PressPoint:
    travel: float                 # m
    force: float                  # N, on the indenter
    voltages: dict                # V, open electrodes
    area: float                   # m^2, reference area of the material points in contact
    half_width: float             # m, current contact radius (2D: half-width) about the indenter centre
    penetration: float            # m, largest
    iterations: int               # Newton iterations (all Uzawa passes)
    uzawa: int                    # multiplier updates
    max_pressure: float = 0.0     # Pa, largest contact pressure (nominal)


@dataclass(frozen=True)
class SlipZone:
    """The slip zone of a press's final state, per contact point: its current position, its
    state (fem.contact's OPEN 0, STICK 1, SLIP 2) and, with Coulomb friction, the slip
    distance summed over the load steps (m; None for frictionless and sticking)."""

    x: np.ndarray                 # (dim, n) m, current positions of the contact points
    state: np.ndarray             # (n,) OPEN, STICK or SLIP
    slip: np.ndarray | None       # (n,) m

    def half_width(self, which: int, centre=(0.0, 0.0)) -> float:
        """m, the largest lateral distance from `centre` of a point in state `which` (0 if none)."""
        nl = self.x.shape[0] - 1
        r = np.sqrt(((self.x[:nl] - np.asarray(centre[:nl], float)[:, None]) ** 2).sum(axis=0))
        return float(r[self.state == which].max(initial=0.0))

    def record(self, centre=(0.0, 0.0)) -> dict:
        """The zone's summary in SI units (the result's JSON record)."""
        return {"open_points": int((self.state == 0).sum()), "stick_points": int((self.state == 1).sum()),
                "slip_points": int((self.state == 2).sum()), "stick_half_width_m": self.half_width(1, centre),
                "slip_half_width_m": self.half_width(2, centre),
                "largest_slip_m": None if self.slip is None else float(self.slip.max(initial=0.0))}


@dataclass
class PressResult:
    indenter: Indenter
    penalty: float                          # Pa/m
    method: str
    points: list[PressPoint] = field(default_factory=list)   # every converged state, in order
    state: ContactState | None = field(default=None, repr=False)   # the final contact state
    failed_trials: int = 0
    message: str = ""
    stats: dict = field(default_factory=dict, repr=False)   # the solver's work (Press.stats: factorizations, CPU s)

    @property
    def curve(self) -> np.ndarray:
        """(travel, force) of the converged states, sorted by travel."""
        a = np.array([(p.travel, p.force) for p in self.points])
        return a[np.argsort(a[:, 0])] if len(a) else a

    @property
    def slip_zone(self) -> SlipZone | None:
        """The final state's slip zone (None before a converged state)."""
        st = self.state
        if st is None:
            return None
        dim = st.x.shape[0]
        return SlipZone(st.x.reshape(dim, -1), st.zone.ravel(), None if st.slip is None else st.slip.ravel())

    @property
    def total_iterations(self) -> int:
        return sum(p.iterations for p in self.points)


@dataclass
class Options:
    penalty: float | None = None    # Pa/m; default penalty_factor x mu / h
    penalty_factor: float = 100.0
    method: str = "augmented"       # augmented | penalty
    gap_tol: float = 1e-3           # largest penetration / travel
    tol: float = 1e-6               # Newton, scaled relative residual (or round-off: fem.contact)
    uzawa_tol: float | None = 1e-3  # Newton's tolerance while the multipliers still move (None: tol)
    max_iter: int = 25
    max_uzawa: int = 40
    force_tol: float = 1e-3         # force control: |F - target| / target
    first_travel: float = 0.02      # force control: first trial, as a fraction of the layer height
    first_force: float | None = None  # force control with the predictor: first trial at the travel the
    #                                   unpressed stiffness gives for this fraction of the target (None: first_travel)
    active_set_update: bool = True  # False: the tangent keeps the active set of the step's start
    fix_cycling: bool = True        # when an active set comes back, finish Newton on it (False: keep updating)
    intorder: int = 3               # contact quadrature on the top facets (3: 2 points per 2D facet)
    rule: str = "auto"              # contact points: gauss (intorder) | nodal (P2 nodes, lumped) | midpoints (3D:
    #                                 the edge midpoints only, the vertices free: for comparison) | auto (3D nodal)
    line_search: bool = True        # backtrack on the scaled residual (else only to keep J > 0)
    predictor: bool = True          # start each travel from the tangent prediction x + (d - d0) dx/dd
    chord: bool = True              # try the last factorization first (a chord step) while the active set holds
    reuse_analysis: bool = True     # PARDISO: one symbolic analysis for every tangent of the press (fem.linalg.Refactorizer)
    assembly: str = "vectorised"    # vectorised (fem.hyperelastic, fem.assembly) | skfem (the reference path)
    solver: str = "uzawa"           # frictionless and Coulomb: semismooth (Newton on the Alart-Curnier equations,
    #                                 the multipliers unknowns; fem.contact._alart_curnier) | uzawa (penalty Newton
    #                                 inside the Uzawa loop; sticking contact always) | auto (uzawa, and a step it
    #                                 stops in again by semismooth). Default uzawa: under auto the Q1/P0 hexahedral
    #                                 press that reaches 1 N on uzawa stops by a semi-smooth stagnation at 0.90 N, and
    #                                 the 3D probe's frictionless press was not measured to 1 N (docs/benchmarks.md)
    semismooth_factor: float = 3.0  # the Alart-Curnier parameter eps, x mu / h (its solution does not depend on it;
    #                                 the iteration does: 3 took the 2D probe to 1 N under every law, 10 stagnated at mu 0.3)
    continuation: bool = True       # past a stagnating Newton (an unstable state): pseudo-transient continuation
    #                                 (fem.contact.continuation) to a stable equilibrium at the same travel
