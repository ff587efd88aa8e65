"""The MuJoCo adapter: the contacts on a skin body, each step, into the skin runtime.

    import mujoco
    from taxel.skin.model import SkinModel
    from taxel.skin.mujoco import MujocoSkin
    m = mujoco.MjModel.from_xml_path(fingertip_xml()); d = mujoco.MjData(m)
    skin = MujocoSkin(m, SkinModel.load("skin.npz"), body="pad", noise=True, seed=0)
    while ...:
        mujoco.mj_step(m, d)
        volts = skin.step(d)            # (rows, cols) V

The skin body's frame is the skin's frame: origin at taxel (0, 0)'s centre on the
surface, x along the columns, y along the rows, z out of the surface (the example's
pad is so). Each step reads every active contact with a geom of that body
(`d.contact`): its force (normal and both friction components in the contact frame:
`d.efc_force` for elliptic cones, else mujoco.mj_contactForce) turned into the force on the skin in the skin frame
(a press has f_z < 0), and its point.

A contact as a patch (`patches`). MuJoCo resolves a body on the pad into a few contact
points (the gallery's flat probe: 4 points on its rim, 2 mm off centre), which are not
where the pressure is. So the contacts are grouped by the other geom, and each group
becomes the pressure over that geom's footprint on the surface, carrying the group's
total force (normal and tangential), centred under the geom's centre (the contact
points' own centre of pressure is not reliable: the flat probe's 4 rim points put it
0.2 mm off a centred press); a tilted geom's off-centre pressure is outside the model:

- a cylinder (a flat probe, axis along the normal): a uniform disc of its radius (the
  FEM's flat probe load, fem.assembly.PatchLoad "flat": the same model, so the skin's
  and the 3D FEM's presses by that probe are the same load);
- a sphere of radius R: Hertz's disc, p ~ sqrt(1 - r^2 / a^2),
  a = (3 F R / (4 E*))^(1/3), E* the silicone's plane-strain modulus (`modulus`, Pa),
  at most R;
- a capsule lying on the surface (an edge): a line load along its axis, uniform over
  its segment's length, across it Hertz's strip of half-width b = sqrt(4 F R / (pi l E*));
- any other geom: its contact points as they are (point forces).

The tangential force is spread like the normal pressure (a full-slip Coulomb patch, or
a stuck one under a uniform shear traction: the model's assumption). The patch's
quadrature points and forces go to the runtime, which integrates the influence W over
them. mujoco is imported here only: the runtime (taxel.skin.runtime) never needs it.
"""


from __future__ import annotations

from importlib import resources

import numpy as np

from taxel.skin.model import SkinModel
from taxel.skin.runtime import SkinRuntime

_RINGS, _SPOKES, _ALONG = 3, 8, 12


def fingertip_xml() -> str:
    """The path of the example MJCF model: a fingertip pad carrying the thesis 3 x 3 array
    (pitch 7 mm, 4 mm taxels, 3 mm margin) and a probe, a sphere and an edge to press it."""
    return str(resources.files("taxel.skin") / "fingertip.xml")


def disc(radius: float, round_: bool) -> tuple[np.ndarray, np.ndarray]:
    """Offsets (n, 2) m and weights (n,) summing to 1 over a disc: uniform or Hertzian
    (Gauss-Legendre rings in r dr, equal spokes)."""
    t, w = np.polynomial.legendre.leggauss(_RINGS)
    r = 0.5 * (t + 1) * radius
    wr = 0.5 * w * r * (np.sqrt(np.clip(1 - (r / radius) ** 2, 0, None)) if round_ else 1.0)
    a = (np.arange(_SPOKES) + 0.5) * 2 * np.pi / _SPOKES
    off = np.stack([np.outer(r, np.cos(a)).ravel(), np.outer(r, np.sin(a)).ravel()], axis=1)
    wts = np.repeat(wr, _SPOKES)
    return off, wts / wts.sum()


def strip(axis: np.ndarray, length: float, half: float) -> tuple[np.ndarray, np.ndarray]:
    """Offsets and weights of a line load: uniform along `axis` (unit, in plane) over
    `length`, Hertzian across it, p ~ sqrt(1 - t^2 / half^2) (Gauss-Legendre, 4 points)."""
    s = (np.arange(_ALONG) + 0.5) / _ALONG * length - length / 2
    t, w = np.polynomial.legendre.leggauss(4)
    normal = np.array([-axis[1], axis[0]])
    off = s[:, None, None] * axis + (half * t)[None, :, None] * normal
    wts = np.tile(w * np.sqrt(1 - t ** 2), _ALONG)
    return off.reshape(-1, 2), wts / wts.sum()


_UNIT = {False: disc(1.0, False), True: disc(1.0, True)}      # a disc of unit radius: uniform, Hertzian


class MujocoSkin:
    """A SkinRuntime fed by a MuJoCo model's contacts on one body (module docstring)."""

    def __init__(self, model, skin: SkinModel, body: str, noise: bool = False, seed: int | None = None,
                 modulus: float = 92e3, patches: bool = True):
        import mujoco
        self._mj = mujoco
        self.model = model
        self.body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
        if self.body < 0:
            raise ValueError(f"body '{body}': no such body in the MuJoCo model; name the body that carries the skin")
        if not modulus > 0:
            raise ValueError(f"modulus = {modulus}: the silicone's plane-strain modulus in Pa, > 0 (e.g. 92e3)")
        self.runtime = SkinRuntime(skin, noise, seed, dt=float(model.opt.timestep))
        self.modulus, self.use_patches = float(modulus), patches
        self._f = np.zeros(6)

    def contacts(self, data) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(points (m, 2) m, forces (m, 3) N on the skin in the skin frame, the other geom's id (m,))."""
        mj, m = self._mj, self.model
        c = data.contact                                      # the struct-of-arrays view: every contact at once
        b1, b2 = m.geom_bodyid[c.geom1], m.geom_bodyid[c.geom2]
        idx = np.flatnonzero((c.exclude == 0) & ((b1 == self.body) | (b2 == self.body)))
        if not len(idx):
            return np.zeros((0, 2)), np.zeros((0, 3)), np.zeros(0, int)
        adr, dim = c.efc_address[idx], c.dim[idx]
        if m.opt.cone == mj.mjtCone.mjCONE_ELLIPTIC and np.all(adr >= 0) and np.all(dim >= 3):
            f = data.efc_force[adr[:, None] + np.arange(3)]     # elliptic: the contact-frame force itself
        else:
            f = np.empty((len(idx), 3))
            for k, i in enumerate(idx):
                mj.mj_contactForce(m, data, int(i), self._f)
                f[k] = self._f[:3]
        keep = f[:, 0] > 0
        idx, f = idx[keep], f[keep]
        on_geom2 = np.einsum("cji,cj->ci", c.frame[idx].reshape(-1, 3, 3), f)    # world: geom1's force on geom2
        sign = np.where(b2[idx] == self.body, 1.0, -1.0)[:, None]
        R, p0 = data.xmat[self.body].reshape(3, 3), data.xpos[self.body]
        geoms = np.where(b1[idx] == self.body, c.geom2[idx], c.geom1[idx])
        return (c.pos[idx] - p0) @ R[:, :2], (sign * on_geom2) @ R, geoms

    def patches(self, data) -> tuple[np.ndarray, np.ndarray]:
        """(points (n, 2), forces (n, 3)): each touching geom's contacts as its patch (module docstring)."""
        pts, fs, geoms = self.contacts(data)
        if not self.use_patches or not len(fs):
            return pts, fs
        m, mj = self.model, self._mj
        R = data.xmat[self.body].reshape(3, 3)
        out_p, out_f = [], []
        for g in np.unique(geoms):
            sel = geoms == g
            F = fs[sel].sum(axis=0)
            N = max(-F[2], 0.0)
            kind, size = m.geom_type[g], m.geom_size[g]
            centre = (R.T @ (data.geom_xpos[g] - data.xpos[self.body]))[:2]     # the geom's centre over the surface
            if kind == mj.mjtGeom.mjGEOM_CYLINDER:
                off, w = _UNIT[False]
                off = off * float(size[0])
            elif kind == mj.mjtGeom.mjGEOM_SPHERE and N > 0:
                a = min(float(size[0]), (3 * N * float(size[0]) / (4 * self.modulus)) ** (1 / 3))
                off, w = _UNIT[True]
                off = off * a
            elif kind == mj.mjtGeom.mjGEOM_CAPSULE and N > 0:
                axis = (R.T @ data.geom_xmat[g].reshape(3, 3)[:, 2])[:2]
                length = 2 * float(size[1])
                axis = axis / max(np.linalg.norm(axis), 1e-12)
                half = min(float(size[0]), np.sqrt(4 * N * float(size[0]) / (np.pi * length * self.modulus)))
                off, w = strip(axis, length, half)
            else:
                out_p.append(pts[sel])
                out_f.append(fs[sel])
                continue
            out_p.append(centre + off)
            out_f.append(w[:, None] * F)
        return np.concatenate(out_p), np.concatenate(out_f)

    def step(self, data) -> np.ndarray:
        """The taxels' voltages (rows, cols) V after this simulator step."""
        return self.runtime.step(*self.patches(data))
