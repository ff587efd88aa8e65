"""The skin file: everything a simulator needs of a designed taxel array (numpy only).

Frame (the skin frame): the sensor's top surface, x along the columns, y along the
rows, in metres from taxel (0, 0)'s centre (taxel (r, c) is centred at
(c pitch, r pitch)), z its outward normal. A contact's force is the force on the skin
in that frame: a press has f_z < 0; a normal-only force is given as its magnitude
F > 0 (pressing), the same as (0, 0, -F).

The sensor model (built by taxel.skin.build, whose docstring derives it): a force
f_j(t) at the point p_j of the surface drives taxel k through its spatial influence,

    u_k(t) = sum_j sum_d W_kd(p_j) f_jd(t)                 (N, the force "seen" by taxel k)
    v_k    = h(s) u_k                                      (V, the readout's output)

W (`influence`, (taxels, 3, ny, nx)) a plain array on an evenly spaced grid of the
surface (`grid_x`, `grid_y`), bilinear between its points: the short-circuit charge
taxel k collects per newton along d at a point, over the reference taxel's charge
per newton of a press on its own footprint (so W_k,z = -1 for a press there: the
sign of a press is f_z < 0). From a 3D scene it is the surface map's (taxel.analyses.
surface_map: every taxel, normal and both shears, non-separable); from a 2D section,
the separable normal-only influence of taxel.analyses.surface.influence (shear columns zero;
`spatial` says which). h the reference taxel's path from a force on its footprint to
its readout output through the scene's readout chain, as poles and residues
(taxel.skin.readout), discretized at the skin's step `dt` by first-order hold as
x[k+1] = Ad x[k] + Bd u[k], v[k] = Cd x[k] + Dd u[k]; `dynamics_error` its measured
error against the solver's frequency sweep over 1 Hz .. `band`, the band where it
holds 1 % in magnitude and 1 degree in phase. Sign: the solver's (a charge
amplifier's output is -Q_sc / C_f in its passband).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

FORMAT = "taxel-skin/2"

_ARRAYS = ("grid_x", "grid_y", "influence", "Ad", "Bd", "Cd", "Dd", "A", "B", "C", "D", "noise_freqs", "noise_psd",
           "check_points", "check_fem", "check_model")


@dataclass
class SkinModel:
    """A skin's sensor model (module docstring); `save`/`load` as .npz."""

    rows: int
    cols: int
    pitch: float                 # m, taxel centre to centre
    taxel_width: float           # m
    margin: float                # m, silicone beyond the outer taxels' edges
    grid_x: np.ndarray           # (nx,) m, evenly spaced (skin frame)
    grid_y: np.ndarray           # (ny,) m
    influence: np.ndarray        # (taxels, 3, ny, nx) W_kd: N seen per N of force along x, y, z (z outward)
    spatial: str                 # where W comes from, in words
    sensitivity: float           # V/N, S_ref: the reference taxel's open-circuit voltage per newton on its footprint
    dt: float                    # s, the step Ad..Dd are discretized at
    Ad: np.ndarray
    Bd: np.ndarray
    Cd: np.ndarray
    Dd: np.ndarray
    A: np.ndarray                # the continuous h(s) (V per N), SI
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    noise_freqs: np.ndarray      # (nf,) Hz
    noise_psd: np.ndarray        # (sources, nf) V^2/Hz at the readout output
    noise_sources: list[str]
    saturation: float            # V, the largest |output| before clipping (inf: none)
    adc: dict | None             # {bits, lo, hi, gain, offset} or None (no ADC)
    influence_error: float       # max |W_model - W_check| over the checks, of W's peak (1)
    check_points: np.ndarray     # (k, 2) m, presses between grid points (skin frame)
    check_fem: np.ndarray        # (k, taxels) W_z there from the source (FEM presses or the map's spline)
    check_model: np.ndarray      # (k, taxels) the skin's bilinear W_z there
    reduction_error: float       # h's error: the reduced model's against direct FEM solves + its modal cut's
    readout: str                 # the readout chain in words
    provenance: dict = field(default_factory=dict)   # scene (data), scene_sha256, taxel_version, built
    dynamics_error: float = float("nan")   # Ad..Dd against the solver's sweep, of its peak, over 1 Hz .. band
    band: float = float("nan")             # Hz: up to here within 1 % in magnitude and 1 degree in phase
    format: str = FORMAT

    @property
    def taxels(self) -> int:
        return self.rows * self.cols

    def centres(self) -> np.ndarray:
        """(rows, cols, 2) m, each taxel's centre (x, y)."""
        r, c = np.meshgrid(np.arange(self.rows), np.arange(self.cols), indexing="ij")
        return np.stack([c * self.pitch, r * self.pitch], axis=-1).astype(float)

    def extent(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) m of the sensor's surface."""
        e = self.taxel_width / 2 + self.margin
        return -e, (self.cols - 1) * self.pitch + e, -e, (self.rows - 1) * self.pitch + e

    def save(self, path):
        """Write the skin as .npz to a path (returned as a Path) or a binary file object."""
        path = path if hasattr(path, "write") else Path(path)
        meta = {k: getattr(self, k) for k in ("rows", "cols", "pitch", "taxel_width", "margin", "sensitivity", "dt",
                                               "noise_sources", "spatial", "saturation", "adc", "influence_error",
                                               "reduction_error", "readout", "provenance", "format",
                                               "dynamics_error", "band")}
        meta["saturation"] = None if not np.isfinite(self.saturation) else self.saturation
        np.savez_compressed(path, meta=np.array(json.dumps(meta)), **{k: getattr(self, k) for k in _ARRAYS})
        return path

    @classmethod
    def load(cls, path) -> "SkinModel":
        """A skin written by `save`; ValueError (one line) for another file or format."""
        try:
            with np.load(path, allow_pickle=False) as z:
                arrays = {k: z[k] for k in _ARRAYS}
                meta = json.loads(str(z["meta"]))
        except (OSError, ValueError, KeyError) as exc:
            raise ValueError(f"{path}: not a skin file ({exc}); write one with taxel skin SCENE -o FILE.npz") from None
        if meta.get("format") != FORMAT:
            raise ValueError(f"{path}: skin format {meta.get('format')!r}, this taxel reads {FORMAT!r}; "
                             "rebuild it with taxel skin SCENE -o FILE.npz")
        meta["saturation"] = np.inf if meta["saturation"] is None else meta["saturation"]
        return cls(**meta, **arrays)
