"""The 3-DoF lumped model informed by the FEM of the scene (fem.readout.identified),
beside the seed's (fem.readout.taxel_model, thesis section 3.1, errata corrected).

The FEM targets, for the pressed (or only) taxel of an array scene:
* static compliance c = F^T x / 1 N of the scene's load (open circuit, lossless K0);
* static short-circuit charge per newton Q_sc = -C V_oc at the pressed electrode
  (every electrode grounded), and the static capacitance C_ii;
* the first resonance: the first peak of |Q_sc(f)| of the pressed taxel's own path in the
  scene's reduced model (taxel.analyses.solves.reduced, charge outputs, cached) up to its
  highest frequency (2 kHz by default).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from taxel.fem import dynamics
from taxel.fem import linalg
from taxel.fem import readout
from taxel.scene import Scene, SceneError
from taxel.schema import electrode_name
from taxel.analyses.model.problem import problem
from taxel.analyses.solves.dynamic import lumped_model
from taxel.analyses.solves.reduced import cached


@dataclass
class FemTargets:
    compliance: float            # m/N
    charge_per_newton: float     # C/N (signed: the FEM's sign convention)
    capacitance: float           # F
    first_resonance: float       # Hz
    peak: float                  # C/N: |Q_sc / F| at the first resonance


def targets(scene: Scene) -> FemTargets:
    """The FEM quantities the informed model is fitted to (module docstring)."""
    if scene.array is None:
        raise SceneError("the lumped model describes a taxel array scene ([array])")
    dm = dynamics.model(problem(scene.replace(**{"model.symmetry": "full"})))
    solve = linalg.scaled_solver(dm.K0.tocsc(), dm.red.is_u, linalg.resolve("auto", dm.K0.shape[0],
                                                                            dim=dm.sy.tm.mesh.dim()))
    X = solve(np.column_stack([dm.F, dm.Be]))[0]
    nf = dm.red.nf
    C = np.linalg.inv(X[nf:, 1:])
    Q = -C @ X[nf:, 0]
    name = electrode_name(*scene.load.taxel)
    i = dm.names.index(name) if name in dm.names else 0
    model = cached(scene, None, "charge")
    f_top = 2e3                      # the reduced model holds to 2 kHz at least (reduced.reduce)
    f = np.geomspace(10.0, f_top, 800)
    j = next((k for k, n in enumerate(model.input_names) if n.endswith(":" + name)), 0)
    h = np.abs(model.frf(f)[:, i, j])
    peaks = np.flatnonzero((h[1:-1] > h[:-2]) & (h[1:-1] >= h[2:])) + 1
    if not len(peaks):
        raise SceneError(f"no resonance of the charge response below {f_top:g} Hz; the lumped fit needs one")
    return FemTargets(float(dm.F @ X[:, 0]), float(Q[i]), float(C[i, i]), float(f[peaks[0]]), float(h[peaks[0]]))


def informed(scene: Scene, fem: FemTargets | None = None) -> readout.Identified:
    """The FEM-informed 3-DoF model of the scene's taxel (fem.readout.identified)."""
    fem = fem or targets(scene)
    seed = lumped_model(scene)
    d = scene.dynamics
    eta_p = seed.b[1] * 2 * np.pi * d.reference_frequency / seed.k[1] if d.piezo_loss is None else d.piezo_loss
    loss = np.array([d.silicone_loss, eta_p, d.silicone_loss])
    return readout.identified(seed, fem.compliance, fem.charge_per_newton, fem.first_resonance, fem.capacitance, loss,
                              fem.peak)
