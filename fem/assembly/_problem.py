"""What the finite-element model solves, in the FEM's own terms.

A Problem is a tagged mesh (regions, facet sets, electrodes), the kinematics of
its model type, the discretization, the material of each region, the load on the
"load" facets, the supports and the state of each electrode. taxel.analyses
builds it once from a scene; the FEM never sees the scene. Everything is SI.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal, Mapping, Union

from taxel.fem.constitution import Kinematics
from taxel.fem.constitution import Piezo, Solid
from taxel.meshing.build import TaggedMesh

@dataclass(frozen=True)
class Indenter:
    """A rigid indenter above the top surface (SI units)."""

    shape: Literal["flat", "sphere", "cylinder"]
    radius: float                  # flat: half-width (2D) or radius; sphere/cylinder: its radius
    edge_radius: float = 0.0       # flat punch: rounded edge (0 <= edge_radius <= radius)
    centre: tuple[float, float] = (0.0, 0.0)   # lateral centre (x, y); 2D uses x only
    travel: float | None = None    # m, prescribed travel (displacement control); None: force control
    force: float | None = None     # N, requested force (force control)
    # sticking: no slip once in contact; a number mu >= 0: Coulomb friction (fem.contact)
    friction: Union[Literal["frictionless", "sticking"], float] = "frictionless"

    def __post_init__(self):
        if self.shape not in ("flat", "sphere", "cylinder"):
            raise ValueError(f"indenter shape {self.shape!r}: use flat, sphere or cylinder")
        if self.radius <= 0:
            raise ValueError("indenter radius must be positive")
        if self.shape == "flat" and not 0 <= self.edge_radius <= self.radius:
            raise ValueError("indenter edge_radius must be between 0 and the punch radius")
        if self.friction not in ("frictionless", "sticking") and not (
                isinstance(self.friction, (int, float)) and not isinstance(self.friction, bool)
                and self.friction >= 0 and self.friction < float("inf")):
            raise ValueError(f"indenter friction {self.friction!r}: use frictionless, sticking or a "
                             "Coulomb coefficient >= 0")
        if (self.travel is None) == (self.force is None):
            raise ValueError("an Indenter takes exactly one of travel (m) or force (N)")

    @property
    def coulomb(self) -> float | None:
        """The Coulomb coefficient mu of a numeric friction (None: frictionless or sticking)."""
        return None if isinstance(self.friction, str) else float(self.friction)

    @property
    def rho(self) -> float:
        return self.edge_radius if self.shape == "flat" else self.radius

    @property
    def core(self) -> float:
        return self.radius - self.rho


# an electrode is open (floating, zero net charge), grounded, or held at a voltage (float, V)
ElectrodeState = Union[Literal["open", "ground"], float]


@dataclass(frozen=True)
class Discretization:
    order: Literal[1, 2] = 2       # 2: P2 displacement / P1 pressure (Taylor-Hood); 1: MINI / P1
    mixed: bool = True             # solids: mixed u-p (locking-free), or displacement only
    hex_pressure: Literal["p1", "p0"] = "p1"   # hexahedra, order 2: Q2 / P1-discontinuous, or Q2 / P0 (to compare)


@dataclass(frozen=True)
class PatchLoad:
    """A downward load on the "load" facets (the whole top when the layout has no
    load patch): a total force in N, or a pressure in Pa; flat, or Hertzian
    p(r) ~ sqrt(1 - r^2 / a^2) over the patch ("round")."""

    force: float | None = None
    pressure: float | None = None
    profile: Literal["flat", "round"] = "flat"

    def __post_init__(self):
        if (self.force is None) == (self.pressure is None):
            raise ValueError("a PatchLoad takes exactly one of force (N) or pressure (Pa)")


@dataclass(frozen=True)
class Supports:
    bottom: Literal["bonded", "rollers", "free"] = "bonded"
    edges: Literal["free", "clamped", "simply_supported", "rollers"] = "free"


@dataclass(frozen=True)
class Damping:
    """Loss factors and Rayleigh damping (fem.dynamics)."""

    silicone_loss: float = 0.1              # structural loss factor of the solids
    piezo_loss: float | None = None         # default 1/Qm of the material
    dielectric_loss: float | None = None    # default tan(delta) of the material
    rayleigh_alpha: float = 0.0             # 1/s, C = alpha M + beta K
    rayleigh_beta: float = 0.0              # s
    reference_frequency: float = 100.0      # Hz: the lumped models' loss factors as viscous damping
    loss_band: tuple[float, float] = (1.0, 2000.0)   # Hz: the FEM's causal law holds the loss factors here (fem.constitution)


@dataclass(frozen=True)
class Problem:
    mesh: TaggedMesh
    kinematics: Kinematics
    materials: Mapping[str, Piezo | Solid]            # every region's material, by name
    load: PatchLoad
    supports: Supports = Supports()
    electrodes: Mapping[str, ElectrodeState] = field(default_factory=dict)   # every electrode's state
    discretization: Discretization = Discretization()
    hyperelastic: bool = False        # solids with Yeoh data solved as Yeoh (fem.hyperelastic)
    damping: Damping = Damping()
    indenter: Indenter | None = None  # pressed by a rigid indenter (fem.contact, fem.contact); load unused
