"""The scene tables: one `[table]` of a scene as its schema class (`ModelTable`,
`MeshTable`, `ArrayTable`, `PlateTable`, `LayerTable`, `LoadTable`, `SupportsTable`,
`DynamicsTable`, `AnalysisTable`, `ReadoutTable` and its `AdcTable`, `WarmTouchTable`), the default meshes, and a user
material table's units (`[materials.NAME]`). The scene (taxel.scene) is made of them;
`taxel.scene` re-exports every name here.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AfterValidator, Field, StrictBool, StrictInt, model_validator

from taxel import units
from taxel.schema import (Capacitance, Coordinate, Duration, Force, Fraction, Frequency, FrictionLaw, HeatTransfer, Length,
                          LossFactor, MeshSize, NoiseCurrent, NoiseVoltage, Pressure, Resistance, SignedVoltage,
                          Strict, Temperature, Thickness, Voltage, dimensionless)


# The unit of each key of a user material table ([materials.NAME]) that has one; a
# value is a string with its unit ("27.5 kPa") or a number in SI. The scene converts
# the strings here, so the FEM (fem.constitution.from_record) reads SI numbers only.
# Keys not listed (kind, nu, eps_r, eps_T, eps_S, Qm, tan_delta) are plain numbers.
MATERIAL_UNITS = {"E": ("Pa", "modulus"), "mu": ("Pa", "shear modulus"), "K": ("Pa", "bulk modulus"),
                  "C10": ("Pa", "Yeoh constant"), "C20": ("Pa", "Yeoh constant"), "C30": ("Pa", "Yeoh constant"),
                  "rho": ("kg/m^3", "density"), "s": ("1/Pa", "compliance"), "d": ("C/N", "piezoelectric constant"),
                  "c": ("Pa", "stiffness"), "e": ("C/m^2", "piezoelectric stress constant"),
                  "conductivity": ("W/(m*K)", "thermal conductivity"), "specific_heat": ("J/(kg*K)", "specific heat"),
                  "pyro": ("C/(m^2*K)", "pyroelectric coefficient"),
                  "permittivity_tc": ("1/K", "temperature coefficient"), "d_tc": ("1/K", "temperature coefficient")}


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
    """The model type: a 2D section (plane strain or plane stress), a disk (axisymmetric) or 3D."""
    depth: Length | None = None
    """Out-of-plane depth of a 2D model; default: the taxel or plate width."""
    silicone: Literal["linear", "yeoh", "auto"] = "linear"
    """The silicone law: linear, Yeoh, or auto (linear while its estimated error is within tolerance)."""
    tolerance: Fraction = 0.02
    """Auto models: the largest accepted estimated relative error of the outputs."""
    symmetry: Literal["auto", "full", "half", "quarter"] = "auto"
    """Solve a half (cut at x = 0) or quarter (and y = 0) of a mirror-symmetric array; auto: the largest the scene allows in 3D."""
    fidelity: Literal["fixed", "auto"] = "fixed"
    """Auto: the cheapest model, mesh and silicone law whose estimated error on `outputs` is within tolerance."""
    outputs: tuple[Literal["sensitivity", "crosstalk", "charge_sensitivity"], ...] = ("sensitivity",)
    """The outputs the model choice (fidelity = "auto") judges the error on."""


# The mesh a scene without mesh.size gets, per model type of an array scene: (size,
# piezo_size; None: size / 4), measured within 0.5 % on the thesis taxel's pressed-taxel
# voltage (benchmarks/default_mesh.py, docs/benchmarks.md). 3D: the error estimate's cheapest 3D mesh (taxel.analyses.accuracy.CHEAP_3D).
DEFAULT_MESH = {"plane_strain": (0.5e-3, None), "plane_stress": (0.75e-3, None),
                "axisymmetric": (0.5e-3, None), "3d": (1.5e-3, 0.6e-3)}
# A 3D array scene pressed by a flat punch in contact (Scene.pressed_by_punch) without mesh.size:
# (size, piezo_size, piezo_layers), the silicone meshed free (meshing.layout.Layout.free, by
# taxel.analyses.model.geometry.punch_grading); within 1 % of the press's nested-mesh reference at a
# quarter of its unknowns (benchmarks/press_3d_mesh.py, docs/benchmarks.md).
DEFAULT_PRESS_MESH = (1.4e-3, 0.56e-3, 1)


class MeshTable(Strict):
    size: MeshSize | None = None
    """Element size far from the piezo; default: the model type's default mesh (taxel.scene.DEFAULT_MESH)."""
    piezo_size: MeshSize | None = None
    """In-plane element size on the taxels; default: the default mesh's, or size / 4."""
    piezo_layers: StrictInt = Field(2, ge=1, le=8)
    """Elements through each piezo layer (2: within 0.5 % on the thesis taxel)."""
    order: Literal[1, 2] = 2
    """Element order: 1, P1 (+bubble in the silicone: MINI); 2, P2 / P1 Taylor-Hood."""
    formulation: Literal["mixed", "displacement"] = "mixed"
    """The silicone's formulation: u-p mixed, or displacement only (locks when nearly incompressible)."""
    extruded: StrictBool | None = None
    """3D: the silicone extruded through its height (true) or meshed free, graded at the taxel edges and the punch's rim (false); default: free for a 3D punch press."""
    element: Literal["tet", "hex"] = "tet"
    """3D arrays: tetrahedra meshed by gmsh, or hexahedra on a structured grid aligned with the layers and taxel edges."""


class ArrayTable(Strict):
    rows: StrictInt = Field(1, ge=1, le=16)
    """Taxel rows (along y)."""
    cols: StrictInt = Field(1, ge=1, le=16)
    """Taxel columns (along x)."""
    taxel_width: Length = "4 mm"
    """Width of a square piezo taxel."""
    piezo: str = "PSI-5H4E"
    """The taxels' piezo material: a built-in name or a [materials] table."""
    piezo_thickness: Length = "0.127 mm"
    """Thickness of the piezo taxels."""
    poling: Literal["up", "down"] = "up"
    """Poling direction of the piezo (along z)."""
    gap: Coordinate = "3 mm"
    """Gap between neighbouring taxels, edge to edge."""
    margin: Thickness = "3 mm"
    """Silicone beyond the outer taxels."""
    silicone: str = "Ecoflex-00-30"
    """The silicone: a built-in name or a [materials] table."""
    silicone_above: Thickness = "1 mm"
    """Silicone above the taxels (between them and the pressed surface)."""
    silicone_below: Thickness = "1 mm"
    """Silicone below the taxels."""

    @property
    def pitch(self) -> float:
        """The centre-to-centre distance of neighbouring taxels, m: taxel width plus gap."""
        return self.taxel_width + self.gap

    @property
    def footprint(self) -> float:
        """The array's width along x with its margins, m: cols taxels, cols - 1 gaps, two margins."""
        return self.cols * self.taxel_width + (self.cols - 1) * self.gap + 2 * self.margin


class LayerTable(Strict):
    material: str
    """The layer's material: a built-in name or a [materials] table."""
    thickness: Length
    """The layer's thickness."""
    poling: Literal["up", "down"] = "up"
    """Poling direction of a piezo layer (along z)."""


class PlateTable(Strict):
    shape: Literal["rectangle", "disk"] = "rectangle"
    """The plate's outline."""
    width: Length | None = None
    """A rectangle's width, along x."""
    length: Length | None = None
    """A rectangle's length, along y (3D)."""
    radius: Length | None = None
    """A disk's radius."""
    layers: list[LayerTable] = Field(min_length=1)
    """The stack of full-width layers, bottom first."""


class LoadTable(Strict):
    kind: Literal["taxel", "between", "probe", "pressure"] = "taxel"
    """What presses: a pressure patch on a taxel, between two taxels, a probe, or a pressure on the whole top."""
    force: Force | None = "1 N"
    """The total force of the load."""
    pressure: Pressure | None = None
    """The pressure of kind = "pressure" (instead of a force)."""
    taxel: tuple[StrictInt, StrictInt] = (0, 0)
    """[row, col] of the pressed taxel, or of the taxel under the probe's centre."""
    neighbour: tuple[StrictInt, StrictInt] | None = None
    """kind = "between": the other taxel [row, col]."""
    profile: Literal["flat", "round"] = "flat"
    """A probe's pressure patch without contact: uniform (flat), or Hertzian sqrt(1 - r^2/a^2) (round)."""
    radius: Length | None = None
    """The probe's radius (its half-width in 2D): a punch's or a sphere's."""
    offset: tuple[Coordinate, Coordinate] = (0.0, 0.0)
    """The probe's centre from the taxel's centre, [x, y]."""
    contact: bool = False
    """A probe as a rigid indenter pressed to `force` or `travel` (true), or as its pressure patch (false)."""
    shape: Literal["flat", "sphere", "cylinder"] = "flat"
    """The probe's shape: a flat punch (rounded edge), a sphere or a cylinder."""
    edge_radius: Length | None = None
    """A flat punch's edge radius; default: radius / 20."""
    friction: FrictionLaw = None
    """A press's friction: "sticking" (the default under contact), "frictionless", or a Coulomb coefficient such as 0.4."""
    travel: Length | None = None
    """The indenter's prescribed travel (displacement control, instead of a force)."""


class SupportsTable(Strict):
    bottom: Literal["bonded", "rollers", "free"] = "bonded"
    """The bottom face: bonded (fixed), on rollers (free in plane), or free."""
    edges: Literal["free", "clamped", "simply_supported", "rollers"] = "free"
    """The side faces: free, clamped, simply supported or on rollers."""


class DynamicsTable(Strict):
    """Damping. No sourced damping data exists for Ecoflex: loss factors are parameters."""
    silicone_loss: Annotated[float, dimensionless("loss factor", ge=0, lt=2)] = 0.1
    """The silicone's structural loss factor eta (no sourced value for Ecoflex: a parameter)."""
    piezo_loss: LossFactor | None = None
    """The piezo's structural loss factor; default: 1/Qm of the material."""
    dielectric_loss: LossFactor | None = None
    """The piezo's dielectric loss tangent; default: tan(delta) of the material."""
    rayleigh_alpha: float = Field(0.0, ge=0)
    """Rayleigh damping's mass factor alpha (1/s) in C = alpha M + beta K."""
    rayleigh_beta: float = Field(0.0, ge=0)
    """Rayleigh damping's stiffness factor beta (s) in C = alpha M + beta K."""
    reference_frequency: Frequency = "100 Hz"
    """Lumped models: the frequency a loss factor becomes viscous damping at, b = eta k / (2 pi f_ref)."""


class AnalysisTable(Strict):
    type: Literal["static", "frequency", "transient"] = "static"
    """The analysis: static, a frequency sweep, or a transient."""
    f_min: Frequency = "1 Hz"
    """A sweep's lowest frequency."""
    f_max: Frequency = "1000 Hz"
    """A sweep's highest frequency."""
    points: StrictInt = Field(200, ge=2, le=100000)
    """A sweep's number of frequencies."""
    spacing: Literal["log", "linear"] = "log"
    """A sweep's frequency spacing."""
    method: Literal["reduced", "direct"] = "reduced"
    """A sweep on a reduced-order model (Krylov projection, its error measured) or a direct solve per frequency."""
    tolerance: Fraction = 1e-3
    """A reduced sweep's accepted relative error."""
    input: Literal["step", "impulse", "chirp", "csv"] = "step"
    """A transient's force history: a step, an impulse, a chirp, or a CSV file."""
    duration: Duration = "1 s"
    """A transient's duration."""
    dt: Duration = "0.5 ms"
    """A transient's time step."""
    rise: Duration = "1 ms"
    """A step's rise time (a smooth ramp)."""
    width: Duration = "10 ms"
    """An impulse's half-sine width."""
    f0: float = Field(0.0, ge=0)
    """A chirp's start frequency, Hz."""
    f1: float = Field(100.0, gt=0)
    """A chirp's end frequency, Hz (the thesis: 0 to 100 Hz over 8 s)."""
    file: str | None = None
    """A csv input's file: columns time (s) and force (N)."""


class AdcTable(Strict):
    """The ADC that digitizes the readout's output ([readout.adc]; fem.readout.Converter).
    Its quantisation is noise of LSB^2 / 12 (LSB = span / 2^enob) spread evenly to rate / 2;
    its input range clips the output (the readout's output shifted to `offset`), the smaller
    of it and the amplifier's swing sets the saturation. A rig's [adc] replaces it."""
    bits: StrictInt = Field(ge=1, le=32)
    """The ADC's resolution in bits."""
    range: tuple[SignedVoltage, SignedVoltage]
    """The ADC's input range [low, high], e.g. ["0 V", "3.3 V"] for a 3.3 V reference."""
    offset: SignedVoltage | None = None
    """The ADC input of a zero readout output (its bias); default: the range's middle."""
    enob: Annotated[float, dimensionless("effective number of bits", gt=0, le=32)] | None = None
    """Effective number of bits: its noise as the quantisation of that many bits; default: bits (an ideal ADC)."""
    rate: Frequency | None = None
    """Sampling rate; default: twice the noise band's top (the band holds all of LSB^2 / 12)."""

    @model_validator(mode="after")
    def _span(self):
        lo, hi = self.range
        if not hi > lo:
            raise ValueError(f"readout.adc.range must go from low to high, got [{lo:g}, {hi:g}] V")
        if self.offset is not None and not lo <= self.offset <= hi:
            raise ValueError(f"readout.adc.offset {self.offset:g} V is outside the range [{lo:g}, {hi:g}] V")
        if self.enob is not None and self.enob > self.bits:
            raise ValueError(f"readout.adc.enob {self.enob:g} is above its bits ({self.bits}); give enob <= bits")
        return self


# The default noise band (Hz): the vibrations human mechanoreceptors sense, up to 300 Hz (the
# thesis, section 1.2, its reference [12]; Pacinian corpuscles are the fastest), from 1 Hz, a slow
# press (a piezo taxel reads no static force). `taxel solve`, `taxel optimize` ([resolution]) and the
# tolerance study's noise outputs all take it from here (ReadoutTable.band).
NOISE_BAND = ("1 Hz", "300 Hz")


class ReadoutTable(Strict):
    """The readout chain behind each taxel (fem.readout): its circuit, notch, noise sources, ADC and band."""
    circuit: Literal["open", "resistor", "charge_amplifier"] = "open"
    """The readout circuit: open (the open-circuit voltage), a resistor, or a charge amplifier."""
    R: Resistance = "500 Mohm"
    """A resistor readout's input resistance (the thesis: tau 1.7-3.1 s at about 4 nF)."""
    C_f: Capacitance = "820 pF"
    """A charge amplifier's feedback capacitance (TI SLOA033A)."""
    R_f: Resistance = "10 Mohm"
    """A charge amplifier's feedback resistance."""
    R_i: Resistance = "10 kohm"
    """A charge amplifier's input resistor (assumed; it sets the upper cutoff)."""
    C_c: Capacitance = "100 pF"
    """The cable's capacitance (assumed: about 1 m)."""
    notch: bool = False
    """The thesis's second-order Butterworth band-stop at the mains frequency."""
    notch_frequency: Frequency = "50 Hz"
    """The notch's centre frequency."""
    notch_bandwidth: Frequency = "10 Hz"
    """The notch's bandwidth."""
    # noise of the chain (taxel.analyses.solves.noise; fem.readout has the physics). The thesis does not
    # name its op-amp: the defaults are a TL072-class JFET op-amp (TI datasheet SLOS080: 18 nV/sqrt(Hz)
    # at 1 kHz, 0.01 pA/sqrt(Hz), +-12 V linear swing on +-15 V supplies), white (no 1/f corner).
    e_n: NoiseVoltage = "18 nV/Hz**0.5"
    """The op-amp's (or buffer's) voltage noise density (default: a TL072-class JFET op-amp)."""
    i_n: NoiseCurrent = "10 fA/Hz**0.5"
    """The op-amp's current noise density."""
    e_n_corner: Frequency | None = None
    """The 1/f corner of e_n (none: white)."""
    swing: Voltage = "12 V"
    """The amplifier's largest linear output (+-)."""
    temperature: Temperature = "296.15 K"
    """Temperature of the resistors and of the piezo's dielectric loss (their thermal noise)."""
    hum: tuple[Voltage, ...] = ()
    """Mains pickup at the output before the notch: peak amplitudes of the mains frequency and its odd harmonics."""
    mains_frequency: Frequency = "50 Hz"
    """The mains frequency (hum at it and its odd harmonics 3, 5, ...)."""
    band: tuple[Frequency, Frequency] = NOISE_BAND
    """The band of the noise, the minimum detectable force and the readout's V/N (default: what human mechanoreceptors sense)."""
    adc: AdcTable | None = None
    """The ADC behind the readout ([readout.adc]); none: no quantisation, the amplifier's swing clips."""

    @model_validator(mode="after")
    def _band(self):
        if not self.band[0] < self.band[1]:
            raise ValueError(f"readout.band must go from low to high, got [{self.band[0]:g}, {self.band[1]:g}] Hz")
        return self


class WarmTouchTable(Strict):
    """A warm finger on the skin (taxel.analyses.solves.warm_touch): a body at `finger` touches the
    scene's load footprint through `contact_conductance` for `duration`, then lifts; the rest
    of the surface (and the footprint after the lift) exchanges heat with air at `ambient`
    through `convection`; the skin starts at `ambient`. The warm press adds the scene's load
    force over the same `duration`. Defaults: a fingertip at 34 C (skin about 30-35 C) on a
    skin at 23 C (the readout's 296.15 K); the finger's conductance (assumed: a fingertip's
    effusivity over sqrt(pi t) at t ~ 1 s is 600-1000 W/(m^2 K)); still air, 10 W/(m^2 K)."""
    finger: Temperature = "307.15 K"
    """The finger's temperature."""
    ambient: Temperature = "296.15 K"
    """The air's and the skin's starting temperature."""
    contact_conductance: HeatTransfer = "1000 W/(m^2*K)"
    """The finger-skin contact conductance."""
    convection: HeatTransfer = "10 W/(m^2*K)"
    """The heat transfer coefficient to the air."""
    duration: Duration = "1 s"
    """How long the finger stays."""
    time: Duration = "3 s"
    """The simulated time (at least the duration)."""
    dt: Duration = "10 ms"
    """The time step of the heat conduction and the readout."""
