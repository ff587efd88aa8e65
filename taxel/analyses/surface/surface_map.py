"""The surface map: where a press lands, in 3D, for every taxel at once.

A `SurfaceMap` holds, on a grid of the sensor's top surface, every taxel's
short-circuit charge per newton of a point force along x, y and z there (C/N),
and the taxels' capacitance matrix (F). By reciprocity (docs/theory/surface-map.md,
fem.static.unit_voltage_fields) the charge taxel j collects, short-circuited, under
a unit force along k at x is u_k(x) of the static solve with 1 V on electrode j and
every other taxel grounded: one linear 3D solve per electrode gives the whole map.

Conventions: plan coordinates x, y in m, origin at the array centre, z the outward
normal of the top surface (a press is a force with f_z < 0); charges are the
short-circuit charges (what a charge amplifier integrates), open-circuit voltages
follow through the capacitance matrix, V = -C^-1 Q_sc (every taxel open at once,
the common ground the reference). Between grid points the map is a bicubic spline.

    m = surface_map(scene)                           # taxel.analyses.surface.surface_map.build
    m.charge([(x, y)], [(0, 0, -1.0)])              # C, a 1 N point press at (x, y)
    m.voltage(points, forces, Footprint(2e-3))       # V, open circuit, a 2 mm disc probe
    m.crosstalk((x, y), "taxel_0_1")                 # signed ratio to the best taxel
    m.to_file("map.npz"); SurfaceMap.from_file("map.npz")

The linear map is the small-force limit; `ProbeCorrection` carries the rig's
probe on the Yeoh silicone (a force-dependent factor per position on a coarse grid
of 3D presses, interpolated), applied by `probe_voltage`.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np
from scipy.interpolate import NdBSpline, RectBivariateSpline

FORMAT = "taxel-surface-map-1"
DIRECTIONS = ("x", "y", "z")


@dataclass(frozen=True)
class Footprint:
    """A probe's contact footprint on the top surface: a disc of `radius` (m; 0: a
    point force), the pressure over it `flat` (uniform) or `round` (Hertzian,
    proportional to sqrt(1 - r^2 / radius^2)); the resultant is the force given."""

    radius: float = 0.0
    profile: str = "flat"

    def __post_init__(self):
        if self.radius < 0 or self.profile not in ("flat", "round"):
            raise ValueError(f"footprint: radius {self.radius} m, profile {self.profile!r}; "
                             "give radius >= 0 and profile 'flat' or 'round'")

    def quadrature(self, rings: int = 6, spokes: int = 16) -> tuple[np.ndarray, np.ndarray]:
        """Offsets (n, 2) in m and weights (n,) summing to 1 over the disc (Gauss-Legendre
        in r with the profile and r dr, equal steps in angle)."""
        if self.radius == 0:
            return np.zeros((1, 2)), np.ones(1)
        t, w = np.polynomial.legendre.leggauss(rings)
        r = 0.5 * (t + 1) * self.radius
        wr = 0.5 * self.radius * w * r * (np.sqrt(np.clip(1 - (r / self.radius) ** 2, 0, None))
                                          if self.profile == "round" else 1.0)
        a = (np.arange(spokes) + 0.5) * 2 * np.pi / spokes
        off = np.stack([np.outer(r, np.cos(a)).ravel(), np.outer(r, np.sin(a)).ravel()], axis=1)
        wts = np.repeat(wr, spokes)
        return off, wts / wts.sum()


@dataclass(frozen=True, eq=False)
class ProbeCorrection:
    """The rig's probe on the Yeoh silicone against the linear map: at each knot
    (x_k, y_l) of a coarse grid and each force F_m, the ratio of the pressed best
    taxel's 3D-press short-circuit charge to the linear map's for the same footprint
    and force. Interpolated bilinearly in position and linearly in force (clamped)."""

    x: np.ndarray                 # (kx,) m, knots
    y: np.ndarray                 # (ky,) m
    forces: np.ndarray            # (m,) N, the presses' forces (ascending)
    factor: np.ndarray            # (m, ky, kx) dimensionless
    footprint: Footprint

    def at(self, points, force: float) -> np.ndarray:
        """The factor at points (n, 2) for a press of `force` N (> 0)."""
        from scipy.interpolate import RegularGridInterpolator
        pts = np.atleast_2d(np.asarray(points, float))
        f = np.clip(force, self.forces[0], self.forces[-1])
        if len(self.y) == 1:                   # one row of knots: linear along x (clamped)
            per_force = np.array([np.interp(pts[:, 0], self.x, fk[0]) for fk in self.factor])
        else:
            per_force = np.array([RegularGridInterpolator((self.y, self.x), fk, bounds_error=False, fill_value=None)(
                pts[:, ::-1]) for fk in self.factor])                       # (m, n)
        if len(self.forces) == 1:
            return per_force[0]
        return np.array([np.interp(f, self.forces, per_force[:, i]) for i in range(pts.shape[0])])


@dataclass(frozen=True, eq=False)        # arrays: compare fields with np.array_equal
class SurfaceMap:
    """Every taxel's short-circuit charge per newton of a point force at each grid
    point of the top surface, and the capacitance matrix (module docstring)."""

    x: np.ndarray                 # (nx,) m, grid, origin at the array centre
    y: np.ndarray                 # (ny,) m
    taxels: tuple[str, ...]       # electrode names (taxel_ROW_COL), the order of every taxel axis
    charge_per_newton: np.ndarray  # (ntaxels, 3, ny, nx) C/N, force along x, y, z (z outward)
    capacitance: np.ndarray       # (ntaxels, ntaxels) F, the taxels' Maxwell capacitance matrix
    correction: ProbeCorrection | None = None
    info: dict = field(default_factory=dict, compare=False)   # scene name, mesh, solves, seconds
    centres: np.ndarray | None = None   # (ntaxels, 2) m, each taxel's centre (the array's plan)

    def __post_init__(self):
        n = len(self.taxels)
        if self.charge_per_newton.shape != (n, 3, len(self.y), len(self.x)) or self.capacitance.shape != (n, n):
            raise ValueError(f"surface map: charge_per_newton {self.charge_per_newton.shape} and capacitance "
                             f"{self.capacitance.shape} do not match {n} taxels on a {len(self.y)} x {len(self.x)} grid")

    # -- sampling ------------------------------------------------------------------
    @cached_property
    def _spline(self) -> NdBSpline:
        """Every taxel's and direction's interpolating spline (FITPACK's, RectBivariateSpline: one
        grid, so one set of knots) as one spline with (ntaxels, 3) values: one call per set of
        points instead of 3 per taxel (a search of single presses made 27 calls per point:
        benchmarks/surface_map_sampling.py)."""
        k = min(3, len(self.x) - 1, len(self.y) - 1)
        fits = [[RectBivariateSpline(self.y, self.x, self.charge_per_newton[j, d], kx=k, ky=k)
                 for d in range(3)] for j in range(len(self.taxels))]
        ty, tx = fits[0][0].get_knots()
        c = np.stack([np.stack([f.get_coeffs() for f in row], axis=-1) for row in fits], axis=-2)
        return NdBSpline((ty, tx), c.reshape(len(ty) - k - 1, len(tx) - k - 1, len(self.taxels), 3), k)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(x0, x1, y0, y1) of the mapped surface, m."""
        return float(self.x[0]), float(self.x[-1]), float(self.y[0]), float(self.y[-1])

    def index(self, taxel: str) -> int:
        try:
            return self.taxels.index(taxel)
        except ValueError:
            raise KeyError(f"{taxel}: no such taxel; the map has: {', '.join(self.taxels)}") from None

    def response(self, points) -> np.ndarray:
        """(n, ntaxels, 3) C/N: each taxel's short-circuit charge per newton along x, y, z
        at points (n, 2) m (clamped to the mapped surface)."""
        pts = np.atleast_2d(np.asarray(points, float))
        x0, x1, y0, y1 = self.bounds
        px, py = np.clip(pts[:, 0], x0, x1), np.clip(pts[:, 1], y0, y1)
        return self._spline(np.column_stack([py, px]))

    # -- loads ---------------------------------------------------------------------
    def charge(self, points, forces, footprint: Footprint | None = None) -> np.ndarray:
        """(n, ntaxels) C: short-circuit charges under a force (n, 3) or (3,) N (x, y, z;
        a press has f_z < 0) at each point (n, 2) m, spread over `footprint` (default a
        point force). Linear in the force (the small-force limit)."""
        pts = np.atleast_2d(np.asarray(points, float))
        f = np.broadcast_to(np.asarray(forces, float), (pts.shape[0], 3))
        off, w = (footprint or Footprint()).quadrature()
        R = self.response((pts[:, None, :] + off[None, :, :]).reshape(-1, 2)).reshape(pts.shape[0], len(w), -1, 3)
        return np.einsum("nqtk,q,nk->nt", R, w, f)

    def averaged(self, footprint: Footprint) -> "SurfaceMap":
        """This map with every grid value averaged over `footprint` centred there: the same
        grid's response to a force spread over the footprint (its quadrature, one spline
        call), so that a search over many presses costs point evaluations."""
        if footprint.radius == 0:
            return self
        if footprint in self._averages:
            return self._averages[footprint]
        X, Y = np.meshgrid(self.x, self.y)
        pts = np.column_stack([X.ravel(), Y.ravel()])
        off, w = footprint.quadrature()
        R = self.response((pts[:, None, :] + off[None, :, :]).reshape(-1, 2)).reshape(len(pts), len(w), -1, 3)
        avg = np.einsum("nqtk,q->tkn", R, w).reshape(len(self.taxels), 3, len(self.y), len(self.x))
        out = self._averages[footprint] = SurfaceMap(
            self.x, self.y, self.taxels, avg, self.capacitance, None,
            {**self.info, "averaged_over": {"radius_m": footprint.radius, "profile": footprint.profile}}, self.centres)
        return out

    @cached_property
    def _averages(self) -> dict:
        return {}

    def voltage(self, points, forces, footprint: Footprint | None = None) -> np.ndarray:
        """(n, ntaxels) V: open-circuit voltages, every taxel open, V = -C^-1 Q_sc."""
        return -np.linalg.solve(self.capacitance, self.charge(points, forces, footprint).T).T

    def press(self, points, force: float = 1.0, footprint: Footprint | None = None,
              circuit: str = "open") -> np.ndarray:
        """(n, ntaxels): a normal press of `force` N (> 0, into the surface) at each point:
        open-circuit voltages (V, `circuit` "open") or short-circuit charges (C, "short")."""
        f = (0.0, 0.0, -float(force))
        return self.voltage(points, f, footprint) if circuit == "open" else self.charge(points, f, footprint)

    def crosstalk(self, point, taxel: str, footprint: Footprint | None = None) -> float:
        """Taxel `taxel`'s open-circuit voltage under a normal press at `point`, as a signed
        fraction of the largest |voltage| of any taxel there (1 where it is the best taxel)."""
        v = self.press([point], 1.0, footprint)[0]
        return float(v[self.index(taxel)] / np.abs(v).max())

    def probe_voltage(self, points, force: float) -> np.ndarray:
        """(n, ntaxels) V: open-circuit voltages under the rig's probe pressed with `force` N
        on the Yeoh silicone: the linear map over the probe's footprint times the
        correction's factor there (requires `correction`)."""
        if self.correction is None:
            raise ValueError("this surface map has no probe correction; build it with probe=True")
        c = self.correction
        return self.press(points, force, c.footprint) * c.at(points, force)[:, None]

    # -- files ---------------------------------------------------------------------
    def to_file(self, path) -> Path:
        """Write the map to `path` (.npz); `from_file` reads it back exactly."""
        path = Path(path)
        arrays = {"x": self.x, "y": self.y, "charge_per_newton": self.charge_per_newton,
                  "capacitance": self.capacitance}
        meta = {"format": FORMAT, "taxels": list(self.taxels), "info": self.info}
        if self.centres is not None:
            arrays["centres"] = self.centres
        if self.correction is not None:
            c = self.correction
            arrays.update(corr_x=c.x, corr_y=c.y, corr_forces=c.forces, corr_factor=c.factor)
            meta["footprint"] = {"radius": c.footprint.radius, "profile": c.footprint.profile}
        with path.open("wb") as fh:
            np.savez_compressed(fh, meta=np.array(json.dumps(meta)), **arrays)
        return path

    @classmethod
    def from_file(cls, path) -> "SurfaceMap":
        """The map written by `to_file`; ValueError (one line) for a file that is not one."""
        try:
            with np.load(Path(path), allow_pickle=False) as z:
                meta = json.loads(str(z["meta"]))
                if meta.get("format") != FORMAT:
                    raise KeyError("format")
                corr = None
                if "corr_factor" in z:
                    corr = ProbeCorrection(z["corr_x"], z["corr_y"], z["corr_forces"], z["corr_factor"],
                                           Footprint(**meta["footprint"]))
                return cls(z["x"], z["y"], tuple(meta["taxels"]), z["charge_per_newton"], z["capacitance"],
                           corr, meta.get("info", {}), z["centres"] if "centres" in z else None)
        except (OSError, KeyError, ValueError, json.JSONDecodeError) as exc:
            raise ValueError(f"{path}: not a surface map file ({exc}); write one with SurfaceMap.to_file") from None


# -- a mesh's own load patch -------------------------------------------------------

# Dunavant's degree-4 rule on a triangle: barycentric points, weights summing to 1
_TRI_B = np.array([[0.445948490915965, 0.445948490915965, 0.108103018168070],
                   [0.445948490915965, 0.108103018168070, 0.445948490915965],
                   [0.108103018168070, 0.445948490915965, 0.445948490915965],
                   [0.091576213509771, 0.091576213509771, 0.816847572980459],
                   [0.091576213509771, 0.816847572980459, 0.091576213509771],
                   [0.816847572980459, 0.091576213509771, 0.091576213509771]])
_TRI_W = np.array([0.223381589678011] * 3 + [0.109951743655322] * 3) / 0.999999999999999


def patch_quadrature(tm) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 2) m and weights (n,) summing to 1 of a 3D tagged mesh's "load" facets (a
    uniform pressure patch as that mesh discretizes it: a disc is a polygon there), unfolded
    over its mirror planes: `m.charge(points, -F * weights[:, None] * e_z).sum(0)` is the
    map's answer to the same load a direct solve on that mesh carries."""
    f = tm.facets["load"]
    P = tm.mesh.p[:, tm.mesh.facets[:, f]]                               # (3, 3 vertices, nf)
    area = 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0], axis=0), axis=0)
    pts = np.einsum("qk,dkf->fqd", _TRI_B, P)[..., :2].reshape(-1, 2)
    w = (area[:, None] * _TRI_W[None, :]).ravel()
    images = [pts]
    for k in tm.layout.planes:
        images += [q * np.where(np.arange(2) == k, -1.0, 1.0) for q in images]
    return np.concatenate(images), np.tile(w, len(images)) / (w.sum() * len(images))


# -- building ------------------------------------------------------------------------

def map_scene(scene):
    """The scene whose linear 3D static model the map is solved on: the scene's array,
    materials and mesh, a linear silicone, no load patch (a pressure over the whole top:
    the load is not solved, only the electrodes are driven), every taxel grounded (the
    electrodes are held by the reciprocal solve), mirror planes where the array has them."""
    from taxel.scene import SceneError
    if scene.array is None or scene.model.type != "3d":
        raise SceneError("surface map: needs a 3d array scene (model.type = '3d' and an [array] table)")
    return scene.replace(**{"model.silicone": "linear", "analysis.type": "static", "load.kind": "pressure",
                            "load.pressure": 1.0, "electrodes": {"ground": "ground", "taxels": "ground"},
                            "model.fidelity": "fixed"})


def default_spacing(scene) -> float:
    """The grid step: an eighth of the narrower of the taxel and the gap, 0.1 mm at least."""
    a = scene.array
    return max(1e-4, min(a.taxel_width, a.gap if a.gap > 0 else a.taxel_width) / 8)


def build(scene, spacing: float | None = None, method: str = "auto") -> SurfaceMap:
    """The linear surface map of a 3D array scene (`map_scene`), on a grid of `spacing`
    (m; default `default_spacing`) over the whole top surface, from one factorization per
    mirror class (fem.static.surface_response). Raises SceneError for a scene that is not
    a 3D array."""
    import time
    from taxel.fem import assembly, static
    from taxel.analyses.model.problem import problem

    t0 = time.perf_counter()
    sc = map_scene(scene)
    prob = problem(sc)
    lay = prob.mesh.layout
    t1 = time.perf_counter()
    sy = assembly.assemble(prob)
    t2 = time.perf_counter()
    h = spacing or default_spacing(scene)
    hx, hy = lay.plan.half, lay.plan_half_y
    x = np.linspace(-hx, hx, int(np.ceil(2 * hx / h)) + 1)
    y = np.linspace(-hy, hy, int(np.ceil(2 * hy / h)) + 1)
    X, Y = np.meshgrid(x, y)
    z = lay.height * (1 - 1e-9)
    pts = np.stack([X.ravel(), Y.ravel(), np.full(X.size, z)])
    res = static.surface_response(sy, pts, method)
    t3 = time.perf_counter()
    taxels = [k for k in res.names if k.startswith("taxel_")]
    keep = [res.names.index(k) for k in taxels]
    R = res.R[keep].reshape(len(taxels), 3, len(y), len(x))
    centre = {t.name: (t.x, t.y) for t in lay.taxels} if not lay.planes else None
    if centre is None:
        from taxel.analyses.model.geometry import layout
        from taxel.analyses.model.problem import check
        centre = {t.name: (t.x, t.y) for t in layout(sc.replace(**{"model.symmetry": "full"}), check(sc)).taxels}
    info = {"scene": scene.name, "unknowns": int(sy.A.shape[0]), "planes": list(lay.planes),
            "taxel_width": float(scene.array.taxel_width),
            "factorizations": res.factorizations, "right_hand_sides": res.right_hand_sides,
            "residual": res.residual, "solver": res.solver, "spacing": h,
            "seconds": {"mesh": t1 - t0, "assemble": t2 - t1, "solve": t3 - t2, "total": t3 - t0}}
    return SurfaceMap(x, y, tuple(taxels), R, res.capacitance[np.ix_(keep, keep)], None, info,
                      np.array([centre[k] for k in taxels]))
