"""The FEM's causal loss law (fem.constitution) against the constant (hysteretic) loss
factor it replaced: the fitted law, and how far the thesis taxel's responses move.

1. The law: relaxation frequencies, weights, the loss factor's largest deviation from
   eta over 1 Hz-2 kHz, and the real part's rise through the band (Kramers-Kronig).
2. thesis-pzt-single-2d and thesis-pzt-3x3-2d (the pressed taxel), direct FEM sweeps:
   |V_oc| per newton, |Q_sc| per newton and |C| at 1, 10, 100 Hz and 1 kHz, and the
   first resonance of the open-circuit voltage (peak of |V_oc| on a fine grid), with the
   causal law and with the constant loss factors (kappa = 1 + i eta, 1 / (1 + i eta),
   1 - i tan(delta): the model before the change; the same mesh and matrices).

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/causal_damping.py
"""

from __future__ import annotations

import numpy as np

import taxel
from taxel.analyses.adapter import problem
from taxel.fem import dynamics
from taxel.fem import constitution

POINTS = [1.0, 10.0, 100.0, 1000.0]


def hysteretic(dm):
    """The constant loss factors of the same kinds (the law before fem.constitution)."""
    k = {}
    for kind, (eta, compliance) in dm.relax.losses.items():
        k[kind] = (1 / (1 + 1j * eta) if kind.startswith("volumetric") else 1 - 1j * eta) if compliance \
            else 1 + 1j * eta
    return lambda w: {n: k.get(n, 1.0) for n in dm.parts}


def responses(dm, kappa=None):
    if kappa is not None:
        dm.kappa = kappa
    fine = np.geomspace(200.0, 5000.0, 120)
    pr = dynamics.sweep(dm, POINTS, method="direct")
    peak = dynamics.sweep(dm, fine, method="reduced", tol=1e-6)
    f1 = fine[int(np.argmax(np.abs(peak.V_oc[:, 0])))]
    if kappa is not None:
        del dm.kappa
    return np.abs(pr.V_oc[:, 0]), np.abs(pr.Q_sc[:, 0]), np.abs(pr.C[:, 0, 0]), f1


def main():
    law = constitution.relaxation_law({"shear": (0.1, False), "volumetric": (0.1, True)})
    print("the law (silicone, eta = 0.1): relaxation frequencies "
          + ", ".join(f"{1 / (2 * np.pi * t):.3g}" for t in law.tau) + " Hz")
    print("  shear weights " + ", ".join(f"{c:.3f}" for c in law.weights["shear"])
          + f"; loss within {100 * constitution.ripple(law, 'shear', 0.1):.1f} % of 0.1 over 1 Hz-2 kHz")
    k = {f: law.kappa(2 * np.pi * f)["shear"] for f in (0.0, 1.0, 100.0, 2000.0)}
    print("  Re kappa at 0, 1, 100, 2000 Hz: " + ", ".join(f"{v.real:.3f}" for v in k.values())
          + f" (Kramers-Kronig for a constant 0.1: (2000 / 1)^(2 atan(0.1) / pi) = "
          f"{2000 ** (2 * np.arctan(0.1) / np.pi):.2f}; law {k[2000.0].real / k[1.0].real:.2f})")
    for name in ("thesis-pzt-single-2d", "thesis-pzt-3x3-2d"):
        dm = dynamics.model(problem(taxel.load(name)))
        new = responses(dm)
        old = responses(dm, hysteretic(dm))
        print(f"\n{name} (pressed taxel), causal law vs the constant loss factors:")
        for label, a, b, unit in (("|V_oc|", new[0], old[0], "V/N"), ("|Q_sc|", new[1], old[1], "C/N"),
                                  ("|C|", new[2], old[2], "F")):
            print(f"  {label:7s} " + "; ".join(f"{f:g} Hz {x:.4g} ({100 * (x / y - 1):+.1f} %)"
                                                for f, x, y in zip(POINTS, a, b)) + f"  [{unit}]")
        print(f"  first resonance of V_oc: {new[3]:.0f} Hz (constant loss factors: {old[3]:.0f} Hz, "
              f"{100 * (new[3] / old[3] - 1):+.1f} %)")


if __name__ == "__main__":
    main()
