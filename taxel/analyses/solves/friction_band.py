"""The friction band of a press: the pressed taxel's sensitivity and crosstalk at the
two limits of the probe's friction, frictionless and sticking, and at the scene's own
Coulomb coefficient between them (`load.friction = 0.4`, fem.contact's return mapping).

No sourced coefficient exists for a probe on Ecoflex (the rig's probe is described by
the `thesis-pzt-probe-*` examples' `[load]` table, which says "sticking"), so the band
is what a user who does not know the coefficient can bound the answer by: the two
limits always, the scene's coefficient where it gives one. Each law is the same scene
solved again with only `load.friction` changed (three static solves: the band costs
about three presses, and a leg that stops short says so, `FrictionLeg.success`).
"""

from __future__ import annotations

from dataclasses import dataclass

from taxel.scene import Scene


@dataclass(frozen=True)
class FrictionLeg:
    """One friction law's answer (SI): the pressed taxel's open-circuit V/N and the crosstalk."""

    friction: str | float          # "frictionless", "sticking" or the Coulomb coefficient
    sensitivity: float             # V/N, signed, per newton of the force reached
    crosstalk: float | None        # largest |V| of a neighbour / |V| of the pressed taxel (None without one)
    force: float                   # N, the force the press reached
    travel: float                  # m, the indenter's travel there
    success: bool                  # False: the press stopped short of the scene's load (its last state)
    stop: str = ""                 # why it stopped short ("" when it did not)

    def record(self) -> dict:
        return {"friction": self.friction, "sensitivity_V_per_N": self.sensitivity, "crosstalk": self.crosstalk,
                "force_N": self.force, "travel_m": self.travel, "success": self.success, "stop": self.stop}


@dataclass(frozen=True)
class FrictionBand:
    """The press's answer at frictionless, at the scene's Coulomb coefficient (if it gives
    one) and sticking: how much the unknown friction of the probe on the silicone matters."""

    frictionless: FrictionLeg
    coulomb: FrictionLeg | None    # at the scene's coefficient; None when the scene names a limit
    sticking: FrictionLeg

    @property
    def legs(self) -> list[FrictionLeg]:
        return [leg for leg in (self.frictionless, self.coulomb, self.sticking) if leg is not None]

    @property
    def sensitivity_spread(self) -> float:
        """(largest - smallest |V/N|) over the band / |V/N| sticking: how far the unknown
        friction moves the sensitivity, relative to the sticking answer."""
        s = [abs(leg.sensitivity) for leg in self.legs]
        return (max(s) - min(s)) / abs(self.sticking.sensitivity)

    def record(self) -> dict:
        return {"frictionless": self.frictionless.record(),
                "coulomb": None if self.coulomb is None else self.coulomb.record(),
                "sticking": self.sticking.record(), "sensitivity_spread": self.sensitivity_spread}

    def lines(self) -> list[str]:
        """The band as summary lines (taxel solve --friction-band)."""
        out = ["friction band (the pressed taxel at each law):",
               f"  {'friction':>12}  {'V/N':>10}  {'crosstalk':>9}  {'force':>8}"]
        for leg in self.legs:
            name = leg.friction if isinstance(leg.friction, str) else f"mu = {leg.friction:g}"
            xt = "-" if leg.crosstalk is None else f"{100 * leg.crosstalk:.2f} %"
            out.append(f"  {name:>12}  {leg.sensitivity:>10.4g}  {xt:>9}  {leg.force:>6.4g} N"
                       + ("" if leg.success else f"  (stopped short: {leg.stop})"))
        out.append(f"  the sensitivity spreads by {100 * self.sensitivity_spread:.1f} % of the sticking value")
        return out


def friction_leg(scene: Scene, friction, result=None, **options) -> FrictionLeg:
    """The press scene solved with `load.friction = friction` (or `result`, its solve
    already made) as one leg of a band; `options` as taxel.analyses.solve's."""
    from taxel.analyses.solves.analysis import solve
    res = result if result is not None else solve(scene.replace(**{"load.friction": friction}), **options)
    out = res.outputs()
    if "sensitivity" not in out:
        raise ValueError("a friction band needs a taxel electrode to press (array or plate electrodes)")
    pt = res.contact.points[-1] if res.contact is not None and res.contact.points else None
    return FrictionLeg(friction, out["sensitivity"], out.get("crosstalk"), abs(res.applied_force),
                       0.0 if pt is None else pt.travel, res.success, "" if res.stop is None else res.stop.message)


def friction_band(scene: Scene, result=None, **options) -> FrictionBand:
    """Solve a press scene (`load.contact = true`) at frictionless, its own Coulomb
    coefficient (if `load.friction` is a number) and sticking; `result`: the scene's own
    solve, reused for its own law; `options` as taxel.analyses.solve's."""
    ld = scene.load
    if ld.kind != "probe" or not ld.contact:
        raise ValueError("a friction band needs a press: load.kind = 'probe' and load.contact = true")
    own = "sticking" if ld.friction is None else ld.friction

    def leg(friction) -> FrictionLeg:
        return friction_leg(scene, friction, result if friction == own else None, **options)
    mu = own if isinstance(own, float) else None
    return FrictionBand(leg("frictionless"), None if mu is None else leg(mu), leg("sticking"))
