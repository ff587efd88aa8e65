r"""The reduced-order model of a scene: a MIMO dynamic model from the FEM, kept.

Inputs (N): a force on each taxel's footprint (`inputs="taxels"`, array scenes
without an indenter: the same uniform pressure the scene's `load.kind = "taxel"`
puts on the pressed taxel, on the same mesh), or the scene's own load
(`inputs="probe"`). Outputs: the scene's readout chain at every active electrode
(V), or the short-circuit charges (`output="charge"`, C).

A 2D model is the section through the pressed row: its paths are the row's
taxels pressed, the row's taxels read (3 x 3 of the 9 x 9 paths of a 3 x 3
array; the others need a 3D model).

Two views of the same reduced model (fem.reduced):
* `frf(f)`: the reduced second-order model with the FEM's complex loss factors,
  exactly the model the frequency analysis solves, then the readout (fem.circuits);
* `state_space()`: its real first-order realization (fem.statespace: condensed,
  modal, loss factors as viscous damping matched at each mode's frequency), which
  `simulate`, and the exports (python-control, scipy.signal, MATLAB .mat) use.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np

from taxel.fem import circuits, dynamics, reduced, statespace
from taxel.fem.assembly import elements, load_vector
from taxel.fem.problem import PatchLoad
from taxel.fem.sweep import PortResponse
from taxel.scene import Scene, SceneError
from taxel.analyses.adapter import problem, readout


@dataclass
class ReducedModel:
    """A scene's reduced model (see the module docstring); built by `reduce(scene)`."""

    scene: Scene
    red: reduced.Reduced
    inputs: list[str]              # "force:<taxel>" or "force:probe"
    outputs: list[str]             # "<quantity>:<electrode>"
    output_unit: str               # V or C
    readout: circuits.Readout | str    # a Readout, or "charge"
    loss: str = "modal"
    seconds: float = 0.0
    _ss: statespace.StateSpace | None = field(default=None, repr=False)

    @property
    def order(self) -> int:
        """The state-space order (number of states)."""
        return self.state_space().order

    def frf(self, freqs) -> np.ndarray:
        """(nf, outputs, inputs) complex: readout output per newton of each input, with
        the FEM's loss factors (the reduced second-order model)."""
        freqs = np.atleast_1d(np.asarray(freqs, float))
        V, Ci = reduced.ports(self.red, freqs)
        return port_readout(freqs, V, Ci, self.red.names, self.readout)

    def state_space(self) -> statespace.StateSpace:
        if self._ss is None:
            self._ss = statespace.realize(self.red, self.readout, self.loss)
        return self._ss

    def simulate(self, t, force) -> np.ndarray:
        """Outputs (nt, outputs) for forces (nt, inputs) in N at uniform times t (s)."""
        return self.state_space().simulate(t, force)


def port_readout(freqs, V, Ci, names, r) -> np.ndarray:
    """The readout (fem.circuits) applied to each input's port response: (nf, na, m)."""
    if r == "charge":
        return -np.einsum("fij,fjm->fim", np.linalg.inv(Ci), V)
    out = np.zeros_like(V)
    for j in range(V.shape[2]):
        out[:, :, j] = circuits.readout(PortResponse(freqs, V[:, :, j], Ci, names, "reduced", 0.0), r)
    return out


def taxel_loads(dm: dynamics.DynamicModel) -> tuple[np.ndarray, list[str]]:
    """Reduced load vectors (n, taxels) of 1 N uniformly over each taxel's footprint
    on the top surface (facets whose midpoint lies over the taxel; the plan is
    fragmented at every taxel edge, so the footprint is exact), and the taxels' names."""
    sy = dm.sy
    tm, prob = sy.tm, sy.problem
    mesh = tm.mesh
    top = np.asarray(tm.facets["top"])
    mid = mesh.p[:, mesh.facets[:, top]].mean(axis=1)
    x, y = (mid[0], np.zeros(len(top))) if mesh.dim() == 2 else (mid[0], mid[1])
    eu = elements(mesh.dim(), prob.discretization.order, prob.discretization.mixed)[0]
    cols, names = [], []
    for patch in tm.layout.taxels:
        inside = np.array([patch.contains(a, b, tol=1e-9 * patch.half) for a, b in zip(x, y)])
        t = replace(tm, facets={**tm.facets, "load": top[inside]}, layout=replace(tm.layout, load=patch))
        b, force = load_vector(replace(prob, mesh=t, load=PatchLoad(force=1.0)), eu, sy.A.shape[0])
        cols.append(dm.red.P.T @ b / force)
        names.append(patch.name)
    return np.column_stack(cols), names


def reduce(scene: Scene, inputs: str | None = None, output: str = "readout", f_max: float | None = None,
           tol: float = 1e-4, loss: str = "modal") -> ReducedModel:
    """The reduced model of a scene (module docstring). inputs: "taxels" (default for
    array scenes without an indenter) or "probe"; output: "readout" or "charge";
    f_max: the highest frequency it must hold (default the scene's analysis.f_max,
    at least 2 kHz)."""
    t0 = time.perf_counter()
    if scene.model.symmetry != "full" if hasattr(scene.model, "symmetry") else False:
        scene = scene.replace(**{"model.symmetry": "full"})
    arr = scene.array
    pressed_by_indenter = scene.load.kind == "indenter" and scene.load.contact
    if inputs is None:
        inputs = "taxels" if arr is not None and not pressed_by_indenter else "probe"
    if inputs not in ("taxels", "probe"):
        raise SceneError(f"inputs = '{inputs}': use 'taxels' (a force on each taxel) or 'probe' (the scene's load)")
    if output not in ("readout", "charge"):
        raise SceneError(f"output = '{output}': use 'readout' (the scene's readout chain) or 'charge'")
    if inputs == "taxels" and (arr is None or pressed_by_indenter):
        raise SceneError("inputs = 'taxels' needs a taxel-array scene ([array]) without a contact indenter; "
                         "use inputs = 'probe'")
    dm = dynamics.model(problem(scene))
    if inputs == "taxels":
        loads, taxels = taxel_loads(dm)
        names_in = [f"force:{k}" for k in taxels]
    else:
        loads, names_in = dm.F[:, None], ["force:probe"]
    f_top = max(f_max or scene.analysis.f_max, 2000.0)
    red = reduced.build(dm, loads, f_top, max(scene.analysis.f_min, 0.1), tol)
    r = "charge" if output == "charge" else readout(scene)
    quantity = "charge" if output == "charge" else ("voltage" if r.circuit != "charge_amplifier" else "output")
    return ReducedModel(scene, red, names_in, [f"{quantity}:{k}" for k in red.names],
                        "C" if output == "charge" else "V", r, loss, time.perf_counter() - t0)
