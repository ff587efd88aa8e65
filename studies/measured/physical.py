r"""The FEM's physical scales against a rig's chirp FRF: which are identifiable.

The rig's FRF of a pressed taxel (charge amplifier, notch) on the FEM of the scene
depends on the physical scales

    piezo      the piezoelectric coefficient scale (the coupling matrix e scaled at
               fixed c^E and eps^S: d scaled by the same factor);
    gain       the taxel's own gain spread (the rig draws it; multiplies Q_sc);
    modulus    the silicone's moduli scale (shear part times it, the volumetric
               compliance part over it: no new mesh);
    loss       the silicone's loss factor (the causal law of fem.constitution refitted);
    R_f, C_f   the charge amplifier's feedback resistor and capacitor scales,

through H(f) = readout(gain * Q_sc(f; piezo, modulus, loss); R_f, C_f). `model`
evaluates it from one dynamic model (its matrices scaled; fem.dynamics on the pressed
taxel, cached per FEM parameter set), and `identifiability` (studies.measured.silicone:
the Fisher information of log H at a relative error sigma per frequency) gives each
scale's Cramer-Rao standard deviation and their correlations: a scale whose column
of the Jacobian is (nearly) a combination of others is not identifiable from this
record, whatever the fit reports.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from taxel.analyses.adapter import problem
from taxel.fem import constitution, dynamics
from taxel.fem import readout as circuits
from taxel.schema import electrode_name
from taxel.studies.measured.silicone import Identifiability, identifiability

NAMES = ("piezo", "gain", "modulus", "loss", "R_f", "C_f")


class Physical:
    """H(f; scales) of the scene's pressed taxel through `readout` (a charge amplifier)."""

    def __init__(self, scene, readout):
        self.dm = dynamics.model(problem(scene))
        self.readout = readout
        self.index = self.dm.names.index(electrode_name(*scene.load.taxel))
        self._parts = dict(self.dm.parts)
        self._losses = dict(self.dm.relax.losses)
        self._memo = {}

    def q_sc(self, freqs, piezo=1.0, modulus=1.0, loss=None):
        key = (freqs.tobytes(), piezo, modulus, loss)
        if key not in self._memo:
            parts = {}
            for k, P in self._parts.items():
                what = k.split(":")[0]
                sil = k.endswith(":silicone")
                parts[k] = P * (piezo if what == "coupling" else modulus if (sil and what == "shear")
                                else 1 / modulus if (sil and what == "volumetric") else 1.0)
            losses = {k: ((loss, c) if (k.endswith(":silicone") and loss is not None) else (e, c))
                      for k, (e, c) in self._losses.items()}
            dm = replace(self.dm, parts=parts, relax=constitution.relaxation_law(losses, self.dm.relax.band))
            self._memo[key] = dynamics.sweep(dm, freqs, tol=1e-7)
        return self._memo[key]

    def __call__(self, freqs, piezo=1.0, gain=1.0, modulus=1.0, loss=None, R_f=1.0, C_f=1.0):
        port = self.q_sc(np.asarray(freqs, float), piezo, modulus, loss)
        r = replace(self.readout, R_f=self.readout.R_f * R_f, C_f=self.readout.C_f * C_f)
        return gain * circuits.readout(port, r)[:, self.index]


def physical_identifiability(scene, readout, freqs, sigma: float, theta: dict | None = None) -> Identifiability:
    """Cramer-Rao standard deviations (relative) and correlations of NAMES at `theta`
    (default: every scale 1, the scene's silicone loss) over `freqs` at relative error sigma."""
    model = Physical(scene, readout)
    eta = next(e for k, (e, _) in model.dm.relax.losses.items() if k.startswith("shear:"))
    th = {"piezo": 1.0, "gain": 1.0, "modulus": 1.0, "loss": eta, "R_f": 1.0, "C_f": 1.0, **(theta or {})}
    return identifiability(model, th, np.asarray(freqs, float), sigma)
