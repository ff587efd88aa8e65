"""The assumptions behind an answer's numbers: every value of the chain that the user's files did
not give (a scene value equal to the schema's default, a built-in material's constant), what it
moves, and where it comes from. Shown on page one (the answer block) and on an optimization's
page. Nothing is solved here: the table is read from the folder's scene.json.

    rows = assumptions(scene_data)      # [{"assumed": ..., "value": ..., "moves": ..., "source": ...}]
"""

from __future__ import annotations

# [readout] defaults: key -> (what it is, what it moves, its source); the schema's values (taxel.scene.ReadoutTable)
READOUT = {
    "R_i": ("charge amplifier input resistor", "the upper cutoff 1 / (2 pi R_i (C_p + C_c)): the bandwidth",
            "the scene's default readout; the circuit is TI SLOA033A's, the seed gives no value"),
    "C_c": ("cable capacitance", "the upper cutoff and the op-amp noise gain: bandwidth, minimum detectable force",
            "the scene's default readout: about 1 m of cable"),
    "e_n": ("op-amp voltage noise", "the minimum detectable force", "a TL072-class JFET op-amp, TI SLOS080 (the seed "
            "does not name its op-amp)"),
    "i_n": ("op-amp current noise", "the minimum detectable force", "TI SLOS080 (TL072)"),
    "swing": ("amplifier output swing", "the force range to saturation (with an ADC, the smaller full scale clips)",
              "TI SLOS080: +-12 V on +-15 V supplies"),
    "temperature": ("temperature", "the resistors' and the dielectric loss's thermal noise", "23 C, assumed"),
}
UNITS = {"R_i": "Ω", "C_c": "F", "e_n": "V/√Hz", "i_n": "A/√Hz", "swing": "V", "temperature": "K"}
CIRCUIT_KEYS = {"charge_amplifier": ("R_i", "C_c", "e_n", "i_n", "swing", "temperature"),
                "resistor": ("C_c", "e_n", "i_n", "swing", "temperature"), "open": ()}


def _shown(value, unit: str) -> str:
    from taxel.units import engineering, magnitude
    try:
        return engineering(magnitude(value), unit, 3) if unit not in ("K", "V/√Hz", "A/√Hz") else \
            (f"{magnitude(value) - 273.15:.3g} °C" if unit == "K" else engineering(magnitude(value), unit.split("/")[0], 3)
             + "/√Hz")
    except Exception:
        return str(value)


def _defaults() -> dict:
    from taxel.scene import DynamicsTable, ReadoutTable
    from taxel.schema import to_data
    return {"readout": to_data(ReadoutTable()), "dynamics": to_data(DynamicsTable())}


def assumptions(scene: dict, adc: dict | None = None) -> list[dict]:
    """The assumed values of a scene's data (a result folder's scene.json): the readout's
    defaults its circuit uses, the piezo's loss model when the material is built in, and the
    silicone's loss factor; each with what it moves and its source. `adc`: the rig's ADC the
    readout numbers were taken on ({"rig", "bits", "range_V"}), when not the user's."""
    from taxel.fem.constitution import library
    rows = []
    defaults = _defaults()
    readout = scene.get("readout") or {}
    for key in CIRCUIT_KEYS.get(readout.get("circuit", "open"), ()):
        if key in readout and str(readout[key]) == str(defaults["readout"].get(key)):
            what, moves, source = READOUT[key]
            rows.append({"assumed": what, "value": _shown(readout[key], UNITS.get(key, "")), "moves": moves,
                         "source": source})
    if adc:
        rows.append({"assumed": "ADC", "value": f"{adc['bits']} bits, {adc['range_V'][0]:g} to {adc['range_V'][1]:g} V",
                     "moves": "the quantisation noise (the minimum detectable force) and the full scale (saturation)",
                     "source": f"the {adc['rig']} rig file (studies/bench/builtin)"})
    elif readout.get("circuit", "open") != "open" and not readout.get("adc"):
        rows.append({"assumed": "ADC", "value": "none (an ideal converter)", "moves": "no quantisation noise in the "
                     "minimum detectable force; the amplifier's swing alone sets the saturation",
                     "source": "the scene names no [readout.adc]"})
    elif readout.get("adc") and not {"enob", "rate"} <= set(readout["adc"]):
        rows.append({"assumed": "ADC noise", "value": ", ".join(v for k, v in (
            ("enob", "enob = bits (an ideal quantiser)"), ("rate", "rate = twice the band's top")) if k not in readout["adc"]),
                     "moves": "the quantisation noise: the minimum detectable force",
                     "source": "the defaults of [readout.adc] (the scene gives no enob or rate)"})
    array = scene.get("array") or {}
    dyn = scene.get("dynamics") or {}
    name = str(array.get("piezo", ""))
    piezo = library().get(name.lower()) if name not in (scene.get("materials") or {}) else None
    if piezo is not None and getattr(piezo, "Qm", None):
        if dyn.get("piezo_loss") is None:
            rows.append({"assumed": f"{piezo.name} mechanical loss factor 1/Qm",
                         "value": f"{1 / piezo.Qm:.3g} (Qm = {piezo.Qm:g}), frequency-independent; the lumped "
                                  f"models take it as viscous at {_shown(dyn.get('reference_frequency', '100 Hz'), 'Hz')} "
                                  "(the scene's dynamics reference frequency)",
                         "moves": "the frequency and step responses (their gain near and above the first "
                                  "resonance); not the static sensitivity",
                         "source": f"the built-in {piezo.name} record ({piezo.source or 'no source'}); Qm is "
                                   "not in that table"
                                   if "PVDF" in piezo.name else f"the built-in {piezo.name} record ({piezo.source})"})
        if dyn.get("dielectric_loss") is None and getattr(piezo, "tan_delta", None):
            rows.append({"assumed": f"{piezo.name} dielectric loss tangent", "value": f"{piezo.tan_delta:g} "
                         "(the datasheet's, at 1 kHz, taken at every frequency)",
                         "moves": "the dielectric-loss noise: the minimum detectable force",
                         "source": f"the built-in {piezo.name} record ({piezo.source})"})
    if str(dyn.get("silicone_loss", defaults["dynamics"]["silicone_loss"])) == str(defaults["dynamics"]["silicone_loss"]):
        rows.append({"assumed": "silicone loss factor", "value": str(defaults["dynamics"]["silicone_loss"]),
                     "moves": "the frequency and step responses (damping of the silicone's resonance)",
                     "source": "the scene's default dynamics: no sourced damping data for Ecoflex"})
    return rows


def of_answer(a) -> list[dict]:
    """The answer's assumptions (reports.answer_assumptions), from its folder's scene and its readout's."""
    import json
    from taxel.optimize.answer_folder import READOUT_FILE
    if a.path is None or not (a.path / "scene.json").exists():
        return []
    scene = json.loads((a.path / "scene.json").read_text())
    chain = json.loads((a.path / READOUT_FILE).read_text()) if (a.path / READOUT_FILE).exists() else {}
    if chain.get("readout"):                  # the numbers at the readout are the bench chain's
        scene["readout"] = chain["readout"]
    return assumptions(scene, chain.get("adc"))
