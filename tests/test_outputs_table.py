"""The one output table (taxel.analyses.results.outputs) names what the results produce:
a static solve's outputs, its readout's, a noise budget's and a design's noise floor are
the table's rows for that use, each unit one pint reads (or a ratio / a level in dB)."""

from __future__ import annotations

import pytest

from taxel import api, units
from taxel.analyses.results.outputs import OUTPUTS, USES, table, units_of


def test_every_unit_is_read_by_pint_and_every_use_is_known():
    for o in OUTPUTS.values():
        assert o.uses and o.uses <= set(USES), o.name
        if o.unit not in ("ratio", "dB"):
            assert units.quantity(f"1 {o.unit}").to_base_units().magnitude > 0, o.name
    assert units_of("tolerance")["crosstalk"] == "" and units_of("metric")["snr"] == "dB"
    with pytest.raises(KeyError):
        table("statics")


def test_the_results_produce_the_table_s_outputs():
    """A 2D static solve through a charge amplifier: its outputs are the table's "static" ones,
    the readout's among them; its noise budget's are the "noise" ones; the design noise floor's
    the "design_noise" ones."""
    from taxel.analyses.solves.noise import design_noise, quasi_static_noise
    scene = api.load("thesis-pzt-3x3-2d").replace(**{"readout.circuit": "charge_amplifier", "mesh.size": "1 mm"})
    res = api.solve(scene)
    out = res.outputs()
    assert set(out) <= set(table("static")) and {"sensitivity", "crosstalk", "max_strain"} <= set(out)
    assert set(table("readout")) <= set(out)
    nr = quasi_static_noise(scene, out["sensitivity"], out["charge_sensitivity"])
    assert set(nr.outputs()) == set(table("noise"))
    assert set(design_noise(scene, out)) == set(table("design_noise"))
