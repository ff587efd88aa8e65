"""Load control of a press (fem.contact.Press): displacement control (travel steps, halved
on failure, grown by 1.5 after an easy step) and force control (Newton on F(d) with the
path's own stiffness dF/dd, at most twice the last step, regula falsi with the Illinois
rule once bracketed, a failed trial bisected towards the last converged travel, a trial past the
target a bracket end only). Every
converged state is a point of the press's curve (Press.res.points). A press that stops
keeps the cause its last failed trial measured (PressError.cause); a penalty stop is
raised at once (no shorter step mends it)."""

from __future__ import annotations

import numpy as np

from ._records import PressError


def travel(pr, d_target, first=0.25, min_frac=1e-3):
    """Displacement control to travel d_target."""
    step = first * (d_target - pr.d)
    while abs(pr.d - d_target) > 1e-15 * max(abs(d_target), 1e-300):
        d = pr.d + step if abs(step) < abs(d_target - pr.d) else d_target
        try:
            pt = pr.attempt(d)
        except PressError as exc:
            if exc.cause == "penalty" or abs(step) / 2 < min_frac * abs(d_target):
                raise
            step /= 2
            continue
        if pt.iterations <= 6:
            step *= 1.5
    return pr.res.points[-1]

def force(pr, F_target, max_trials=40):
    """Force control: the travel whose force is F_target (secant / regula falsi on F(d)),
    from the last converged state. A load step ends at its target: a trial that crosses it
    by more than the tolerance is a bracket end, not a state (the press returns to the state
    before it), so the path is monotone up to each target (a Coulomb or sticking press's
    state depends on its path; a semi-smooth step that jumped to 3.49 N on a 3 N target
    stopped there, unable to come back)."""
    o = pr.o
    pts = pr.res.points
    if pts:                                  # the current state is the first "trial"
        d, F = pr.d, pts[-1].force
        d_prev, F_prev = (pts[-2].travel, pts[-2].force) if len(pts) > 1 else (0.0, 0.0)
    else:
        d, F, d_prev, F_prev = 0.0, 0.0, 0.0, 0.0
    below = [(p.travel, p.force) for p in pts if p.force < F_target]
    lo, hi, last_side = max(below, default=(0.0, 0.0)), None, None
    dt, Ft = d, F                    # the last trial's travel and force
    failed = None                    # the last failed trial (PressError), named when the target is not reached
    for _ in range(max_trials):
        if pts and abs(F - F_target) <= o.force_tol * F_target:
            pr.res.message = (f"{F:.4g} N at travel {1e3 * d:.4g} mm; {len(pts)} states, "
                                f"{pr.res.total_iterations} Newton iterations")
            return pts[-1]
        side = Ft < F_target
        if Ft < F_target:
            lo = (dt, Ft)
        else:
            hi = (dt, Ft)
        if hi is not None and side == last_side:   # Illinois: the kept end's excess is halved
            if side:
                hi = (hi[0], F_target + (hi[1] - F_target) / 2)
            else:
                lo = (lo[0], F_target - (F_target - lo[1]) / 2)
        last_side = side
        if d == 0.0 and hi is None and o.predictor and o.first_force is not None:
            # the unpressed state's own stiffness: the travel of first_force x the target
            slope = pr.slope if pr.slope is not None else pr.start_rates()
            d_new = o.first_force * F_target / slope
        elif d == 0.0 and hi is None:
            d_new = o.first_travel * pr.height
        elif o.predictor and pr.slope is not None and pr.slope > 0:
            # Newton on F(d) with the path's own stiffness; at most twice the last step,
            # and inside the bracket once there is one
            step = (F_target - F) / pr.slope
            d_new = d + float(np.clip(step, -2 * abs(d - d_prev) - 1e-9, 2 * max(abs(d - d_prev), 0.25 * d)))
            if hi is not None and not min(lo[0], hi[0]) < d_new < max(lo[0], hi[0]):
                d_new = _falsi(lo, hi, F_target)
        elif hi is None:                     # secant from the last two states, at most 1.5x the step
            slope = (F - F_prev) / (d - d_prev) if d != d_prev else F / d
            step = (F_target - F) / max(slope, 1e-300)
            d_new = d + min(step, 1.5 * max(d - d_prev, 0.25 * d))
        else:                                # regula falsi inside the bracket
            d_new = _falsi(lo, hi, F_target)
        saved = pr.snapshot()
        while True:
            try:
                pt = pr.attempt(d_new)
                break
            except PressError as exc:
                if exc.cause == "penalty":
                    raise
                if abs(d_new - pr.d) < 1e-4 * pr.height:      # every shorter trial failed: named as a force stop
                    raise PressError(exc.cause, f"force control: {F_target:.4g} N not reached, every trial from "
                                     f"the last state at {F:.4g} N failed down to the shortest step", pr.res,
                                     f"the last failed trial: {exc}") from exc
                failed = exc
                d_new = (pr.d + d_new) / 2
        dt, Ft = pt.travel, pt.force
        if (Ft - F_target) * (F - F_target) < 0 and abs(Ft - F_target) > o.force_tol * F_target:
            pr.restore(saved)                # past the target: a bracket end; the step goes on from the state before
            pr.stats["crossings"] = pr.stats.get("crossings", 0) + 1
            continue
        d_prev, F_prev = d, F
        d, F = dt, Ft
    summary = f"force control: {F_target:.4g} N not reached in {max_trials} trials, the last at {F:.4g} N"
    if failed is None:
        raise PressError("trials", summary, pr.res)
    raise PressError(failed.cause, summary, pr.res, f"the last failed trial: {failed}")


def _falsi(lo, hi, F_target):
    """Regula falsi inside the bracket (bisection if its ends carry the same force)."""
    if hi[1] == lo[1]:
        return (lo[0] + hi[0]) / 2
    return lo[0] + (F_target - lo[1]) * (hi[0] - lo[0]) / (hi[1] - lo[1])

