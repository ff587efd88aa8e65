"""The rig file: one validated TOML description of a bench (units as strings).

    name = "thesis-bench"
    [port]
    url = "/dev/ttyACM0"            # a device path or a pyserial URL: socket://127.0.0.1:PORT, loop://, rfc2217://
    baud = 921600
    protocol = "taxel-cobs"         # taxel-cobs | taxel-ascii
    [sampling]
    rate = "2 kHz"                  # nominal
    [adc]
    bits = 16
    range = ["-10 V", "10 V"]       # the input span the codes cover
    offset = "0 V"                  # input voltage at code 0 (besides the range midpoint; default 0)
    [[channels]]
    index = 0                       # position in the frame
    name = "taxel_0_0"              # taxel_ROW_COL or force
    gain = 1.0                      # taxel channels: V at the ADC per V out of the conditioning
    [[channels]]
    index = 9
    name = "force"
    sensitivity = "0.5 V/N"         # the load cell (with its amplifier), V at the ADC per N
    [[channels]]                    # optional: the actuator's travel (an LVDT or encoder), V at the ADC per m
    index = 10
    name = "travel"
    sensitivity = "1 V/mm"
    [conditioning]                  # in front of every taxel; [conditioning.taxel_R_C] overrides one
    circuit = "charge_amplifier"    # open | resistor (R) | charge_amplifier (C_f, R_f, R_i, C_c)
    C_f = "820 pF"
    R_f = "10 MOhm"
    notch = true                    # the 50 Hz second-order Butterworth band-stop
    [probe]                         # the rigid probe that presses the sensor
    friction = "unknown"            # its Coulomb coefficient on the silicone: a number >= 0, "frictionless",
                                    # "sticking" or "unknown" (the answer's friction band: both limits only)

Conversions: volts at the ADC = offset + counts * (hi - lo) / 2^bits (two's-
complement counts, so code 0 is the offset); a taxel channel's SI value is the
conditioning output in V = volts / gain; the force channel's is N = volts / sensitivity,
the travel channel's m = volts / sensitivity.
Every error is one line naming the key and the fix (RigError, a ValueError).
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Annotated, Literal

from pydantic import BeforeValidator, Field, ValidationError, ValidationInfo, model_validator

from taxel import units
from taxel.fem.readout import Readout
from taxel.schema import Ratio, Strict
from taxel.schema import one_line, read_toml

from taxel.studies.bench.protocol import MAX_CHANNELS, Protocol


class RigError(ValueError):
    """A rig file that cannot be used; the message is one line with the fix."""


def _q(unit: str, what: str, positive=False):
    """A quantity: a string with a unit in a file; plain SI numbers in rig.json (context si_numbers)."""
    def parse(v, info: ValidationInfo):
        si = bool(info.context and info.context.get("si_numbers"))
        return units.to_si(v, unit, what, positive=positive, si_numbers=si)
    return BeforeValidator(parse)


Volt = Annotated[float, _q("V", "voltage")]
Rate = Annotated[float, _q("Hz", "frequency", positive=True)]
Resistance = Annotated[float, _q("ohm", "resistance", positive=True)]
Capacitance = Annotated[float, _q("F", "capacitance")]
CHANNEL_NAME = re.compile(r"^(taxel_(\d+)_(\d+)|force|travel)$")


def _sensitivity(v, info: ValidationInfo):
    """V/N for the load cell, V/m for the actuator's travel (the channel's name says which)."""
    if v is None:
        return None
    travel = (info.data or {}).get("name") == "travel"
    si = bool(info.context and info.context.get("si_numbers"))
    return units.to_si(v, "V/m" if travel else "V/N", "travel sensitivity" if travel else "load-cell sensitivity",
                       positive=True, si_numbers=si)


class Port(Strict):
    url: str = Field(min_length=1)
    baud: int = Field(115200, gt=0)
    protocol: Protocol = "taxel-cobs"


class Sampling(Strict):
    rate: Rate


class ADC(Strict):
    bits: int = Field(16, ge=2, le=32)
    range: tuple[Volt, Volt] = ("-10 V", "10 V")
    offset: Volt = 0.0

    @model_validator(mode="after")
    def _span(self):
        if not self.range[1] > self.range[0]:
            raise ValueError(f"range must go from low to high, got {list(self.range)}")
        return self

    @property
    def lsb(self) -> float:
        return (self.range[1] - self.range[0]) / 2 ** self.bits

    @property
    def code_limits(self) -> tuple[int, int]:
        return -(2 ** (self.bits - 1)), 2 ** (self.bits - 1) - 1


class Channel(Strict):
    index: int = Field(ge=0, lt=MAX_CHANNELS)
    name: str
    gain: Ratio | None = None
    sensitivity: Annotated[float | None, BeforeValidator(_sensitivity)] = None

    @model_validator(mode="after")
    def _kind(self):
        if not CHANNEL_NAME.match(self.name):
            raise ValueError(f"unknown channel {self.name!r}; name it taxel_ROW_COL (e.g. taxel_1_2), force or travel")
        if self.kind in ("force", "travel"):
            if self.sensitivity is None:
                raise ValueError(f"the {self.name} channel needs its sensitivity, e.g. sensitivity = "
                                 + ('"0.5 V/N" (the load cell)' if self.kind == "force" else '"1 V/mm" (the travel sensor)'))
            if self.gain is not None:
                raise ValueError(f"the {self.name} channel takes sensitivity, not gain")
        else:
            if self.sensitivity is not None:
                raise ValueError(f"{self.name}: a taxel channel takes gain (V/V), not sensitivity")
        return self

    @property
    def kind(self) -> Literal["taxel", "force", "travel"]:
        return self.name if self.name in ("force", "travel") else "taxel"

    @property
    def taxel(self) -> tuple[int, int] | None:
        m = CHANNEL_NAME.match(self.name)
        return (int(m.group(2)), int(m.group(3))) if m.group(2) is not None else None

    @property
    def volts_per_si(self) -> float:
        """ADC volts per SI unit of the channel (V/V, V/N or V/m)."""
        return self.sensitivity if self.kind in ("force", "travel") else (1.0 if self.gain is None else self.gain)

    @property
    def unit(self) -> str:
        return {"force": "N", "travel": "m"}.get(self.kind, "V")


class Conditioning(Strict):
    circuit: Literal["open", "resistor", "charge_amplifier"] = "open"
    R: Resistance = "500 MOhm"
    C_f: Capacitance = "820 pF"
    R_f: Resistance = "10 MOhm"
    R_i: Resistance = "10 kOhm"
    C_c: Capacitance = "100 pF"
    notch: bool = False
    notch_frequency: Rate = "50 Hz"
    notch_bandwidth: Rate = "10 Hz"

    def readout(self) -> Readout:
        """The chain as the FEM's and lumped model's Readout."""
        return Readout(**self.model_dump())


def _probe_friction(v):
    """probe.friction: "unknown", "frictionless", "sticking" or a Coulomb coefficient (a number >= 0)."""
    if v in ("unknown", "frictionless", "sticking"):
        return v
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
        raise ValueError(f'expected a Coulomb coefficient >= 0 such as 0.4, "unknown", "frictionless" or "sticking", '
                         f'got {v!r}')
    return float(v)


class Probe(Strict):
    # the probe's Coulomb coefficient on the silicone (a number >= 0, or a limit), the middle of the
    # answer's friction band (taxel.jobs.friction_band); "unknown": no sourced value, the band's two
    # limits (frictionless, sticking) are the answer
    friction: Annotated[Literal["unknown", "frictionless", "sticking"] | float,
                        BeforeValidator(_probe_friction)] = "unknown"

    @property
    def coefficient(self) -> float | None:
        """The Coulomb coefficient when the rig gives one (None: unknown or a limit)."""
        return self.friction if isinstance(self.friction, float) else None


class Rig(Strict):
    name: str = "rig"
    port: Port
    sampling: Sampling
    adc: ADC = ADC()
    channels: list[Channel] = Field(min_length=1, max_length=MAX_CHANNELS)
    conditioning: dict = Field(default_factory=dict)
    probe: Probe = Probe()                 # the rigid probe that presses the sensor (its friction)

    @model_validator(mode="after")
    def _channels(self):
        seen: dict[int, str] = {}
        for ch in self.channels:
            if ch.index in seen:
                raise ValueError(f"duplicate channel index {ch.index} ({seen[ch.index]} and {ch.name}); "
                                 "give each channel its own index")
            seen[ch.index] = ch.name
        names = [c.name for c in self.channels]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"duplicate channel name {sorted(dup)[0]!r}; each name once")
        if sorted(seen) != list(range(len(seen))):
            raise ValueError(f"channel indices must be 0..{len(seen) - 1} (the frame's n samples), "
                             f"got {sorted(seen)}")
        self.chains()                      # validates the conditioning table
        return self

    @property
    def n(self) -> int:
        return len(self.channels)

    def ordered(self) -> list[Channel]:
        return sorted(self.channels, key=lambda c: c.index)

    @property
    def names(self) -> list[str]:
        return [c.name for c in self.ordered()]

    def chains(self) -> dict[str, Conditioning]:
        """The conditioning in front of each taxel channel."""
        base = {k: v for k, v in self.conditioning.items() if not isinstance(v, dict)}
        per = {k: v for k, v in self.conditioning.items() if isinstance(v, dict)}
        taxels = [c.name for c in self.ordered() if c.kind == "taxel"]
        for k in per:
            if k not in taxels:
                raise ValueError(f"conditioning.{k}: unknown channel; the taxel channels are {', '.join(taxels)}")
        chains = {}
        for t in taxels or [""]:
            try:
                chains[t] = Conditioning.model_validate({**base, **per.get(t, {})})
            except ValidationError as err:
                where = f"conditioning.{t}" if t in per else "conditioning"
                raise ValueError(f"{where}: {_rig_line(err)}") from None
        return chains

    def counts_to_volts(self, counts):
        return self.adc.offset + counts * self.adc.lsb

    def volts_per_si(self):
        import numpy as np
        return np.array([c.volts_per_si for c in self.ordered()])


def _rig_line(err: ValidationError) -> str:
    return one_line(err)


def parse_rig(data: dict, source: str = "rig", si_numbers: bool = False) -> Rig:
    """A validated rig from a dict (TOML-like, units as strings; with si_numbers, SI numbers as in rig.json)."""
    try:
        return Rig.model_validate(data, context={"si_numbers": si_numbers})
    except ValidationError as err:
        raise RigError(f"{source}: {_rig_line(err)}") from None


BUILTIN = Path(__file__).parent / "builtin"


def builtin_rigs() -> list[str]:
    return sorted(p.stem for p in BUILTIN.glob("*.toml"))


def load_rig(path: str | Path) -> Rig:
    """A validated rig from a TOML file or a built-in name; RigError (one line) otherwise."""
    path = Path(path)
    if not path.is_file() and (BUILTIN / f"{path}.toml").is_file():
        path = BUILTIN / f"{path}.toml"
    if not path.is_file():
        raise RigError(f"{path}: no such rig file; give the path of a rig TOML file "
                       f"or a built-in rig ({', '.join(builtin_rigs())})")
    return parse_rig(read_toml(path, RigError), str(path))


# The example under the rig key reference (docs/reference/keys/rig.md): a built-in rig, whole.
KEY_EXAMPLES = {"the built-in rig thesis-bench": (BUILTIN / "thesis-bench.toml").read_text()}
