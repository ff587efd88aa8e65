"""File formats and toolboxes of a reduced model's state space x' = A x + B u,
y = C x + D u (u: forces in N; y: volts, or coulombs for charge outputs):

- python-control `StateSpace` with the input and output names (`to_control`);
- `scipy.signal.StateSpace` (`to_scipy`; it carries no names);
- MATLAB/Simulink `.mat` (`save_mat`): A, B, C, D, InputName, OutputName,
  InputUnit, OutputUnit, Description; in MATLAB `ss(A, B, C, D, 'InputName', InputName, ...)`;
- the project's own `.npz` (`save_npz` / `load_npz`): the state space, the second-order
  reduced model behind it (so `frf` keeps the FEM's loss factors) and the scene's
  provenance (the validated scene as JSON, its SHA-256, the taxel version, the date).
"""

from __future__ import annotations

import json
import zipfile
import zlib
from pathlib import Path

import numpy as np


def to_control(A, B, C, D, inputs, outputs, name="taxel"):
    """A python-control StateSpace with named signals."""
    import control
    return control.ss(A, B, C, D, inputs=list(inputs), outputs=list(outputs), name=name)


def to_scipy(A, B, C, D):
    """A scipy.signal.StateSpace (continuous)."""
    from scipy import signal
    return signal.StateSpace(A, B, C, D)


def save_mat(path, A, B, C, D, inputs, outputs, input_unit, output_unit, description) -> Path:
    """MATLAB .mat (version 5) with cell arrays of names and units."""
    from scipy.io import savemat
    path = Path(path)

    def cell(items):
        return np.array(list(items), dtype=object).reshape(-1, 1)
    savemat(path, {"A": A, "B": B, "C": C, "D": D, "InputName": cell(inputs), "OutputName": cell(outputs),
                   "InputUnit": cell([input_unit] * len(inputs)), "OutputUnit": cell([output_unit] * len(outputs)),
                   "Description": description}, oned_as="column")
    return path


def load_mat(path) -> dict:
    """A, B, C, D and the names of a .mat written by `save_mat`."""
    from scipy.io import loadmat
    m = loadmat(path)
    names = {k: [str(np.ravel(x)[0]) for x in np.ravel(m[k])] for k in ("InputName", "OutputName")}
    return {"A": m["A"], "B": m["B"], "C": m["C"], "D": m["D"], "inputs": names["InputName"],
            "outputs": names["OutputName"]}


def save_npz(path, arrays: dict, meta: dict) -> Path:
    """Arrays (float, complex or bool) and JSON metadata in one compressed .npz."""
    path = Path(path)
    np.savez_compressed(path, meta=np.array(json.dumps(meta)), **arrays)
    return path


def check_arrays(arrays: dict, meta: dict) -> None:
    """A model file's arrays before use (ValueError, one line): every one numeric and finite;
    the state space A (n, n), B (n, p), C (q, n), D (q, p); the metadata a JSON object."""
    if not isinstance(meta, dict):
        raise ValueError("its metadata is not a table")
    for k, v in meta.items():
        if isinstance(v, float) and not np.isfinite(v):
            raise ValueError(f"its metadata {k} is {v}")
    for k, v in arrays.items():
        if v.dtype.kind not in "biufc":
            raise ValueError(f"array {k} is not numeric ({v.dtype})")
        if v.dtype.kind in "fc" and not np.isfinite(v).all():
            raise ValueError(f"array {k} holds NaN or infinite values")
    A, B, C, D = (arrays[k] for k in ("A", "B", "C", "D"))
    if not (A.ndim == B.ndim == C.ndim == D.ndim == 2 and A.shape[0] == A.shape[1] == B.shape[0] == C.shape[1]
            and D.shape == (C.shape[0], B.shape[1])):
        raise ValueError(f"the state space's shapes do not fit: A {A.shape}, B {B.shape}, C {C.shape}, D {D.shape}")


def load_npz(path) -> tuple[dict, dict]:
    """(arrays, meta) of a file written by `save_npz`; ValueError (one line) otherwise."""
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files if k != "meta"}
            meta = json.loads(str(z["meta"]))
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, zlib.error) as exc:
        raise ValueError(f"{path}: not a reduced model file ({str(exc).splitlines()[0] if str(exc) else type(exc).__name__}); write it with taxel reduce SCENE -o FILE.npz") \
            from None
    return arrays, meta
