r"""The reduced-order model of a scene: a MIMO dynamic model from the FEM, kept.

Inputs (N): a force on each taxel's footprint (`inputs="taxels"`, array scenes
without an indenter: the same uniform pressure the scene's `load.kind = "taxel"`
puts on the pressed taxel, on the same mesh), or the scene's own load
(`inputs="probe"`). Outputs: the scene's readout chain at every active electrode
(V), or the short-circuit charges (`output="charge"`, C).

A 2D model is the section through the pressed row: its paths are the row's
taxels pressed, the row's taxels read (3 x 3 of the 9 x 9 paths of a 3 x 3
array; the others need a 3D model).

Two views of the same reduced model (fem.dynamics):
* `frf(f)`: the reduced second-order model with the FEM's causal loss law
  (fem.constitution), exactly the model the frequency analysis solves, then the
  readout (fem.readout);
* `state_space()`: its real first-order realization (fem.dynamics: the loss law's
  internal variables, condensed, modal, truncated to the modes that matter in the
  band with a measured error), which `simulate` and the exports (python-control,
  scipy.signal, MATLAB .mat) use. Both agree with the direct FEM sweep.
"""

from __future__ import annotations

import hashlib
import json
import time
from dataclasses import asdict, dataclass, field, replace
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from taxel.fem import readout as circuits
from taxel.fem import dynamics
from taxel.fem.assembly import elements, load_vector
from taxel.fem.assembly import PatchLoad
from taxel.fem.constitution import Relaxation
from taxel.fem.dynamics import PortResponse
from taxel.scene import Scene, SceneError, parse
from taxel.schema import to_data
from taxel.schema import electrode_name
from taxel.analyses.solves import reduced_export
from taxel.analyses.solves.version import code_version
from taxel.analyses.model.problem import problem, readout
from taxel.analyses.results.base import FORMAT, write_result


@dataclass
class ReducedModel:
    """A scene's reduced model (see the module docstring); built by `reduce(scene)`."""

    scene: Scene
    red: dynamics.ProjectedModel
    input_names: list[str]         # "force:<taxel>" or "force:probe"
    output_names: list[str]        # "<quantity>:<electrode>"
    output_unit: str               # V or C
    readout: circuits.Readout | str    # a Readout, or "charge"
    band: tuple = (1.0, 2000.0)    # Hz: where the state space's modal truncation is measured (fem.dynamics)
    seconds: float = 0.0
    provenance: dict = field(default_factory=dict)
    _ss: dynamics.StateSpace | None = field(default=None, repr=False)
    kind = "reduced"
    error = None                   # no ErrorEstimate: the reduction's own measured error is `measured_error`

    @property
    def order(self) -> int:
        """The state-space order (number of states)."""
        return self.state_space().order

    def frf(self, freqs) -> np.ndarray:
        """(nf, outputs, inputs) complex: readout output per newton of each input, with
        the FEM's loss law (the reduced second-order model)."""
        freqs = np.atleast_1d(np.asarray(freqs, float))
        V, Ci = dynamics.ports(self.red, freqs)
        return port_readout(freqs, V, Ci, self.red.names, self.readout)

    def state_space(self) -> dynamics.StateSpace:
        """The real first-order realization (fem.dynamics), A, B, C, D in SI units."""
        if self._ss is None:
            self._ss = dynamics.realize(self.red, self.readout, self.band)
        return self._ss

    def simulate(self, t, force) -> np.ndarray:
        """Outputs (nt, outputs) for forces (nt, inputs) in N at uniform times t (s)."""
        return self.state_space().simulate(t, force)

    @property
    def measured_error(self) -> float:
        """The reduction's relative error against direct solves at the last check frequency."""
        return self.red.error

    def pressed(self) -> tuple[int, int]:
        """(output, input) index of the pressed taxel's own path (else the first)."""
        name = electrode_name(*self.scene.load.taxel)
        i = next((k for k, n in enumerate(self.output_names) if n.endswith(":" + name)), 0)
        j = next((k for k, n in enumerate(self.input_names) if n.endswith(":" + name)), 0)
        return i, j

    def outputs(self) -> dict[str, float]:
        """reduced_order (states); reduction_error (measured, relative);
        static_gain: the pressed path's readout output per newton at 1 Hz (V/N or C/N)."""
        i, j = self.pressed()
        return {"reduced_order": float(self.order), "reduction_error": float(self.red.error),
                "static_gain": float(abs(self.frf([1.0])[0, i, j]))}

    def record(self) -> dict:
        return {"kind": self.kind, "format": FORMAT, "scene": self.scene.name, "inputs": self.input_names,
                "outputs_named": self.output_names, "output_unit": self.output_unit, "input_unit": "N",
                "readout": self.readout_label, "band_Hz": list(self.band),
                "truncation_error": self.state_space().truncation_error, "loss_law": self.red.relax.to_data(),
                "order": self.order, "basis_size": self.red.order, "measured_error": self.red.error,
                "checks": [[f, e] for f, e in self.red.checks], "seconds": self.seconds,
                "files": {"npz": "model.npz", "mat": "model.mat"}, "provenance": self.provenance,
                "outputs": self.outputs(), "error_estimate": None,
                "error_note": "no mesh-error estimate; the reduction's own error is measured against direct "
                              "solves (measured_error)"}

    @property
    def readout_label(self) -> str:
        return "short-circuit charge" if self.readout == "charge" else self.readout.label

    def summary(self) -> list[str]:
        i, j = self.pressed()
        return [f"reduced model of {self.scene.name}: {len(self.input_names)} inputs (N) x {len(self.output_names)} outputs "
                f"({self.output_unit}, {self.readout_label})",
                f"  {self.order} states ({self.red.order} basis vectors), built in {self.seconds:.1f} s, "
                f"measured error {self.red.error:.1e} (checks at "
                + ", ".join(f"{f:.4g} Hz" for f, _ in self.red.checks) + ")",
                f"  static gain {self.input_names[j]} -> {self.output_names[i]}: {self.outputs()['static_gain']:.4g} "
                f"{self.output_unit}/N",
                f"  losses: the causal law of fem.constitution ({self.red.relax.n} relaxation times), exact in the "
                f"state space; its modal truncation error {self.state_space().truncation_error:.1e} over "
                f"{self.band[0]:g}-{self.band[1]:g} Hz"]

    def __str__(self) -> str:
        return "\n".join(self.summary())

    # exports (taxel.analyses.solves.reduced_export)
    def to_control(self):
        ss = self.state_space()
        return reduced_export.to_control(ss.A, ss.B, ss.C, ss.D, self.input_names, self.output_names, self.scene.name)

    def to_scipy(self):
        ss = self.state_space()
        return reduced_export.to_scipy(ss.A, ss.B, ss.C, ss.D)

    def save_mat(self, path) -> Path:
        ss = self.state_space()
        return reduced_export.save_mat(path, ss.A, ss.B, ss.C, ss.D, self.input_names, self.output_names, "N",
                                       self.output_unit, f"taxel reduced model of {self.scene.name}: "
                                       f"{self.readout_label}; provenance in the .npz")

    def save(self, path) -> Path:
        """The model as .npz (state space, reduced second-order model, provenance)."""
        ss, r = self.state_space(), self.red
        arrays = {"A": ss.A, "B": ss.B, "C": ss.C, "D": ss.D, "M": r.M, "mech": r.mech, "F": r.F, "Be": r.Be,
                  "E": r.E, "u_cols": r.u_cols, **{f"part:{k}": P for k, P in r.parts.items()}}
        meta = {"format": FORMAT, "inputs": self.input_names, "outputs": self.output_names, "output_unit": self.output_unit,
                "readout": "charge" if self.readout == "charge" else asdict(self.readout), "band": list(self.band),
                "truncation_error": ss.truncation_error, "seconds": self.seconds, "names": r.names, "alpha": r.alpha,
                "beta": r.beta, "relax": r.relax.to_data(),
                "error": r.error, "checks": r.checks, "scene": to_data(self.scene), "provenance": self.provenance}
        return reduced_export.save_npz(path, arrays, meta)

    @classmethod
    def load(cls, path) -> "ReducedModel":
        """A model written by `save` (ValueError, one line, for another file)."""
        a, m = reduced_export.load_npz(path)
        try:
            reduced_export.check_arrays(a, m)
            red = dynamics.ProjectedModel({k[5:]: v for k, v in a.items() if k.startswith("part:")},
                                  Relaxation.from_data(m["relax"]), a["M"], a["mech"],
                                  m["alpha"], m["beta"], a["F"], a["Be"], a["E"], a["u_cols"], m["names"], m["error"],
                                  [tuple(c) for c in m["checks"]], m["seconds"])
            r = m["readout"] if m["readout"] == "charge" else circuits.Readout(**m["readout"])
            model = cls(parse(m["scene"]), red, m["inputs"], m["outputs"], m["output_unit"], r, tuple(m["band"]),
                        m["seconds"], m["provenance"])
            model._ss = dynamics.StateSpace(a["A"], a["B"], a["C"], a["D"], float(m["truncation_error"]))
        except (KeyError, TypeError, ValueError, AttributeError, IndexError, SceneError) as exc:
            why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise ValueError(f"{path}: not a reduced model file ({why}); write it with taxel reduce SCENE -o FILE.npz") \
                from None
        return model

    def to_folder(self, out) -> list[Path]:
        """result.json, scene.json, model.npz and model.mat."""
        out = Path(out)
        paths = write_result(out, self.record(), self.scene)
        return paths + [self.save(out / "model.npz"), self.save_mat(out / "model.mat")]



def read_folder(folder) -> ReducedModel:
    """The model of a folder written by `ReducedModel.to_folder` (taxel.read)."""
    rec = json.loads((Path(folder) / "result.json").read_text())
    return ReducedModel.load(Path(folder) / rec.get("files", {}).get("npz", "model.npz"))


def port_readout(freqs, V, Ci, names, r) -> np.ndarray:
    """The readout (fem.readout) applied to each input's port response: (nf, na, m)."""
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
           tol: float = 1e-4) -> ReducedModel:
    """The reduced model of a scene (module docstring). inputs: "taxels" (default for
    array scenes without an indenter) or "probe"; output: "readout" or "charge";
    f_max: the highest frequency it must hold (default the scene's analysis.f_max,
    at least 2 kHz)."""
    t0 = time.perf_counter()
    if scene.model.symmetry != "full":          # dynamic models are solved on the full mesh
        scene = scene.replace(**{"model.symmetry": "full"})
    arr = scene.array
    pressed_by_indenter = scene.load.kind == "probe" and scene.load.contact
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
    red = dynamics.build(dm, loads, f_top, max(scene.analysis.f_min, 0.1), tol)
    r = "charge" if output == "charge" else readout(scene)
    quantity = "charge" if output == "charge" else ("voltage" if r.circuit != "charge_amplifier" else "output")
    data = to_data(scene)
    provenance = {"scene": scene.name, "scene_sha256": hashlib.sha256(json.dumps(data, sort_keys=True).encode())
                  .hexdigest(), "taxel_version": _version(), "built": datetime.now(timezone.utc).isoformat(
                      timespec="seconds"), "unknowns": int(dm.M.shape[0]), "inputs": inputs, "output": output}
    return ReducedModel(scene, red, names_in, [f"{quantity}:{k}" for k in red.names],
                        "C" if output == "charge" else "V", r, (max(scene.analysis.f_min, 0.1), f_top),
                        time.perf_counter() - t0, provenance)


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("taxel")
    except PackageNotFoundError:
        return "unknown"


def cached(scene: Scene, inputs: str | None = None, output: str = "readout") -> ReducedModel:
    """`reduce(scene, inputs, output)`, kept in the user's cache (taxel.analyses.solves.crosstalk.cache_dir)
    keyed by the scene's SHA-256, the options and the code version (taxel.analyses.solves.version:
    a change to the FEM or the analyses rebuilds it); rebuilt when missing or unreadable."""
    from taxel.analyses.solves.crosstalk import cache_dir
    key = hashlib.sha256(json.dumps([to_data(scene), inputs, output, FORMAT, code_version()],
                                    sort_keys=True).encode()).hexdigest()
    path = cache_dir() / f"reduced-{key[:16]}.npz"
    try:
        return ReducedModel.load(path)
    except ValueError:
        pass
    model = reduce(scene, inputs, output)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        model.save(path)
    except OSError:
        pass
    return model


@dataclass
class OnePort:
    """One path of a reduced model as a one-port taxel, the interface the chain fits
    use for the lumped model (studies.measured.frf.lumped_frf, calibrate): the
    static capacitance `C_p` of electrode `output` (F), `force` = 1 N, and `V_oc(f)`
    defined as -Q_sc(f) / C_p with Q_sc the FEM's short-circuit charge per newton of
    taxel `output` pressed on `input`, every electrode held at 0 V (as the rig's charge
    amplifiers hold them; the capacitance relaxes with frequency, fem.constitution, so
    the charge, not the open-circuit voltage, is the path's invariant). Values are remembered per frequency array (a least-squares
    fit asks for the same frequencies again and again)."""

    model: ReducedModel
    output: int
    input: int
    C_p: float
    force: float = 1.0
    _memo: dict = field(default_factory=dict, repr=False)

    def V_oc(self, freqs) -> np.ndarray:
        freqs = np.asarray(freqs, float)
        key = freqs.tobytes()
        if key not in self._memo:
            V, Ci = dynamics.ports(self.model.red, freqs)
            Q_sc = -np.linalg.solve(Ci, V)[:, self.output, self.input]      # every electrode at 0 V
            self._memo[key] = -Q_sc / self.C_p
        return self._memo[key]

    def Q_sc(self, freqs) -> np.ndarray:
        return -self.C_p * self.V_oc(freqs) * self.force


def one_port(model: ReducedModel, taxel: tuple[int, int] | None = None) -> OnePort:
    """The path of `taxel` pressed and read (default the scene's pressed taxel) as a OnePort."""
    name = electrode_name(*(taxel if taxel is not None else model.scene.load.taxel))
    names = model.red.names
    i = names.index(name) if name in names else 0
    j = next((k for k, n in enumerate(model.input_names) if n.endswith(":" + name)), 0)
    C = np.linalg.inv(dynamics.ports(model.red, [1e-3])[1][0]).real
    return OnePort(model, i, j, float(C[i, i]))
