"""The scene tables: one `[table]` of a scene as its schema class (`ModelTable`,
`MeshTable`, `ArrayTable`, `PlateTable`, `LayerTable`, `LoadTable`, `SupportsTable`,
`DynamicsTable`, `AnalysisTable`, `ReadoutTable`), the default meshes, and a user
material table's units (`[materials.NAME]`). The scene (taxel.scene) is made of them;
`taxel.scene` re-exports every name here.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AfterValidator, Field, StrictBool, StrictInt

from taxel import units
from taxel.schema import (Capacitance, Coordinate, Duration, Force, Fraction, Frequency, FrictionLaw, Length,
                          LossFactor, MeshSize, NoiseCurrent, NoiseVoltage, Pressure, Resistance, Strict,
                          Temperature, Thickness, Voltage, dimensionless)


# The unit of each key of a user material table ([materials.NAME]) that has one; a
# value is a string with its unit ("27.5 kPa") or a number in SI. The scene converts
# the strings here, so the FEM (fem.constitution.from_record) reads SI numbers only.
# Keys not listed (kind, nu, eps_r, eps_T, eps_S, Qm, tan_delta) are plain numbers.
MATERIAL_UNITS = {"E": ("Pa", "modulus"), "mu": ("Pa", "shear modulus"), "K": ("Pa", "bulk modulus"),
                  "C10": ("Pa", "Yeoh constant"), "C20": ("Pa", "Yeoh constant"), "C30": ("Pa", "Yeoh constant"),
                  "rho": ("kg/m^3", "density"), "s": ("1/Pa", "compliance"), "d": ("C/N", "piezoelectric constant"),
                  "c": ("Pa", "stiffness"), "e": ("C/m^2", "piezoelectric stress constant")}


def material_in_si(rec):
    """A user material table with every unit string converted to its SI number
    (MATERIAL_UNITS; entries of the matrices s, d, c, e one by one); numbers are SI
    and kept. Raises ValueError (one line, naming the key) for a wrong unit."""
    if not isinstance(rec, dict):
        return rec

    def si(key, v):
        unit, what = MATERIAL_UNITS[key]
        if isinstance(v, list):
            return [si(key, x) for x in v]
        if not isinstance(v, str):
            return v
        try:
            return units.to_si(v, unit, what, si_numbers=True)
        except units.UnitError as exc:
            raise ValueError(f"{key}: {exc} (in {unit})") from None
    return {k: si(k, v) if k in MATERIAL_UNITS else v for k, v in rec.items()}


UserMaterial = Annotated[dict, AfterValidator(material_in_si)]


class ModelTable(Strict):
    type: Literal["plane_strain", "plane_stress", "axisymmetric", "3d"] = "plane_strain"
    depth: Length | None = None     # out-of-plane depth of a 2D model; default: the taxel or plate width
    silicone: Literal["linear", "yeoh", "auto"] = "linear"   # constitutive model of the silicone
    tolerance: Fraction = 0.02   # "auto": largest accepted linear-model voltage error
    # solve a half (cut at x = 0) or quarter (and y = 0) of a mirror-symmetric array: see
    # symmetry_planes; "auto": the largest the scene allows, in 3d (a 2D section is cheap: full)
    symmetry: Literal["auto", "full", "half", "quarter"] = "auto"
    # "auto": the cheapest model, mesh and law whose estimated error on `outputs` is within tolerance
    fidelity: Literal["fixed", "auto"] = "fixed"
    outputs: tuple[Literal["sensitivity", "crosstalk", "charge_sensitivity"], ...] = ("sensitivity",)



# The mesh a scene without mesh.size gets, per model type of an array scene: (size,
# piezo_size; None: size / 4), measured within 0.5 % on the thesis taxel's pressed-taxel
# voltage (benchmarks/default_mesh.py, docs/benchmarks.md). 3D: estimate.CHEAP_3D's mesh.
DEFAULT_MESH = {"plane_strain": (0.5e-3, None), "plane_stress": (0.75e-3, None),
                "axisymmetric": (0.5e-3, None), "3d": (1.5e-3, 0.6e-3)}
# A 3D array scene pressed by a flat punch in contact (Scene.pressed_by_punch) without mesh.size:
# (size, piezo_size, piezo_layers), the silicone meshed free (meshing.layout.Layout.free, by
# taxel.analyses.model.geometry.punch_grading); within 1 % of the press's nested-mesh reference at a
# quarter of its unknowns (benchmarks/press_3d_mesh.py, docs/benchmarks.md).
DEFAULT_PRESS_MESH = (1.4e-3, 0.56e-3, 1)


class MeshTable(Strict):
    size: MeshSize | None = None    # element size far from the piezo; default: DEFAULT_MESH by model type
    piezo_size: MeshSize | None = None  # in-plane element size on the taxels; default: DEFAULT_MESH or size / 4
    piezo_layers: StrictInt = Field(2, ge=1, le=8)   # elements through each piezo layer (2: within 0.5 %)
    order: Literal[1, 2] = 2        # 1: P1 (+bubble in silicone: MINI), 2: P2 / P1 Taylor-Hood
    formulation: Literal["mixed", "displacement"] = "mixed"   # silicone: u-p mixed, or u only (locks)
    # 3D: the silicone extruded through its height (true), or meshed free, graded at the taxel edges
    # and the punch's rim only (false); default: free for a 3D punch press on DEFAULT_PRESS_MESH
    extruded: StrictBool | None = None
    # 3D arrays: tetrahedra meshed by gmsh, or hexahedra on a structured grid aligned with the layers
    # and taxel edges (Q2/P0 with order 2, Q1/P0 with order 1; meshing.hexmesh, benchmarks/press_hex.py)
    element: Literal["tet", "hex"] = "tet"


class ArrayTable(Strict):
    rows: StrictInt = Field(1, ge=1, le=16)
    cols: StrictInt = Field(1, ge=1, le=16)
    taxel_width: Length = "4 mm"
    piezo: str = "PSI-5H4E"
    piezo_thickness: Length = "0.127 mm"
    poling: Literal["up", "down"] = "up"
    gap: Coordinate = "3 mm"        # edge to edge
    margin: Thickness = "3 mm"      # silicone beyond the outer taxels
    silicone: str = "Ecoflex-00-30"
    silicone_above: Thickness = "1 mm"
    silicone_below: Thickness = "1 mm"


class LayerTable(Strict):
    material: str
    thickness: Length
    poling: Literal["up", "down"] = "up"


class PlateTable(Strict):
    shape: Literal["rectangle", "disk"] = "rectangle"
    width: Length | None = None     # rectangle, along x
    length: Length | None = None    # rectangle, along y (3D)
    radius: Length | None = None    # disk
    layers: list[LayerTable] = Field(min_length=1)




class LoadTable(Strict):
    kind: Literal["taxel", "between", "probe", "pressure"] = "taxel"
    force: Force | None = "1 N"
    pressure: Pressure | None = None   # kind = "pressure" only
    taxel: tuple[StrictInt, StrictInt] = (0, 0)    # [row, col] of the pressed taxel or the probe's centre
    neighbour: tuple[StrictInt, StrictInt] | None = None   # kind = "between": the other taxel
    profile: Literal["flat", "round"] = "flat"  # probe without contact, its pressure patch: uniform, or Hertzian sqrt(1-r^2/a^2)
    radius: Length | None = None       # the probe's radius (half-width in 2D)
    offset: tuple[Coordinate, Coordinate] = (0.0, 0.0)   # the probe's centre from the taxel centre
    # kind = "probe": a pressure patch under the probe; contact = true: a rigid indenter pressed to `force` (or to
    # `travel`, displacement control); radius: punch half-width/radius, or sphere radius
    contact: bool = False
    shape: Literal["flat", "sphere", "cylinder"] = "flat"
    edge_radius: Length | None = None  # flat punch's rounded edge; default radius / 20
    # sticking (the default under contact): no slip once in contact, as a dry probe on tacky
    # silicone; frictionless: the closed-form cases (Hertz, Boussinesq); a number mu >= 0: Coulomb
    # friction with that coefficient (e.g. 0.4); see the guide page "Silicone laws and contact"
    friction: FrictionLaw = None
    travel: Length | None = None       # prescribed indenter travel (instead of force)


class SupportsTable(Strict):
    bottom: Literal["bonded", "rollers", "free"] = "bonded"
    edges: Literal["free", "clamped", "simply_supported", "rollers"] = "free"


class DynamicsTable(Strict):
    """Damping. No sourced damping data exists for Ecoflex: loss factors are parameters."""
    silicone_loss: Annotated[float, dimensionless("loss factor", ge=0, lt=2)] = 0.1     # structural loss factor eta of the silicone
    piezo_loss: LossFactor | None = None        # default 1/Qm of the material
    dielectric_loss: LossFactor | None = None   # default tan(delta) of the material
    rayleigh_alpha: float = Field(0.0, ge=0)          # 1/s, C = alpha M + beta K
    rayleigh_beta: float = Field(0.0, ge=0)           # s
    reference_frequency: Frequency = "100 Hz"         # lumped models: eta -> viscous eta / (2 pi f_ref) (the FEM: fem.constitution)


class AnalysisTable(Strict):
    type: Literal["static", "frequency", "transient"] = "static"
    f_min: Frequency = "1 Hz"
    f_max: Frequency = "1000 Hz"
    points: StrictInt = Field(200, ge=2, le=100000)
    spacing: Literal["log", "linear"] = "log"
    method: Literal["reduced", "direct"] = "reduced"
    tolerance: Fraction = 1e-3        # reduced sweep: accepted relative error
    input: Literal["step", "impulse", "chirp", "csv"] = "step"
    duration: Duration = "1 s"
    dt: Duration = "0.5 ms"
    rise: Duration = "1 ms"           # step: rise time (a smooth ramp)
    width: Duration = "10 ms"         # impulse: half-sine width
    f0: float = Field(0.0, ge=0)      # chirp start frequency, Hz
    f1: float = Field(100.0, gt=0)    # chirp end frequency, Hz (thesis: 0 to 100 Hz over 8 s)
    file: str | None = None           # csv: columns time (s), force (N)


class ReadoutTable(Strict):
    circuit: Literal["open", "resistor", "charge_amplifier"] = "open"
    R: Resistance = "500 Mohm"        # resistor: the input resistance (thesis tau 1.7-3.1 s at ~4 nF)
    C_f: Capacitance = "820 pF"       # charge amplifier, TI SLOA033A
    R_f: Resistance = "10 Mohm"
    R_i: Resistance = "10 kohm"       # input resistor (assumed; sets the upper cutoff)
    C_c: Capacitance = "100 pF"       # cable (assumed: about 1 m)
    notch: bool = False               # the thesis's 50 Hz second-order Butterworth band-stop
    notch_frequency: Frequency = "50 Hz"
    notch_bandwidth: Frequency = "10 Hz"
    # noise of the chain (taxel.analyses.solves.noise; fem.readout has the physics). The thesis does not
    # name its op-amp: the defaults are a TL072-class JFET op-amp (TI datasheet SLOS080: 18 nV/sqrt(Hz)
    # at 1 kHz, 0.01 pA/sqrt(Hz), +-12 V linear swing on +-15 V supplies), white (no 1/f corner).
    e_n: NoiseVoltage = "18 nV/Hz**0.5"   # op-amp (or buffer) voltage noise density
    i_n: NoiseCurrent = "10 fA/Hz**0.5"   # op-amp current noise density
    e_n_corner: Frequency | None = None   # 1/f corner of e_n (None: white)
    swing: Voltage = "12 V"               # the amplifier's largest linear output (+-)
    temperature: Temperature = "296.15 K" # of the resistors and the piezo's dielectric loss
    hum: tuple[Voltage, ...] = ()          # mains pickup at the output before the notch: peak amplitudes of
    mains_frequency: Frequency = "50 Hz"  # the mains frequency and its odd harmonics (1, 3, 5...)
