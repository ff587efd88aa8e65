"""Coverage of a design: where on its surface a press at the smallest force of interest
gives at least one taxel a signal above the noise floor (the seed, section 2: "by
increasing this distance [the gap], non-sensitive regions appear ... taxels do not
produce any signals and sensor will not detect the position and amount of the force").

Model. The press is the influence functions' press (taxel.analyses.surface.influence: a
uniform pressure patch as wide as a taxel, the size of the thesis rig's 4 mm flat
punch, on the 2D section through the middle row, linear silicone). Taxel (r, c)'s
open-circuit peak for a press of force F at (x, y) is, as in
taxel.analyses.surface.localization,

    V_rc(x, y) = S_c F G_r(y) G_c(x),

S_c the taxel's own open-circuit sensitivity pressed at its centre (V/N), G the
influence functions (1 at the taxel's centre; the array's two directions alike and
separable). A press is detected when the best taxel's peak exceeds k times the
noise's rms sigma (V, referred to the taxel's open-circuit voltage: a readout's gain
scales signal and the noise it refers to its input alike):

    max_rc |V_rc(x, y)| >= k sigma,   k = SIGMAS = 3

(a 3-sigma threshold: a Gaussian noise crosses it on 0.13 % of samples of one sign).
Separability makes the best taxel's peak a product, g(y) b(x) with
b(x) = max_c |S_c G_c(x)| and g(y) = max_r |G_r(y)|, so the 2D surface follows from
one line scan.

coverage = the fraction of the surface between the outer taxels' centres (the square
[0, L]^2, L = (cols - 1) pitch: every press there has a taxel on either side of it in
each direction; a press beyond it is over an outer taxel or off the sensing area)
where the press is detected, on a grid of GRID x GRID points (the spline of the
influence functions between their samples). A dead zone is where it is not: the line
scan's dead intervals `dead_m` are the x where F g(y*) b(x) falls below the threshold
on the surface's worst line y* (the one midway between rows; the line through taxel
centres, y = 0, is the best, `line_fraction`).

Limits (the same as the localization map's): the 2D section is a plane through the
row, infinitely deep, and the array's directions are taken as separable. It is not a
fixed factor off 3D: benchmarks/coverage_metric.py presses the thesis PZT design in 3D,
and at the gap's middle the best peak is 1.68 times the 3-sigma threshold (0.2 N, 1 mV)
against 15.7 in 2D (the patch half on each taxel: what it presses onto a taxel and what
the silicone beside it pulls cancel more in 3D), at the corner between four taxels 7.11
against 4.58. Coverage from the 2D scan is a screen: it finds the dead zones of wide
gaps; a design it passes with less than about a tenfold margin needs 3D presses. No gain
spread, no bias of an estimator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from taxel.analyses.surface.influence import Influence

SIGMAS = 3.0          # k: a press is detected when the best taxel's peak is above k sigma
GRID = 201            # points per direction of the surface grid (and of the line scan)


@dataclass
class Coverage:
    """A design's coverage at one force against one noise floor (module docstring)."""
    fraction: float                  # of the surface [0, L]^2 where a press is detected
    line_fraction: float             # of the line scan along the pressed row (y = 0)
    force_N: float                   # the smallest force of interest
    noise_V: float                   # sigma, referred to a taxel's open-circuit peak
    sigmas: float                    # k
    x_m: np.ndarray                  # (GRID,) the line scan's positions from the first taxel's centre
    best_V: np.ndarray               # (GRID,) the best taxel's peak along the pressed row, at force_N
    dead_m: list[tuple[float, float]]   # the surface's dead intervals along x on its worst line

    @property
    def threshold_V(self) -> float:
        return self.sigmas * self.noise_V

    def record(self) -> dict:
        return {"coverage": self.fraction, "line_coverage": self.line_fraction, "force_N": self.force_N,
                "noise_V": self.noise_V, "sigmas": self.sigmas, "x_m": self.x_m.tolist(),
                "best_V": self.best_V.tolist(), "dead_m": [list(d) for d in self.dead_m]}


def best_peak(infl: Influence, x) -> np.ndarray:
    """b(x) = max_c |S_c G_c(x)| (V/N): the best taxel's open-circuit peak per newton for a press at x."""
    S = np.abs(np.asarray(infl.sensitivity, float))
    return np.max(np.abs(infl.at(np.asarray(x, float))) * S[None, :], axis=1)


def _intervals(x: np.ndarray, bad: np.ndarray) -> list[tuple[float, float]]:
    """The runs of `bad` along x, as (first x, last x) pairs."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], bad.astype(int), [0]])))
    return [(float(x[i]), float(x[j - 1])) for i, j in zip(edges[::2], edges[1::2])]


def coverage(infl: Influence, force: float, noise_V: float, sigmas: float = SIGMAS) -> Coverage:
    """The coverage of the influence functions `infl` (their sensitivities set) for a press of
    `force` N against white noise of rms `noise_V` on every taxel's open-circuit peak."""
    if infl.sensitivity is None:
        raise ValueError("coverage needs the influence functions' sensitivities (taxel.analyses.surface.influence)")
    if not (force > 0 and noise_V > 0 and sigmas > 0):
        raise ValueError(f"coverage needs a positive force, noise and k (got {force}, {noise_V}, {sigmas})")
    L = infl.x[-1] - infl.x[0]
    x = infl.x[0] + np.linspace(0.0, L, GRID)
    b = best_peak(infl, x)                                   # V/N along a line through taxel centres
    g = np.max(np.abs(infl.at(x)), axis=1)                   # max_r |G_r(y)|: 1 at a taxel centre
    surface = force * np.outer(g, b) >= sigmas * noise_V     # (y, x): max_rc |S_c G_r(y) G_c(x)|, separable
    worst = int(np.argmin(g))                                # the line midway between rows
    dead = _intervals(x - infl.x[0], ~surface[worst])
    line = force * b >= sigmas * noise_V
    return Coverage(float(surface.mean()), float(line.mean()), float(force), float(noise_V), float(sigmas),
                    x - infl.x[0], force * b, dead)


def design_coverage(scene, force: float, noise_V: float, sigmas: float = SIGMAS, solve=None,
                    per_pitch: int = 8) -> Coverage:
    """The coverage of a design (a taxel-array scene): its influence functions (the same
    samples as taxel.analyses.surface.localization.localization_error, so the two metrics share
    their solves: 9 static 2D solves for a 3-taxel row at per_pitch 8), then `coverage`."""
    from taxel.analyses.surface.influence import influence
    arr = scene.array
    if arr is None or arr.cols < 2:
        raise ValueError("coverage needs a taxel array with at least two columns")
    return coverage(influence(scene, per_pitch=per_pitch, edges=False, solve=solve), force, noise_V, sigmas)
