"""The FEM-informed 3-DoF lumped model (fem.readout.identified, taxel.analyses.solves.lumped_fem)."""

import numpy as np

import taxel
from taxel.analyses.solves import lumped_fem
from taxel.analyses import problem
from taxel.analyses.solves.dynamic import lumped_model
from taxel.fem import dynamics


def test_informed_lumped_static_charge_per_newton_equals_the_fems_and_the_seeds_does_not():
    scene = taxel.load("thesis-pzt-single-2d")
    fem = lumped_fem.targets(scene)
    idf = lumped_fem.informed(scene, fem)
    lm, seed = idf.model, lumped_model(scene)
    # the FEM's charge by another route: the lossless sweep's short-circuit charge at 1 mHz
    lossless = scene.replace(**{"dynamics.silicone_loss": 0.0, "dynamics.piezo_loss": 0.0,
                                "dynamics.dielectric_loss": 0.0})
    port = dynamics.sweep(dynamics.model(problem(lossless)), [1e-3], "direct")
    q_fem = abs(port.Q_sc[0, 0])
    q_lumped = abs(lm.Q_sc([1e-3])[0]) / lm.force
    assert abs(q_lumped / q_fem - 1) < 1e-2
    assert abs(abs(seed.Q_sc([1e-3])[0]) / seed.force / q_fem - 1) > 0.5          # the seed's is 4-5x below
    # its first mode is the FEM's first resonance, and its static compliance the FEM's
    A = lm.state_space()[0]
    assert np.isclose(np.abs(np.linalg.eigvals(A)).min(), 2 * np.pi * fem.first_resonance, rtol=0.05)
    assert np.isclose((1 / lm.k).sum(), fem.compliance, rtol=1e-9)
    assert idf.scales["silicone_stiffness"] > 1 and idf.scales["silicone_mass"] > 1
