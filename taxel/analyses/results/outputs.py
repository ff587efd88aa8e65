"""The named outputs of a design: one typed table (`OUTPUTS`), each output with its SI unit,
its label on an axis or a page, what it is, and what computes it (the result it reads).

It serves every place that names outputs, each through `table(use)`:

    static        a static result's outputs (StaticResult.outputs): the open-circuit ones,
                  the readout's when the scene names one, the warm touch's when it has one;
    readout       the readout's numbers of a static solve (taxel.analyses.solves.at_readout);
    noise         a noise budget's outputs (NoiseResult.outputs);
    design_noise  the noise floor of a design from its static solve (solves.noise.design_noise);
    tolerance     a tolerance study's per-point outputs, its requirements and yield
                  (studies.yield_analysis, studies.requirements);
    metric        the optimizer's metrics: objectives, requirements, axes (optimize.metrics).

Units: SI; "ratio" is a dimensionless fraction and "dB" a level (their bounds are plain
numbers: `si_unit` is "" for a ratio, the requirement grammar's spelling). `lo`, `hi`: the
values an output can take (a requirement outside them cannot be met).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

USES = ("static", "readout", "noise", "design_noise", "tolerance", "metric")


@dataclass(frozen=True)
class Output:
    """One named output of a design."""
    name: str
    unit: str                     # SI; "ratio" (a fraction) or "dB" (a level) when dimensionless
    label: str                    # on an axis, a page, a requirement ("crosstalk ≤ 2 %")
    description: str              # what it is
    source: str                   # what computes it: the result it reads
    uses: frozenset[str]          # which of USES name it
    lo: float = 0.0
    hi: float = math.inf

    @property
    def axis(self) -> str:
        """The axis label, its unit in parentheses."""
        return f"{self.label} ({self.unit})"

    @property
    def si_unit(self) -> str:
        """The unit a requirement's bound is read in: "" for a ratio, else the unit."""
        return "" if self.unit == "ratio" else self.unit


def _o(name, unit, label, description, source, uses, **bounds) -> Output:
    bad = set(uses) - set(USES)
    assert not bad, f"output {name}: unknown uses {bad}"
    return Output(name, unit, label, description, source, frozenset(uses), **bounds)


_STATIC, _READOUT = ("static", "tolerance", "metric"), ("static", "readout", "metric")
OUTPUTS: dict[str, Output] = {o.name: o for o in (
    _o("sensitivity", "V/N", "sensitivity", "the pressed taxel's open-circuit voltage per newton",
       "StaticResult.outputs: the pressed electrode's voltage over the applied force", _STATIC),
    _o("charge_sensitivity", "C/N", "charge sensitivity", "the pressed taxel's short-circuit charge per newton",
       "StaticResult.outputs: the pressed electrode's short-circuit charge over the applied force",
       ("static", "tolerance")),
    _o("pressed_voltage", "V", "pressed voltage", "the pressed taxel's open-circuit voltage at the applied load",
       "StaticResult.outputs", ("static", "tolerance")),
    _o("tangent_sensitivity", "V/N", "small-signal sensitivity", "the slope |dV/dF| at the operating force of a press",
       "optimize.probe (the press's states)", ("metric",)),
    _o("crosstalk", "ratio", "crosstalk", "the largest neighbour's |V| over the pressed taxel's",
       "StaticResult.outputs: the electrodes' open-circuit voltages", _STATIC),
    _o("readout_sensitivity", "V/N", "sensitivity at the readout", "the readout output per newton, its passband",
       "taxel.analyses.solves.at_readout (AtReadout.sensitivity)", _READOUT),
    _o("readout_crosstalk", "ratio", "crosstalk at the readout", "the largest neighbour's readout over the pressed taxel's",
       "taxel.analyses.solves.at_readout (AtReadout.crosstalk)", _READOUT),
    _o("max_strain", "ratio", "largest silicone strain", "the largest principal strain in the silicone",
       "StaticResult.outputs: the solution's element strains", _STATIC),
    _o("force_range", "N", "force range", "the force that saturates the readout (amplifier swing or ADC range)",
       "taxel.analyses.solves.at_readout (AtReadout.force_range)", ("static", "readout")),
    _o("noise_rms", "V", "noise rms", "the readout output's noise over the band, every source",
       "NoiseResult.noise_rms (taxel.analyses.solves.noise)", ("noise",)),
    _o("total_thickness", "m", "total thickness", "silicone above + piezo + silicone below",
       "optimize.metrics.geometry (the scene alone)", ("metric",)),
    _o("footprint", "m", "footprint", "the array's width along x with its margins",
       "optimize.metrics.geometry (ArrayTable.footprint)", ("metric",)),
    _o("pitch", "m", "pitch", "taxel width plus gap", "optimize.metrics.geometry (ArrayTable.pitch)", ("metric",)),
    _o("gap", "m", "gap", "the gap between neighbouring taxels", "optimize.metrics.geometry", ("metric",)),
    _o("localization_error", "m", "localization error", "the rms over the surface of the press position's Cramer-Rao bound",
       "optimize.coverage (the influence functions)", ("metric",)),
    _o("coverage", "ratio", "coverage", "the fraction of the surface where a press is felt above the noise",
       "optimize.coverage (the design's surface map)", ("metric",), hi=1.0),
    _o("min_detectable_force", "N", "minimum detectable force", "the band's rms noise over the band sensitivity",
       "NoiseResult.min_detectable_force (a static solve's: the quasi-static budget)",
       ("static", "readout", "noise", "design_noise", "tolerance", "metric")),
    _o("snr", "dB", "SNR", "the force's rms over the minimum detectable force", "NoiseResult.snr_at",
       ("noise", "design_noise", "tolerance", "metric"), lo=-math.inf),
    _o("dynamic_range", "dB", "dynamic range", "a full-scale sine up to what clips first, over the noise",
       "NoiseResult.outputs", ("noise", "design_noise", "tolerance", "metric"), lo=-math.inf),
    _o("robust_sensitivity", "V/N", "sensitivity percentile", "the percentile of |sensitivity| over the parts",
       "optimize.robust (the design's fabrication spread)", ("metric",)),
    _o("robust_crosstalk", "ratio", "crosstalk percentile", "the (100 - percentile)th of crosstalk over the parts",
       "optimize.robust", ("metric",)),
    _o("yield", "ratio", "yield", "the fraction of parts meeting every other requirement", "optimize.robust",
       ("metric",), hi=1.0),
    _o("warm_touch_force", "N", "warm-touch false force",
       "the press held as long as a warm finger that gives its peak readout output",
       "taxel.analyses.solves.warm_touch", ("static", "metric")),
    _o("warm_touch_ratio", "ratio", "warm-touch false force / minimum detectable force",
       "the warm-touch false force over the minimum detectable force", "taxel.analyses.solves.warm_touch",
       ("static", "metric")),
)}


def table(use: str) -> dict[str, Output]:
    """The outputs one `use` (of USES) names, in the table's order."""
    if use not in USES:
        raise KeyError(f"output use {use!r}: one of {', '.join(USES)}")
    return {k: o for k, o in OUTPUTS.items() if use in o.uses}


def units_of(use: str) -> dict[str, str]:
    """name -> the unit its requirement's bound is read in ("" for a ratio) of one `use`."""
    return {k: o.si_unit for k, o in table(use).items()}
