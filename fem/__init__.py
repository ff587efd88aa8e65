"""The finite-element model, laid out as its modelling chain.

Each subpackage re-exports its public names (`__all__`); callers import from the
subpackage, never from its private modules (`_name.py`). Each imports only the
ones below it (the import contract in `.ci/importlinter.toml`):

    constitution   materials, kinematics, linear laws, Yeoh and its fit, relaxation
         |
    linalg         direct and Krylov solves, memory checks, the solver choice
         |
    assembly       Problem -> System: forms, vectorised assembly, constraints
         |
    static | readout | thermal
         |           static: linear solve, fields, symmetry;
         |           readout: circuits, noise, the seed's lumped model;
         |           thermal: heat conduction, the pyroelectric charge
    hyperelastic   Yeoh Newton (patch loads), plane-stress Yeoh
         |
    contact        a rigid indenter's press: gap, Newton, load path, records
         |
    dynamics       frequency sweep, time stepping, reduced-order model, state space

The FEM never sees the scene (the TOML schema): `taxel.analyses` builds a
`Problem` from it, and reads the `Solution` back.
"""
