"""The taxel models behind the simulated bench and the silicone fit.

The lumped taxel (fem.readout) of a scene with its silicone's moduli scaled and its
loss factor set (`scaled_model`), the top of its stack per newton (`compliance`:
what the actuator's travel sees), the loss factor a lumped model carries
(`loss_factor`: b = eta k / (2 pi f_ref)), and the FEM transient's short-circuit
charges of a scene's electrodes under a force history (`fem_charges`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from taxel.analyses.model.problem import damping, problem, scene_materials
from taxel.fem import dynamics
from taxel.fem import readout
from taxel.scene import Scene

__all__ = ["scaled_model", "compliance", "loss_factor", "reference_frequency", "fem_charges"]


def scaled_model(scene, modulus_scale: float = 1.0, loss: float | None = None):
    """The scene's lumped taxel with the silicone's moduli scaled and its loss factor set."""
    a, mats = scene.array, scene_materials(scene)
    sil = mats[a.silicone]
    sil = dataclasses.replace(sil, mu=sil.mu * modulus_scale, K=sil.K * modulus_scale,
                              yeoh=None if sil.yeoh is None else tuple(c * modulus_scale for c in sil.yeoh))
    d = damping(scene)
    if loss is not None:
        d = dataclasses.replace(d, silicone_loss=loss)
    return readout.taxel_model(mats[a.piezo], sil, a.taxel_width, a.silicone_above, a.piezo_thickness,
                              a.silicone_below, float(scene.load.force or 1.0), d)


def compliance(lm, freqs) -> np.ndarray:
    """X1(f) / F (m/N): the top of the stack per newton, from the lumped state space."""
    A, B, _, _ = lm.state_space()
    s = 2j * np.pi * np.asarray(freqs, float)
    M = s[:, None, None] * np.eye(len(A))[None] - A[None]
    x = np.linalg.solve(M, np.broadcast_to(B.astype(complex), (len(s),) + B.shape))
    return x[:, 0, 0]


def loss_factor(lm, scene) -> float:
    """The silicone's loss factor of a lumped model: b = eta k / (2 pi f_ref)."""
    return float(lm.b[0] * 2 * np.pi * reference_frequency(scene) / lm.k[0])


def reference_frequency(scene) -> float:
    """The scene's [dynamics] reference frequency (Hz), where the loss factor is defined."""
    return float(damping(scene).reference_frequency)


def fem_charges(scene: Scene, t: np.ndarray, force: np.ndarray) -> tuple[np.ndarray, list[str]]:
    """Short-circuit charges (nt, na) of the scene's electrodes under `force` (N) on its load, by FEM transient."""
    dm = dynamics.model(problem(scene), short=True)
    tr = dynamics.transient(dm, t, force)
    return tr.Q, list(tr.names)
