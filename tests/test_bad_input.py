"""Bad input, one table: every command refuses it with exit code 2 and one line.

Each row of `CASES` is one case: an id, the command line (relative paths, run in
an empty folder), the files to create first, the exit code (2: bad input) and the
words the one line on stderr must contain (the key or file at fault, and often the
fix). For every row: exactly one line on stderr, starting "taxel: error:", holding
every word; no traceback; nothing on stdout; no file created (a failed command
leaves no partial output). The commands are called in-process through
`taxel.cli.main`, the console script's entry point, so the table does not depend
on how the CLI is laid out inside.

The Python API refuses the same scenes with a `SceneError` of one line
(`API_CASES`); studies check every point before they run. Property-based fuzzing
of the four schemas (documents that may also solve) is `test_fuzz_schemas.py`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import pytest
from measure_util import rig_dict, rig_toml

from taxel.cli import main

EXIT_INPUT = 2          # the CLI's exit code for bad input


@dataclass
class Case:
    id: str
    argv: list[str]
    words: tuple[str, ...]                 # each must be in the one line on stderr (case-sensitive)
    files: dict[str, str | bytes] = field(default_factory=dict)
    out: str | None = None                 # the folder the command would write (it must not appear)
    setup: object = None                   # callable(tmp_path) for cases files cannot express
    code: int = EXIT_INPUT
    slow: bool = False                     # marked slow: waits on a timeout (a scheduler that is not there)


# ------------------------------------------------------------------------- scenes
# a small, fast scene (one PZT taxel, coarse mesh) for cases that get as far as meshing
FAST = '[model]\ntype = "plane_strain"\n[mesh]\nsize = "1 mm"\npiezo_size = "0.25 mm"\n'
ARRAY = FAST + "[array]\n"
AXISYM = ARRAY.replace('"plane_strain"', '"axisymmetric"')
PLATE = FAST + '[plate]\nwidth = "20 mm"\nlayers = [{material = "PVDF", thickness = "52 um"}]\n'


def scene(id, text, *words):
    return Case(f"scene-{id}", ["solve", "s.toml"], words, {"s.toml": text})


def replace_in(text, old, new):
    assert old in text
    return text.replace(old, new)


SCENES = [
    scene("unknown-key", ARRAY + "colz = 3\n", "array.colz", "unknown key"),
    scene("unknown-table", ARRAY + "[geometry]\nx = 1\n", "geometry", "unknown key"),
    scene("bool-rows", ARRAY + "rows = true\n", "array.rows"),
    scene("float-rows", ARRAY + "rows = 2.5\n", "array.rows"),
    scene("string-rows", ARRAY + 'rows = "three"\n', "array.rows"),
    scene("rows-0", ARRAY + "rows = 0\n", "array.rows"),
    scene("rows-huge", ARRAY + "rows = 1000\n", "array.rows"),
    scene("inf-width", ARRAY + 'taxel_width = "inf mm"\n', "array.taxel_width", "finite"),
    scene("nan-gap", ARRAY + 'gap = "nan mm"\n', "array.gap"),
    scene("width-1e300", ARRAY + 'taxel_width = "1e300 mm"\n', "array.taxel_width"),
    scene("gap-1nm", ARRAY + 'cols = 2\ngap = "1 nm"\n', "array.gap"),
    scene("width-1nm", ARRAY + 'taxel_width = "1 nm"\n', "array.taxel_width"),
    scene("mesh-size-1nm", replace_in(replace_in(ARRAY, '"1 mm"', '"1 nm"'), '"0.25 mm"', '"0.25 nm"'),
          "mesh", "unknowns"),
    scene("mesh-size-negative", replace_in(ARRAY, '"1 mm"', '"-1 mm"'), "mesh.size", "positive"),
    scene("piezo-size-larger-than-size", replace_in(ARRAY, '"0.25 mm"', '"5 mm"'), "mesh.piezo_size"),
    scene("force-string-abc", ARRAY + '[load]\nforce = "abc"\n', "load.force"),
    scene("force-inf", ARRAY + '[load]\nforce = "inf N"\n', "load.force", "finite"),
    scene("force-list", ARRAY + '[load]\nforce = ["1 N"]\n', "load.force"),
    scene("force-zero", ARRAY + '[load]\nforce = "0 N"\n', "load.force"),
    scene("taxel-out-of-range", ARRAY + "[load]\ntaxel = [3, 0]\n", "load.taxel"),
    scene("taxel-three-numbers", ARRAY + "[load]\ntaxel = [0, 0, 0]\n", "load.taxel"),
    scene("indenter-wider-than-part", ARRAY + '[load]\nkind = "probe"\nradius = "50 mm"\n', "load"),
    scene("indenter-offset-outside", ARRAY + '[load]\nkind = "probe"\nradius = "1 mm"\n'
          'offset = ["40 mm", "0 mm"]\n', "load"),
    scene("both-array-and-plate", ARRAY + '[plate]\nwidth = "1 mm"\nlayers = [{material = "PVDF", '
          'thickness = "1 mm"}]\n', "[array]", "[plate]"),
    scene("neither-array-nor-plate", FAST, "[array]", "[plate]"),
    scene("plate-no-layers", FAST + '[plate]\nwidth = "10 mm"\nlayers = []\n', "plate.layers"),
    scene("plate-no-width", FAST + '[plate]\nlayers = [{material = "PVDF", thickness = "1 mm"}]\n'
          '[load]\nkind = "pressure"\npressure = "1 kPa"\n', "plate.width"),
    scene("plate-unknown-material", FAST + '[plate]\nwidth = "10 mm"\nlayers = [{material = "unobtainium", '
          'thickness = "1 mm"}]\n[load]\nkind = "pressure"\npressure = "1 kPa"\n', "unobtainium"),
    scene("unknown-piezo", ARRAY + 'piezo = "PZT-99"\n', "PZT-99"),
    scene("unknown-silicone", ARRAY + 'silicone = "jelly"\n', "jelly"),
    scene("piezo-as-silicone", ARRAY + 'silicone = "PVDF"\n', "array.silicone"),
    scene("axisym-3x3", ARRAY.replace('"plane_strain"', '"axisymmetric"') + "rows = 3\ncols = 3\n",
          "axisymmetric"),
    scene("tolerance-2", ARRAY.replace('"plane_strain"', '"plane_strain"\ntolerance = 2'), "model.tolerance"),
    scene("fidelity-typo", ARRAY.replace('"plane_strain"', '"plane_strain"\nfidelity = "best"'), "model.fidelity"),
    scene("fidelity-auto-frequency", ARRAY.replace('"plane_strain"', '"plane_strain"\nfidelity = "auto"')
          + '[analysis]\ntype = "frequency"\n', "model.fidelity"),
    scene("outputs-crosstalk-one-taxel", ARRAY.replace('"plane_strain"', '"plane_strain"\noutputs = ["crosstalk"]'),
          "crosstalk"),
    scene("outputs-typo", ARRAY.replace('"plane_strain"', '"plane_strain"\noutputs = ["voltage"]'), "model.outputs"),
    scene("support-typo", ARRAY + '[supports]\nbottom = "glued"\n', "supports.bottom", "glued"),
    scene("electrode-bad-state", ARRAY + '[electrodes]\ntaxel_0_0 = "floating"\n', "electrodes.taxel_0_0"),
    scene("name-path-traversal", 'name = "../../x"\n' + ARRAY, "name"),
    scene("name-slash", 'name = "a/b"\n' + ARRAY, "name"),
    scene("analysis-type-typo", ARRAY + '[analysis]\ntype = "modal"\n', "analysis.type"),
    scene("fmin-above-fmax", ARRAY + '[analysis]\ntype = "frequency"\nf_min = "2 kHz"\n', "f_min"),
    scene("transient-1e10-steps", ARRAY + '[analysis]\ntype = "transient"\nduration = "1e7 s"\n'
          'dt = "1 ms"\n', "analysis", "steps"),
    scene("dt-above-duration", ARRAY + '[analysis]\ntype = "transient"\nduration = "1 ms"\ndt = "1 s"\n',
          "analysis.dt"),
    scene("csv-input-without-file", ARRAY + '[analysis]\ntype = "transient"\ninput = "csv"\n', "analysis.file"),
    scene("csv-input-missing-file", ARRAY + '[analysis]\ntype = "transient"\ninput = "csv"\nfile = "nope.csv"\n',
          "nope.csv"),
    scene("csv-input-garbage", ARRAY + '[analysis]\ntype = "transient"\ninput = "csv"\nfile = "f.csv"\n',
          "f.csv"),
    scene("frequency-points-1e9", ARRAY + '[analysis]\ntype = "frequency"\npoints = 1000000000\n',
          "analysis.points"),
    scene("readout-R-zero", ARRAY + '[readout]\nR = "0 ohm"\n', "readout.R"),
    scene("readout-unknown-circuit", ARRAY + '[readout]\ncircuit = "tube"\n', "readout.circuit"),
    scene("adc-zero-bits", ARRAY + '[readout.adc]\nbits = 0\nrange = ["0 V", "3.3 V"]\n', "readout.adc.bits", "1"),
    scene("adc-range-in-newtons", ARRAY + '[readout.adc]\nbits = 12\nrange = ["0 N", "3.3 N"]\n',
          "readout.adc.range", "not a voltage"),
    scene("adc-range-backwards", ARRAY + '[readout.adc]\nbits = 12\nrange = ["3.3 V", "0 V"]\n',
          "readout.adc.range", "low to high"),
    scene("adc-no-bits", ARRAY + '[readout.adc]\nrange = ["0 V", "3.3 V"]\n', "readout.adc.bits"),
    scene("band-backwards", ARRAY + '[readout]\nband = ["300 Hz", "1 Hz"]\n', "readout.band", "low to high"),
    scene("band-in-seconds", ARRAY + '[readout]\nband = ["1 s", "300 Hz"]\n', "readout.band", "not a frequency"),
    scene("adc-enob-above-bits", ARRAY + '[readout.adc]\nbits = 12\nrange = ["0 V", "3 V"]\nenob = 14\n',
          "readout.adc.enob", "bits"),
    scene("dynamics-negative-loss", ARRAY + "[dynamics]\nsilicone_loss = -0.1\n", "dynamics.silicone_loss"),
    scene("tolerance-150-percent", ARRAY.replace('"plane_strain"', '"plane_strain"\ntolerance = "150 %"'),
          "model.tolerance", "below"),
    scene("tolerance-with-length", ARRAY.replace('"plane_strain"', '"plane_strain"\ntolerance = "1 mm"'),
          "model.tolerance", "fraction"),
    scene("tolerance-bool", ARRAY.replace('"plane_strain"', '"plane_strain"\ntolerance = true'), "model.tolerance"),
    scene("tolerance-zero-percent", ARRAY.replace('"plane_strain"', '"plane_strain"\ntolerance = "0 %"'),
          "model.tolerance"),
    scene("tolerance-nan", ARRAY.replace('"plane_strain"', '"plane_strain"\ntolerance = "nan"'), "model.tolerance",
          "finite"),
    scene("loss-abc", ARRAY + '[dynamics]\nsilicone_loss = "abc"\n', "dynamics.silicone_loss"),
    scene("piezo-loss-200-percent", ARRAY + '[dynamics]\npiezo_loss = "200 %"\n', "dynamics.piezo_loss"),
    scene("sweep-tolerance-hz", ARRAY + '[analysis]\ntype = "frequency"\ntolerance = "1 Hz"\n',
          "analysis.tolerance"),
    scene("plate-indenter-wider", FAST + '[plate]\nwidth = "10 mm"\nlayers = [{material = "PVDF", '
          'thickness = "1 mm"}]\n[load]\nkind = "probe"\nradius = "20 mm"\n', "load.radius", "plate"),
    scene("plate-indenter-offset-off", FAST + '[plate]\nwidth = "10 mm"\nlayers = [{material = "PVDF", '
          'thickness = "1 mm"}]\n[load]\nkind = "probe"\nradius = "2 mm"\noffset = ["4 mm", "0 mm"]\n',
          "load.radius", "offset"),
    scene("disk-indenter-wider", FAST.replace('"plane_strain"', '"axisymmetric"') + '[plate]\nshape = "disk"\n'
          'radius = "5 mm"\nlayers = [{material = "PVDF", thickness = "1 mm"}]\n[load]\nkind = "probe"\n'
          'radius = "6 mm"\n', "load.radius", "disk"),
    scene("3d-plate-indenter-longer", FAST.replace('"plane_strain"', '"3d"') + '[plate]\nwidth = "20 mm"\n'
          'length = "4 mm"\nlayers = [{material = "PVDF", thickness = "1 mm"}]\n[load]\nkind = "probe"\n'
          'radius = "3 mm"\n', "load.radius", "length"),
    scene("yeoh-without-constants", ARRAY.replace('"plane_strain"', '"plane_strain"\nsilicone = "yeoh"')
          + 'silicone = "gel"\n[materials.gel]\nkind = "solid"\nE = 1e5\nnu = 0.45\nrho = 1000\n',
          "materials.gel", "C10"),
    scene("not-toml", "this is [not toml\n", "s.toml", "TOML"),
    scene("empty-file", "", "[array]", "[plate]"),
    scene("binary-file", b"\x00\x01\x02\xff\xfe", "s.toml"),
    scene("latin1", b'[array]\npiezo = "PZT\xe9"\n', "s.toml", "UTF-8"),
]
next(c for c in SCENES if c.id == "scene-csv-input-garbage").files["f.csv"] = "time,force\nabc,def\n"


# the same checks, from the first bad-input table (rows that duplicated one above merged into it)
MORE_SCENES = [
    # ---- unknown / misspelt keys
    scene("unknown-top-level-key", 'colour = "red"\n' + ARRAY, "unknown key 'colour'"),
    scene("unknown-nested-key-colz", ARRAY + "colz = 2\n", "unknown key 'array.colz'"),
    scene("unknown-supports-key", ARRAY + '[supports]\nbottm = "bonded"\n', "supports.bottm"),
    scene("model-type-typo", ARRAY.replace('"plane_strain"', '"plane_strian"'),
          "model.type", "plane_strian"),
    scene("mesh-order-3", ARRAY.replace("[mesh]\n", "[mesh]\norder = 3\n"), "mesh.order", "3"),
    scene("mesh-piezo-layers-0", ARRAY.replace("[mesh]\n", "[mesh]\npiezo_layers = 0\n"),
          "mesh.piezo_layers"),
    # ---- quantities and units
    scene("negative-silicone-thickness", ARRAY + 'silicone_below = "-1 mm"\n',
          "array.silicone_below", "negative"),
    scene("zero-taxel-width", ARRAY + 'taxel_width = "0 mm"\n', "array.taxel_width", "positive"),
    scene("missing-unit-number", ARRAY + "taxel_width = 4\n", "array.taxel_width", "missing unit"),
    scene("missing-unit-string", ARRAY + 'taxel_width = "4"\n', "array.taxel_width", "missing unit"),
    scene("unit-mismatch-force-in-mm", ARRAY + '[load]\nforce = "1 mm"\n', "load.force", "unit mismatch"),
    scene("unit-mismatch-force-in-kPa", ARRAY + '[load]\nforce = "10 kPa"\n', "load.force", "unit mismatch"),
    scene("friction-without-contact", ARRAY + '[load]\nkind = "probe"\nradius = "1 mm"\nfriction = "sticking"\n',
          "load.friction", "load.contact = true"),
    scene("unreadable-quantity", ARRAY + 'taxel_width = "abc mm"\n', "array.taxel_width", "abc mm"),
    # ---- geometry
    scene("overlapping-taxels", ARRAY + 'cols = 2\ngap = "-1 mm"\n', "array.gap", "overlap"),
    scene("plate-and-array-with-indenter", PLATE + "\n[array]\n[load]\nkind = \"probe\"\nradius = \"1 mm\"\n",
          "[array]", "[plate]"),
    scene("neither-array-nor-plate-with-force", FAST + '[load]\nforce = "1 N"\n', "[array]", "[plate]"),
    scene("axisymmetric-3x3", AXISYM + "rows = 3\ncols = 3\n[load]\ntaxel = [1, 1]\n",
          "axisymmetric", "rows = cols = 1"),
    scene("plate-layers-empty", FAST + '[plate]\nwidth = "20 mm"\nlayers = []\n'
          '[load]\nkind = "pressure"\npressure = "1 kPa"\n', "plate.layers"),
    scene("plate-rectangle-without-width", FAST + '[plate]\nlayers = [{material = "PVDF", '
          'thickness = "52 um"}]\n[load]\nkind = "pressure"\npressure = "1 kPa"\n', "plate.width"),
    # ---- materials
    scene("unknown-piezo-material", ARRAY + 'piezo = "PZT-9"\n', "unknown material 'PZT-9'"),
    scene("unknown-silicone-material", ARRAY + 'silicone = "Sorta-Clear"\n',
          "unknown material 'Sorta-Clear'"),
    scene("user-material-without-rho", ARRAY + 'silicone = "soft"\n[materials.soft]\n'
          'kind = "solid"\nE = 3.0e4\nnu = 0.45\n', "materials.soft", "rho"),
    scene("user-material-bad-kind", ARRAY + 'silicone = "soft"\n[materials.soft]\n'
          'kind = "gel"\nrho = 1000.0\n', "materials.soft", "kind"),
    scene("user-material-wrong-unit", ARRAY + 'silicone = "soft"\n[materials.soft]\n'
          'kind = "solid"\nC10 = "27.5 kg"\nK = "55 MPa"\nrho = "1070 kg/m^3"\n', "materials.soft", "C10", "Pa"),
    scene("user-material-wrong-unit-in-a-matrix", ARRAY + 'piezo = "film"\n[materials.film]\nkind = "piezo"\n'
          'rho = 1780\nd = [[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0], ["23 pC/m", 0, 0, 0, 0, 0]]\n',
          "materials.film", "d:", "C/N"),
    scene("axisymmetric-pvdf", AXISYM + 'piezo = "PVDF"\n',
          "PVDF", "transversely isotropic"),
    # ---- warm touch (heat): a material's conductivity, the finger's temperature, the touch's time
    scene("user-material-negative-conductivity", ARRAY + 'silicone = "soft"\n[materials.soft]\nkind = "solid"\n'
          'E = 3.0e4\nnu = 0.45\nrho = 1070\nconductivity = "-0.2 W/(m*K)"\n', "materials.soft", "conductivity",
          "positive"),
    scene("user-material-drift-in-volts", ARRAY + 'piezo = "film"\n[materials.film]\nkind = "piezo"\n'
          'rho = 1780\npermittivity_tc = "0.5 V"\n', "materials.film", "permittivity_tc", "1/K"),
    scene("warm-touch-temperature-in-volts", ARRAY + '[warm_touch]\nfinger = "5 V"\n', "warm_touch.finger",
          "temperature"),
    scene("warm-touch-longer-than-time", ARRAY + '[warm_touch]\nduration = "5 s"\ntime = "3 s"\n',
          "warm_touch.duration", "simulated time"),
    # ---- load
    scene("load-taxel-outside-array", ARRAY + "rows = 2\ncols = 2\n[load]\ntaxel = [2, 0]\n",
          "load.taxel", "outside"),
    scene("load-taxel-negative", ARRAY + "[load]\ntaxel = [-1, 0]\n", "load.taxel", "outside"),
    scene("load-footprint-outside-sensor", ARRAY + '[load]\nkind = "probe"\nradius = "1 mm"\n'
          'offset = ["20 mm", "0 mm"]\n', "load", "outside the sensor"),
    scene("between-without-neighbour", ARRAY + 'cols = 2\n[load]\nkind = "between"\n', "load.neighbour"),
    scene("neighbour-not-adjacent", ARRAY + 'cols = 3\n[load]\nkind = "between"\nneighbour = [0, 2]\n',
          "load.neighbour", "next to"),
    scene("between-rows-in-2d", ARRAY + 'rows = 2\n[load]\nkind = "between"\nneighbour = [1, 0]\n',
          "load.neighbour", "row"),
    scene("indenter-without-radius", ARRAY + '[load]\nkind = "probe"\n', "load.radius"),
    scene("pressure-without-pressure", PLATE + '[load]\nkind = "pressure"\n', "load.pressure"),
    scene("pressure-without-pressure-array", ARRAY + '[load]\nkind = "pressure"\n', "load.pressure"),
    scene("plate-with-taxel-load", PLATE, "load.kind", "taxel"),
    scene("axisymmetric-offset-load",
          AXISYM + '[load]\nkind = "probe"\nradius = "1 mm"\noffset = ["1 mm", "0 mm"]\n',
          "axisymmetric", "load.offset"),
    # ---- supports and electrodes
    scene("bottom-and-edges-free", ARRAY + '[supports]\nbottom = "free"\nedges = "free"\n',
          "supports", "free"),
    scene("unknown-electrode-name", ARRAY + '[electrodes]\ntaxel_9_9 = "open"\n',
          "electrodes.taxel_9_9", "no such electrode"),
    scene("bad-electrode-state", ARRAY + '[electrodes]\ntaxel_0_0 = "maybe"\n',
          "electrodes.taxel_0_0", "maybe"),
    scene("electrode-state-without-unit", ARRAY + '[electrodes]\ntaxel_0_0 = "10"\n',
          "electrodes.taxel_0_0"),
    scene("electrode-state-number", ARRAY + "[electrodes]\ntaxel_0_0 = 5\n", "electrodes.taxel_0_0"),
    scene("no-grounded-electrode", ARRAY + '[electrodes]\nground = "open"\n', "electrodes", "ground"),
    # ---- the file itself
    scene("invalid-toml-syntax", '[array\ntaxel_width = "4 mm"\n', "not valid TOML"),

    # ---- once bugs: a bare 0 skipped the positive check, NaN, wrong material kind, odd paths
    scene("zero-taxel-width-bare-number", ARRAY + "taxel_width = 0\n", "array.taxel_width"),
    scene("zero-indenter-radius-bare-number", ARRAY + '[load]\nkind = "probe"\nradius = 0\n',
          "load.radius"),
    scene("zero-piezo-thickness-bare-number", ARRAY + "piezo_thickness = 0\n", "array.piezo_thickness"),
    scene("nan-force", ARRAY + '[load]\nforce = "nan N"\n', "load.force"),
    scene("solid-as-piezo", ARRAY + 'piezo = "Ecoflex-00-30"\n', "array.piezo"),
    scene("symmetry-typo", ARRAY.replace("[model]\n", '[model]\nsymmetry = "quater"\n'), "model.symmetry"),
    scene("symmetry-quarter-in-2d", ARRAY.replace("[model]\n", '[model]\nsymmetry = "quarter"\n'),
          "model.symmetry", "3d"),
    scene("symmetry-quarter-off-centre", ARRAY.replace('"plane_strain"', '"3d"').replace(
        "[model]\n", '[model]\nsymmetry = "quarter"\n') + "cols = 2\n", "model.symmetry", "not centred"),
    scene("symmetry-half-asymmetric-electrodes", ARRAY.replace("[model]\n", '[model]\nsymmetry = "half"\n')
          + 'cols = 3\n[load]\ntaxel = [0, 1]\n[electrodes]\ntaxel_0_0 = "ground"\n', "model.symmetry",
          "electrodes"),
    scene("tolerance-percent-over-100", ARRAY.replace("[model]\n", '[model]\ntolerance = "120 %"\n'),
          "model.tolerance", "below 1"),
    scene("tolerance-as-length", ARRAY.replace("[model]\n", '[model]\ntolerance = "2 mm"\n'), "model.tolerance"),
    scene("tolerance-negative-percent", ARRAY.replace("[model]\n", '[model]\ntolerance = "-2 %"\n'),
          "model.tolerance"),
    scene("loss-factor-as-frequency", ARRAY + '[dynamics]\npiezo_loss = "1 Hz"\n', "dynamics.piezo_loss"),
    scene("dielectric-loss-100-percent", ARRAY + '[dynamics]\ndielectric_loss = "100 %"\n',
          "dynamics.dielectric_loss"),
    scene("plate-indenter-beyond-edge", PLATE + '[load]\nkind = "probe"\nradius = "8 mm"\n'
          'offset = ["5 mm", "0 mm"]\n', "load.radius", "half-width"),
    scene("plate-indenter-wider-than-the-plate", PLATE + '[load]\nkind = "probe"\nradius = "30 mm"\n', "load.radius"),
    scene("yeoh-user-silicone-without-c10", ARRAY.replace("[model]\n", '[model]\nsilicone = "yeoh"\n')
          + 'silicone = "gel"\n[materials.gel]\nkind = "solid"\nE = 1e5\nnu = 0.45\nrho = 1000\n',
          "materials.gel", "C10", "fit-yeoh"),
    scene("file-not-utf8", b'[array]\ntaxel_width = "4 mm"\n# \xff\xfe\n', "s.toml"),
]
# ------------------------------------------------------------------------- materials
MAT = ARRAY + 'silicone = "gel"\n[materials.gel]\n'
MATERIALS = [
    scene("mat-negative-E", MAT + 'kind = "solid"\nE = -1e5\nnu = 0.4\nrho = 1000\n', "materials.gel", "E"),
    scene("mat-nu-half", MAT + 'kind = "solid"\nE = 1e5\nnu = 0.5\nrho = 1000\n', "materials.gel", "nu"),
    scene("mat-nu-0.6", MAT + 'kind = "solid"\nE = 1e5\nnu = 0.6\nrho = 1000\n', "materials.gel", "nu"),
    scene("mat-nu-minus-1", MAT + 'kind = "solid"\nE = 1e5\nnu = -1.0\nrho = 1000\n', "materials.gel", "nu"),
    scene("mat-negative-rho", MAT + 'kind = "solid"\nE = 1e5\nnu = 0.4\nrho = -1000\n', "materials.gel", "rho"),
    scene("mat-zero-rho", MAT + 'kind = "solid"\nE = 1e5\nnu = 0.4\nrho = 0\n', "materials.gel", "rho"),
    scene("mat-negative-eps", MAT + 'kind = "solid"\nE = 1e5\nnu = 0.4\nrho = 1000\neps_r = -3\n',
          "materials.gel", "eps_r"),
    scene("mat-negative-C10", MAT + 'kind = "solid"\nC10 = -7e3\nK = 1e7\nrho = 1000\n', "materials.gel", "C10"),
    scene("mat-zero-C10", MAT + 'kind = "solid"\nC10 = 0\nK = 1e7\nrho = 1000\n', "materials.gel", "C10"),
    scene("mat-unstable-yeoh", MAT + 'kind = "solid"\nC10 = 1e3\nC20 = -5e4\nK = 1e7\nrho = 1000\n',
          "materials.gel", "unstable"),
    scene("mat-misspelt-key", MAT + 'kind = "solid"\nE = 1e5\nnu = 0.4\nrho = 1000\ndensity = 5\n',
          "materials.gel", "density"),
    scene("mat-missing-rho", MAT + 'kind = "solid"\nE = 1e5\nnu = 0.4\n', "materials.gel", "rho"),
    scene("mat-string-E", MAT + 'kind = "solid"\nE = "soft"\nnu = 0.4\nrho = 1000\n', "materials.gel", "E"),
    scene("mat-kind-typo", MAT + 'kind = "solod"\nE = 1e5\nnu = 0.4\nrho = 1000\n', "materials.gel", "kind"),
    scene("mat-negative-K", MAT + 'kind = "solid"\nmu = 1e4\nK = -1e6\nrho = 1000\n', "materials.gel", "K"),
    scene("mat-piezo-bad-shape", ARRAY + 'piezo = "pz"\n[materials.pz]\nkind = "piezo"\nc = [[1.0]]\n'
          'e = [[1.0]]\neps_S = [[1.0]]\nrho = 7000\n', "materials.pz"),
    scene("mat-piezo-not-pd", ARRAY + 'piezo = "pz"\n[materials.pz]\nkind = "piezo"\n'
          + "c = " + str([[-1.0 if i == j else 0.0 for j in range(6)] for i in range(6)]) + "\n"
          + "e = " + str([[0.0] * 6 for _ in range(3)]) + "\n"
          + "eps_S = " + str([[1.0 if i == j else 0.0 for j in range(3)] for i in range(3)]) + "\nrho = 7000\n",
          "materials.pz", "positive definite"),
    scene("mat-not-a-table", ARRAY + 'silicone = "gel"\n[materials]\ngel = 3\n', "materials.gel"),
]

# ------------------------------------------------------------------------- solve, mesh, lumped options
SOLVE = [
    Case("solve-missing-file", ["solve", "nope.toml"], ("no scene file", "nope.toml")),
    Case("solve-directory", ["solve", "scene-dir"], ("scene-dir",), setup=lambda p: (p / "scene-dir").mkdir()),
    Case("solve-unreadable", ["solve", "/proc/self/mem"], ("/proc/self/mem", "cannot read")),
    Case("solve-vtu-missing-folder", ["solve", "s.toml", "--vtu", "no/such/dir/f.vtu"], ("no/such/dir",),
         {"s.toml": ARRAY}),
    Case("solve-out-is-a-file", ["solve", "s.toml", "--out", "o"], ("o",), {"s.toml": ARRAY, "o": "x"}),
    Case("solve-out-not-writable", ["solve", "s.toml", "--out", "/proc/taxel-o"], ("/proc/taxel-o", "cannot create"),
         {"s.toml": ARRAY}),
    Case("lumped-out-not-writable", ["lumped", "s.toml", "--out", "/proc/taxel-o"], ("/proc/taxel-o",),
         {"s.toml": ARRAY}),
    Case("frequency-out-not-writable", ["solve", "s.toml", "--out", "/proc/taxel-o"], ("/proc/taxel-o",),
         {"s.toml": ARRAY + '[analysis]\ntype = "frequency"\npoints = 5\n'}),
    Case("solve-bad-solver", ["solve", "s.toml", "--solver", "magic"], ("solver",), {"s.toml": ARRAY}),
    Case("mesh-unknown-extension", ["mesh", "s.toml", "-o", "x.unknownext"], ("x.unknownext",),
         {"s.toml": ARRAY}),
    Case("mesh-missing-folder", ["mesh", "s.toml", "-o", "no/dir/x.msh"], ("no/dir",), {"s.toml": ARRAY}),
    Case("mesh-no-output", ["mesh", "s.toml"], ("-o",), {"s.toml": ARRAY}),
    Case("mesh-out-not-writable", ["mesh", "s.toml", "-o", "/proc/taxel-x.msh"], ("-o", "/proc/taxel-x.msh",
         "cannot write"), {"s.toml": ARRAY}),
    Case("mesh-vtu-not-writable", ["mesh", "s.toml", "-o", "/sys/taxel-x.vtu"], ("/sys/taxel-x.vtu", "cannot write"),
         {"s.toml": ARRAY}),
    Case("solve-vtu-not-writable", ["solve", "s.toml", "--vtu", "/proc/taxel-x.vtu"], ("--vtu", "/proc/taxel-x.vtu"),
         {"s.toml": ARRAY}),
    Case("lumped-plate", ["lumped", "p.toml"], ("[array]",),
         {"p.toml": FAST + '[plate]\nwidth = "10 mm"\nlayers = [{material = "PVDF", thickness = "1 mm"}]\n'
                           '[load]\nkind = "pressure"\npressure = "1 kPa"\n'}),
    Case("unknown-command", ["frobnicate"], ("frobnicate",)),
    Case("no-command", [], ("command",)),
    Case("examples-with-argument", ["examples", "extra"], ("extra",)),
    Case("demo-out-is-a-file", ["demo", "--out", "f"], ("f",), {"f": "x"}),
]

# ------------------------------------------------------------------------- studies
STUDY = ('base = "thesis-pzt-single-2d"\noutputs = ["voltage"]\n[overrides]\n"mesh.size" = "1 mm"\n'
         '[[parameters]]\npath = "load.force"\nvalues = ["0.2 N", "0.4 N"]\n')


def study(id, text, *words, extra_files=None):
    return Case(f"study-{id}", ["study", "run", "st.toml", "--out", "o", "--workers", "1", "--quiet"], words,
                {"st.toml": text, **(extra_files or {})}, out="o")


STUDIES = [
    study("unknown-key", STUDY + "colour = 1\n", "colour"),
    study("no-parameters", 'base = "thesis-pzt-single-2d"\n', "parameters"),
    study("missing-base", '[[parameters]]\npath = "load.force"\nvalues = ["1 N"]\n', "base"),
    study("base-missing", STUDY.replace("thesis-pzt-single-2d", "nope"), "base", "nope"),
    study("unknown-path", STUDY.replace("load.force", "lode.force"), "lode.force"),
    study("unknown-leaf", STUDY.replace("load.force", "load.forse"), "forse"),
    study("two-params-one-path", STUDY + '[[parameters]]\npath = "load.force"\nlabel = "f2"\n'
          'values = ["1 N", "2 N"]\n', "load.force", "twice"),
    study("duplicate-names", STUDY + '[[parameters]]\npath = "load.force"\nvalues = ["1 N"]\n', "force"),
    study("empty-values", STUDY.replace('["0.2 N", "0.4 N"]', "[]"), "values"),
    study("range-without-step", 'base = "thesis-pzt-single-2d"\n[[parameters]]\npath = "load.force"\n'
          'start = "0.2 N"\nstop = "1 N"\n', "step"),
    study("range-negative-step", 'base = "thesis-pzt-single-2d"\n[[parameters]]\npath = "load.force"\n'
          'start = "0.2 N"\nstop = "1 N"\nstep = "-0.1 N"\n', "step"),
    study("range-unit-mismatch", 'base = "thesis-pzt-single-2d"\n[[parameters]]\npath = "load.force"\n'
          'start = "0.2 N"\nstop = "1 mm"\nstep = "0.1 N"\n', "unit"),
    study("range-abc", 'base = "thesis-pzt-single-2d"\n[[parameters]]\npath = "load.force"\n'
          'start = "abc"\nstop = "1 N"\nstep = "0.1 N"\n', "abc"),
    study("1e7-points", 'base = "thesis-pzt-single-2d"\n[[parameters]]\npath = "load.force"\n'
          'start = "0 N"\nstop = "1 N"\nstep = "1e-7 N"\n', "points"),
    study("lhs-without-samples", 'base = "thesis-pzt-single-2d"\nsampling = "lhs"\n[[parameters]]\npath = "load.force"\n'
          'start = "0.2 N"\nstop = "1 N"\n', "samples"),
    study("labels-count", STUDY.replace('values = ["0.2 N", "0.4 N"]', 'values = ["0.2 N", "0.4 N"]\n'
          'labels = ["a"]'), "labels"),
    study("bad-outputs", STUDY.replace('["voltage"]', '["happiness"]'), "outputs"),
    study("first-point-invalid", STUDY.replace('"0.2 N"', '"0.2 mm"'), "load.force"),
    study("second-point-invalid", STUDY.replace('"0.4 N"', '"0.4 mm"'), "point 2 of 2", "load.force"),
    study("last-grid-point-invalid", STUDY + '[[parameters]]\npath = "array.rows"\nvalues = [1, 0]\n',
          "point 2 of 4", "array.rows"),
    study("override-invalid", STUDY.replace('"mesh.size" = "1 mm"', '"mesh.size" = "-1 mm"'), "first point",
          "mesh.size"),
    study("lhs-some-points-invalid", 'base = "thesis-pzt-single-2d"\nsampling = "lhs"\nsamples = 6\n'
          '[[parameters]]\npath = "mesh.size"\nstart = "-1 mm"\nstop = "1 mm"\n', "point", "mesh.size"),
    study("lhs-negative-seed", 'base = "thesis-pzt-single-2d"\nsampling = "lhs"\nsamples = 3\nseed = -1\n'
          '[[parameters]]\npath = "load.force"\nstart = "0.2 N"\nstop = "1 N"\n', "seed"),
    study("lhs-huge-seed", 'base = "thesis-pzt-single-2d"\nsampling = "lhs"\nsamples = 3\nseed = 1099511627776\n'
          '[[parameters]]\npath = "load.force"\nstart = "0.2 N"\nstop = "1 N"\n', "seed"),
    study("lhs-float-seed", 'base = "thesis-pzt-single-2d"\nsampling = "lhs"\nsamples = 3\nseed = 1.5\n'
          '[[parameters]]\npath = "load.force"\nstart = "0.2 N"\nstop = "1 N"\n', "seed"),
    study("tolerance-override-bad", STUDY.replace('"mesh.size" = "1 mm"', '"model.tolerance" = "5 mm"'),
          "model.tolerance"),
    study("not-toml", "[[[\n", "st.toml", "TOML"),
    study("binary", b"\xff\xfe\x00", "st.toml"),
    study("base-not-toml", 'base = "b.toml"\n[[parameters]]\npath = "load.force"\nvalues = ["1 N"]\n',
          "b.toml", extra_files={"b.toml": "[[["}),
    Case("study-missing-file", ["study", "run", "nope.toml"], ("nope",)),
    Case("study-out-is-a-file", ["study", "run", "st.toml", "--out", "f", "--workers", "1", "--quiet"], ("f",),
         {"st.toml": STUDY, "f": "x"}),
    Case("study-workers-0", ["study", "run", "st.toml", "--out", "o", "--workers", "0", "--quiet"],
         ("--workers",), {"st.toml": STUDY}, out="o"),
    Case("study-scheduler-unreachable", ["study", "run", "st.toml", "--out", "o", "--scheduler",
         "tcp://127.0.0.1:9", "--quiet"], ("scheduler", "127.0.0.1:9"), {"st.toml": STUDY}, out="o", slow=True),
    Case("study-status-no-folder", ["study", "status", "nothere"], ("nothere",)),
    Case("study-status-no-store", ["study", "status", "d"], ("d", "results.sqlite"),
         setup=lambda p: (p / "d").mkdir()),
    Case("study-status-corrupt-store", ["study", "status", "d"], ("results.sqlite", "move it aside"),
         {"d/results.sqlite": b"this is not a database" * 100}),
    Case("study-export-corrupt-store", ["study", "export", "d", "--csv", "x.csv"],
         ("results.sqlite", "move it aside"), {"d/results.sqlite": b"SQLite format 3\x00" + b"\x07" * 5000}),
    Case("study-run-corrupt-store", ["study", "run", "st.toml", "--out", "d", "--workers", "1", "--quiet"],
         ("results.sqlite", "move it aside"), {"st.toml": STUDY, "d/results.sqlite": b"garbage" * 1000}),
    Case("study-export-no-csv", ["study", "export", "d"], ("--csv",), setup=lambda p: _tiny_store(p / "d")),
    Case("study-export-csv-missing-folder", ["study", "export", "d", "--csv", "no/dir/x.csv"], ("no/dir",),
         setup=lambda p: _tiny_store(p / "d")),
    Case("study-export-csv-not-writable", ["study", "export", "d", "--csv", "/proc/taxel-x.csv"],
         ("/proc/taxel-x.csv",), setup=lambda p: _tiny_store(p / "d")),
    Case("study-corrupt-study-json", ["study", "status", "d"], ("study.json",),
         {"d/study.json": "{not json"}, setup=lambda p: _tiny_store(p / "d")),
]


def _tiny_store(folder):
    from taxel.studies.store import Store
    folder.mkdir(parents=True, exist_ok=True)
    Store(folder).close()


# ------------------------------------------------------------------------- optimization
OPT = ('base = "thesis-pzt-3x3-2d"\n[variables]\ngap = {path = "array.gap", min = "1 mm", max = "5 mm"}\n'
       '[objective]\nminimize = "crosstalk"\n[algorithm]\nmax_evaluations = 4\nglobal = "none"\n')


def opt(id, text, *words):
    return Case(f"opt-{id}", ["optimize", "op.toml", "--out", "o"], words, {"op.toml": text}, out="o")


OPTIMIZE = [
    opt("unknown-key", OPT + "colour = 1\n", "colour"),
    opt("no-variables", OPT.replace('gap = {path = "array.gap", min = "1 mm", max = "5 mm"}\n', ""), "variables"),
    opt("empty-bounds", OPT.replace('min = "1 mm"', 'min = "6 mm"'), "variables.gap", "bounds"),
    opt("unit-mismatch", OPT.replace('max = "5 mm"', 'max = "5 N"'), "variables.gap"),
    opt("start-outside", OPT.replace('max = "5 mm"}', 'max = "5 mm", start = "9 mm"}'), "variables.gap", "start"),
    opt("unknown-metric", OPT.replace('"crosstalk"', '"beauty"'), "objective"),
    opt("two-objectives", OPT.replace('minimize = "crosstalk"', 'minimize = "crosstalk"\nmaximize = "sensitivity"'),
        "objective"),
    opt("constraint-syntax", OPT + '[requirements]\ngap = "= 2 mm"\n', "requirements.gap"),
    opt("constraint-nan", OPT + '[requirements]\ncrosstalk = "<= nan"\n', "requirements.crosstalk"),
    opt("constraint-abc", OPT + '[requirements]\ncrosstalk = "<= abc"\n', "requirements.crosstalk"),
    opt("constraint-infeasible", OPT + '[requirements]\ngap = ">= 10 mm"\n', "requirements.gap", "cannot be met"),
    opt("constraints-retired", OPT + '[constraints]\ngap = ">= 2 mm"\n', "[constraints]", "[requirements]",
        'gap = ">= 2 mm"'),
    opt("coverage-above-all", OPT + '[requirements]\ncoverage = ">= 200 %"\n', "requirements.coverage",
        "never above 100 %"),
    opt("localization-negative", OPT + '[requirements]\nlocalization_error = "<= -0.5 mm"\n',
        "requirements.localization_error", "never below 0"),
    opt("max-evals-0", OPT.replace("max_evaluations = 4", "max_evaluations = 0"), "max_evaluations"),
    opt("algorithm-typo", OPT.replace('global = "none"', 'global = "DIRCT"'), "global"),
    opt("crosstalk-single-taxel", OPT.replace("thesis-pzt-3x3-2d", "thesis-pzt-single-2d"), "crosstalk"),
    opt("pareto-needs-sensitivity", OPT + "[pareto]\npoints = 3\n", "pareto"),
    opt("variable-on-material", OPT.replace('"array.gap"', '"array.silicone"'), "variables.gap", "array.silicone",
        "not a number"),
    opt("variable-on-piezo", OPT.replace('"array.gap"', '"array.piezo"'), "variables.gap", "array.piezo"),
    opt("variable-on-model-type", OPT.replace('"array.gap"', '"model.type"'), "variables.gap", "model.type"),
    opt("variable-on-table", OPT.replace('"array.gap"', '"array"'), "variables.gap", "table"),
    opt("variable-on-bool", OPT.replace('"array.gap"', '"load.contact"'), "variables.gap", "load.contact"),
    opt("variable-on-count", OPT.replace('"array.gap"', '"array.rows"'), "variables.gap", "whole number"),
    opt("variable-inside-number", OPT.replace('"array.gap"', '"array.gap.x"'), "variables.gap", "not a table"),
    opt("variable-unknown-leaf", OPT.replace('"array.gap"', '"array.gapp"'), "variables.gap", "gapp"),
    opt("variable-on-material-kind", OPT.replace('"array.gap"', '"materials.gel.kind"'), "variables.gap",
        "material constant"),
    opt("xtol-percent-too-big", OPT.replace('global = "none"', 'global = "none"\nxtol = "150 %"'), "xtol"),
    opt("constraint-percent-unit", OPT + '[requirements]\ncrosstalk = "<= 5 mm"\n', "requirements.crosstalk"),
    opt("requirement-grammar", OPT + '[requirements]\npitch = "small"\n', "requirements.pitch", "<= value"),
    opt("requirement-unit", OPT + '[requirements]\ncrosstalk = "<= 2 V"\n', "requirements.crosstalk", "a ratio"),
    opt("requirement-pitch-in-newtons", OPT + '[requirements]\npitch = "<= 7 N"\n', "requirements.pitch", "m"),
    opt("not-toml", "[[[", "op.toml"),
    Case("opt-missing-file", ["optimize", "nope.toml"], ("nope",)),
]

# ------------------------------------------------------------------------- Yeoh fit
GOOD_CSV = "strain,stress_Pa\n" + "".join(f"{e},{2e4 * e}\n" for e in (0.1, 0.2, 0.3, 0.4, 0.5))


def fit(id, content, *words, args=("--fit-strain", "0.5")):
    return Case(f"fit-{id}", ["material", "fit-yeoh", "t.csv", *args], words, {"t.csv": content})


FIT = [
    fit("no-header", "1,2\n3,4\n", "t.csv", "header"),
    fit("only-strain", "strain\n0.1\n0.2\n", "t.csv", "stress"),
    fit("huge-values", "strain,stress_Pa\n" + "".join(f"{e},1e308\n" for e in (0.1, 0.2, 0.3, 0.4)), "t.csv"),
    fit("one-strain-value", "strain,stress_Pa\n" + "0.1,1000\n" * 10, "t.csv", "strain"),
    fit("invalid-rows", "strain,stress_Pa\n0.1,1\nabc,2\n0.2,x\n0.3,3\n0.4,4\n", "t.csv", "row"),
    fit("too-few", "strain,stress_Pa\n0.1,1\n0.2,2\n", "t.csv"),
    fit("negative-max-strain", GOOD_CSV, "--fit-strain", args=("--fit-strain", "-1")),
    fit("abc-max-strain", GOOD_CSV, "--fit-strain", args=("--fit-strain", "abc")),
    fit("nan-max-strain", GOOD_CSV, "--fit-strain", args=("--fit-strain", "nan")),
    fit("plot-missing-folder", GOOD_CSV, "no/dir", args=("--fit-strain", "0.5", "--plot", "no/dir/p.png")),
    fit("binary", b"\x00\xff\xfe", "t.csv"),
    fit("mixed-signs", "strain,stress_Pa\n-0.2,-4000\n-0.1,-2000\n0.1,2000\n0.2,4000\n0.3,6000\n0.4,8000\n",
        "t.csv", "compressive", "tension"),
    fit("mixed-one-negative", GOOD_CSV + "-0.05,-1000\n", "t.csv", "compressive"),
    fit("all-compression", "strain,stress_Pa\n" + "".join(f"{-e},{-2e4 * e}\n" for e in (0.1, 0.2, 0.3, 0.4)),
        "t.csv", "negative", "tension"),
    fit("stretch-not-positive", "strain,stress_Pa\n-1.5,-1\n0.1,1\n0.2,2\n0.3,3\n0.4,4\n", "t.csv", "stretch"),
    fit("stretch-column", "stretch,stress_Pa\n0.8,-1\n1.1,1\n1.2,2\n1.3,3\n1.4,4\n", "t.csv", "strain"),
    fit("mixed-signs-percent", "Engineering Strain (%);Engineering Stress (kPa)\n-20;-4\n-10;-2\n10;2\n20;4\n"
        "30;6\n40;8\n", "t.csv", "compressive", "tension"),
    fit("stress-sign-flipped", "strain,stress_Pa\n" + "".join(f"{e},{-2e4 * e}\n" for e in (0.1, 0.2, 0.3, 0.4)),
        "t.csv", "sign"),
    fit("empty", "", "t.csv"),
    Case("fit-missing-file", ["material", "fit-yeoh", "nope.csv"], ("nope.csv",)),
    Case("fit-directory", ["material", "fit-yeoh", "d"], ("d",), setup=lambda p: (p / "d").mkdir()),
]

# ------------------------------------------------------------------------- reports
REPORTS = [
    Case("report-missing-folder", ["report", "nope", "--out", "r"], ("nope",), out="r"),
    Case("report-not-a-result", ["report", "d", "--out", "r"], ("d", "not a study, optimization or solve folder"), setup=lambda p: (p / "d").mkdir(), out="r"),
    Case("report-corrupt-scene-json", ["report", "d", "--out", "r", "--no-compare"], ("scene.json",),
         {"d/scene.json": "{bad", "d/result.json": "{}"}, out="r"),
    Case("report-corrupt-optimum-json", ["report", "d", "--out", "r", "--no-compare"], ("optimum.json",),
         {"d/optimum.json": "{bad"}, out="r"),
    Case("report-second-folder-bad", ["report", "ok", "bad", "--out", "r", "--no-compare"], ("bad",),
         setup=lambda p: _solved_folder(p / "ok"), files={"bad/study.json": "{bad"}, out="r"),
    Case("report-out-is-a-file", ["report", "ok", "--out", "f", "--no-compare"], ("f",), {"f": "x"},
         setup=lambda p: _solved_folder(p / "ok")),
    Case("report-no-folders", ["report", "--out", "r"], ("folders",)),
    Case("work-precision-negative-force", ["work-precision", "thesis-pzt-single-2d", "--force", "-1", "--out", "f"],
         ("--force",), out="f"),
    Case("work-precision-unknown-scene", ["work-precision", "nope-scene", "--out", "f"], ("nope-scene",), out="f"),
]


def _solved_folder(folder):
    assert main(["solve", "thesis-pzt-single-2d", "--out", str(folder)]) == 0



# ------------------------------------------------------------------------- contact
def contact(id, model, kind, extra, *words):
    text = (f'[model]\ntype = "{model}"\n[mesh]\nsize = "1 mm"\npiezo_size = "0.25 mm"\n[array]\n'
            f'[load]\nkind = "{kind}"\nradius = "1 mm"\ncontact = true\n{extra}\n')
    return scene(f"contact-{id}", text, *words)


CONTACT = [
    contact("on-a-taxel-load", "plane_strain", "taxel", "", "load.contact = true needs load.kind = 'probe'"),
    contact("sphere-in-2d", "plane_strain", "probe", 'shape = "sphere"', "load.shape = 'sphere'"),
    contact("cylinder-axisymmetric", "axisymmetric", "probe", 'shape = "cylinder"', "load.shape = 'cylinder'"),
    contact("edge-radius-too-big", "plane_strain", "probe", 'edge_radius = "2 mm"', "load.edge_radius"),
    contact("coulomb-friction", "plane_strain", "probe", 'friction = "coulomb"', "load.friction"),
    contact("negative-friction", "plane_strain", "probe", 'friction = -0.3', "load.friction", "Coulomb coefficient >= 0"),
]

# ------------------------------------------------------------------------- more study files
STUDY_FILES = [study(f"file-{id}", 'base = "thesis-pzt-single-2d"\n' + extra, *words) for id, extra, words in [
    ("unknown-path", '[[parameters]]\npath = "arrya.gap"\nvalues = ["1 mm"]\n', ("unknown scene path",)),
    ("unknown-leaf", '[[parameters]]\npath = "array.gapp"\nvalues = ["1 mm"]\n', ("array.gapp",)),
    ("empty-range", '[[parameters]]\npath = "array.gap"\nstart = "3 mm"\nstop = "1 mm"\nstep = "1 mm"\n',
     ("empty range",)),
    ("empty-values", '[[parameters]]\npath = "array.gap"\nvalues = []\n', ("values is empty",)),
    ("unit-mismatch", '[[parameters]]\npath = "array.gap"\nstart = "1 mm"\nstop = "2 N"\nstep = "1 mm"\n',
     ("unit mismatch",)),
    ("bad-value-unit", '[[parameters]]\npath = "array.gap"\nvalues = ["1 N"]\n', ("array.gap",)),
    ("no-step", '[[parameters]]\npath = "array.gap"\nstart = "1 mm"\nstop = "2 mm"\n', ("step",)),
    ("labels", '[[parameters]]\npath = "array.gap"\nvalues = ["1 mm"]\nlabels = ["a", "b"]\n', ("labels",)),
    ("lhs-without-samples", 'sampling = "lhs"\n[[parameters]]\npath = "array.gap"\nstart = "1 mm"\nstop = "2 mm"\n',
     ("samples",)),
    ("unknown-key-colour", 'colour = 1\n[[parameters]]\npath = "array.gap"\nvalues = ["1 mm"]\n',
     ("unknown key 'colour'",)),
    ("two-named-silicone", 'outputs = ["voltage"]\n[[parameters]]\npath = "array.silicone"\nvalues = ["Ecoflex-00-30"]\n'
     '[[parameters]]\npath = "model.silicone"\nvalues = ["yeoh"]\n', ("two parameters are named 'silicone'",)),
]] + [
    study("file-base-nope", 'base = "nope"\n[[parameters]]\npath = "array.gap"\nvalues = ["1 mm"]\n', "base = 'nope'"),
]

# ------------------------------------------------------------------------- more optimizations
from test_optimize import COARSE_OPT      # noqa: E402  (the file the optimization tests use)
OPTIMIZE_FILES = [opt(f"file-{id}", replace_in(COARSE_OPT, *change), words) for id, change, words in [
    ("infeasible", ('total_thickness = "<= 2.127 mm"', 'total_thickness = "<= 0.1 mm"'), "cannot be met"),
    ("empty-bounds", ('min = "0.2 mm", max = "1.8 mm"', 'min = "1.8 mm", max = "0.2 mm"'), "empty bounds"),
    ("unknown-path", ('path = "array.silicone_above"', 'path = "arry.silicone_above"'), "unknown scene path"),
    ("unit-mismatch", ('max = "1.8 mm"', 'max = "1.8 N"'), "unit mismatch"),
    ("start-outside", ('start = "1 mm"', 'start = "3 mm"'), "outside"),
    ("bad-constraint", ('"<= 2.127 mm"', '"< 2.127 mm"'), "<="),
    ("unknown-metric", ('max_strain = "<= 5"', 'stiffness = "<= 5"'), "requirements.stiffness"),
    ("crosstalk-one-taxel", ('max_strain = "<= 5"', 'crosstalk = "<= 0.05"'), "two modelled taxels"),
    ("unknown-algorithm", ('local = "COBYLA"', 'local = "NEWUOA"'), "algorithm.local"),
]]

# ------------------------------------------------------------------------- more Yeoh fits
STRAIN_ONLY = "Time (s);Engineering Strain\n" + "".join(f"{i};{0.1 * i}\n" for i in range(1, 9))
FIT_MORE = [
    fit("no-stress-column", STRAIN_ONLY, "no stress column", args=()),
    fit("fit-strain-0", STRAIN_ONLY, "--fit-strain", args=("--fit-strain", "0")),
    fit("fit-strain-negative", STRAIN_ONLY, "--fit-strain", args=("--fit-strain", "-0.5")),
    fit("fit-strain-text", STRAIN_ONLY, "--fit-strain", args=("--fit-strain", "half")),
]

# ------------------------------------------------------------------------- measure
BENCH = str(Path(__file__).parents[1] / "studies" / "bench" / "builtin" / "thesis-bench.toml")


def rig_case(id, change, *words):
    return Case(f"rig-{id}", ["measure", "capture", "rig.toml", "--seconds", "1", "--out", "m"],
                ("rig.toml", *words), {"rig.toml": rig_toml(change(rig_dict()))}, out="m")


def _duplicate_index(d):
    chans = [dict(c) for c in d["channels"]]
    chans[1]["index"] = 0
    return {**d, "channels": chans}


def imported(id, name, content, *words):
    return Case(f"import-{id}", ["measure", "import", name, "--rig", "rig.toml", "--out", "m"], (name, *words),
                {"rig.toml": rig_toml(rig_dict()), **({name: content} if content is not None else {})}, out="m")


MEASURE = [
    rig_case("unknown-channel", lambda d: {**d, "channels": d["channels"][:-1] + [{"index": 9, "name": "pressure"}]},
             "unknown channel"),
    rig_case("missing-unit", lambda d: {**d, "channels": d["channels"][:-1]
                                        + [{"index": 9, "name": "force", "sensitivity": 0.5}]}, "missing unit"),
    rig_case("baud-0", lambda d: {**d, "port": {**d["port"], "baud": 0}}, "port.baud"),
    rig_case("probe-friction-negative", lambda d: {**d, "probe": {"friction": -0.3}}, "probe.friction", "Coulomb coefficient >= 0"),
    rig_case("duplicate-index", _duplicate_index, "duplicate channel index 0"),
    rig_case("unknown-conditioning-channel", lambda d: {**d, "conditioning": {**d["conditioning"],
                                                                              "taxel_5_5": {"R_f": "1 MOhm"}}},
             "conditioning.taxel_5_5: unknown channel"),
    rig_case("rate-without-unit", lambda d: {**d, "sampling": {"rate": 2000}}, "sampling.rate: missing unit"),
    rig_case("unknown-key", lambda d: {**d, "port": {**d["port"], "speed": 9600}}, "unknown key 'port.speed'"),
    rig_case("travel-in-V-per-N", lambda d: {**d, "channels": d["channels"] + [
        {"index": 10, "name": "travel", "sensitivity": "0.5 V/N"}]}, "travel sensitivity"),
    rig_case("travel-without-sensitivity", lambda d: {**d, "channels": d["channels"] + [
        {"index": 10, "name": "travel"}]}, "travel channel needs its sensitivity"),
    imported("short-csv", "short.csv", "seq,t_us,taxel_0_0\n0,0,1.0\n", "no column for channel 'taxel_0_1'"),
    imported("text-csv", "text.csv", "seq,t_us," + ",".join(c["name"] for c in rig_dict()["channels"])
             + "\n0,0," + ",".join(["x"] * 10) + "\n", "not a number"),
    imported("not-lvm", "not.lvm", "hello\n", "not a LabVIEW LVM file"),
    imported("junk-tdms", "junk.tdms", b"TDSm garbage" * 10, "not a readable TDMS file"),
    imported("zip-as-tdms", "fake.tdms", b"PK\x03\x04 a zip file", "not a TDMS file"),
    imported("noise-bin", "noise.bin", bytes(range(1, 256)) * 4, "no valid taxel-cobs frame"),
    imported("unknown-type", "data.xyz", "1,2\n", "unknown file type"),
    imported("nan-value", "nan.csv", "t_s," + ",".join(c["name"] for c in rig_dict()["channels"]) + "\n0,"
             + ",".join(["1"] * 9) + ",nan\n", "data row 1", "not a finite number"),
    imported("time-beyond-any-record", "huge.csv", "t_s," + ",".join(c["name"] for c in rig_dict()["channels"])
             + "\n0," + ",".join(["1"] * 10) + "\n1e300," + ",".join(["1"] * 10) + "\n", "data row 2", "beyond"),
    imported("missing-file", "missing.csv", None, "no such file"),
    Case("measure-export-not-a-measurement", ["measure", "export", ".", "--csv", "x.csv"],
         ("not a measurement folder",)),
    Case("measure-capture-into-non-empty-folder", ["measure", "capture", BENCH, "--out", "m"], ("not empty",),
         {"m/keep.txt": "x"}),
]


# ------------------------------------------------------------------------- every numeric option's range
# Each numeric option of taxel/cli/*.py, out of its range: refused while the command line is
# parsed (taxel.cli.files.number), before anything is read or written.
SIM = ["measure", "simulate", "thesis-bench", "--scene", "thesis-pzt-3x3-2d", "--input", "step", "--to", "s.bin"]
CAP = ["measure", "capture", "thesis-bench", "--out", "m"]


def option(id, argv, option, value, *words, out=None):
    return Case(f"range-{id}", [*argv, option, value], (f"argument {option}", *words), out=out)


RANGES = [
    option("reduce-f-max-negative", ["reduce", "thesis-pzt-single-2d", "-o", "m.npz"], "--f-max", "-5", "> 0"),
    option("reduce-f-max-zero", ["reduce", "thesis-pzt-single-2d", "-o", "m.npz"], "--f-max", "0", "> 0"),
    option("reduce-f-max-nan", ["reduce", "thesis-pzt-single-2d", "-o", "m.npz"], "--f-max", "nan", "'nan'"),
    option("reduce-f-max-text", ["reduce", "thesis-pzt-single-2d", "-o", "m.npz"], "--f-max", "2kHz", "'2kHz'"),
    option("simulate-seconds-0", SIM, "--seconds", "0", "> 0"),
    option("simulate-seconds-negative", SIM, "--seconds", "-1", "> 0"),
    option("simulate-seconds-inf", SIM, "--seconds", "inf", "'inf'"),
    option("simulate-corrupt-1", SIM, "--corrupt", "1", "< 1"),
    option("simulate-corrupt-negative", SIM, "--corrupt", "-0.1", ">= 0"),
    option("simulate-between-2", SIM, "--between", "2", "<= 1"),
    option("simulate-seed-negative", SIM, "--seed", "-1", "integer"),
    option("simulate-seed-float", SIM, "--seed", "1.5", "integer"),
    option("simulate-seq0-over-16-bits", SIM, "--seq0", "70000", "<= 65535"),
    option("simulate-t0-us-negative", SIM, "--t0-us", "-1", ">= 0"),
    option("simulate-linger-negative", SIM, "--linger", "-1", ">= 0"),
    option("simulate-delay-a-day", SIM, "--delay", "86400", "<= 3600"),
    option("capture-seconds-0", CAP, "--seconds", "0", "> 0", out="m"),
    option("analyze-resolution-0", ["measure", "analyze", "."], "--resolution", "0", "> 0"),
    option("calibrate-resolution-negative", ["measure", "calibrate", ".", "--scene", "thesis-pzt-single-2d"],
           "--resolution", "-1", "> 0"),
    option("work-precision-force-0", ["work-precision", "thesis-pzt-single-2d", "--out", "f"], "--force", "0",
           "> 0", out="f"),
    option("work-precision-force-kN", ["work-precision", "thesis-pzt-single-2d", "--out", "f"], "--force", "1000",
           "<= 100", out="f"),
    option("study-workers-many", ["study", "run", "thesis-pzt-tolerances", "--out", "o"], "--workers", "100000",
           "<= 256", out="o"),
    option("study-workers-text", ["study", "run", "thesis-pzt-tolerances", "--out", "o"], "--workers", "two",
           "'two'", out="o"),
    option("optimize-workers-0", ["optimize", "nope", "--out", "o"], "--workers", "0", ">= 1", out="o"),
    option("demo-presses-3d-negative", ["demo", "--out", "d"], "--presses-3d", "-1", ">= 0", out="d"),
    option("explore-port-0", ["explore"], "--port", "0", ">= 1"),
    option("explore-port-too-high", ["explore"], "--port", "70000", "<= 65535"),
    Case("explore-no-token-on-the-network", ["explore", "--host", "0.0.0.0", "--no-token"],
         ("--no-token", "--host 0.0.0.0", "127.0.0.1")),
    # sizes checked against the machine before any work (the limit: half its physical memory)
    Case("simulate-seconds-1e9", [*SIM, "--seconds", "1e9"], ("--seconds 1e+09", "GB", "half this machine's memory",
                                                             "give at most --seconds"), out="s.bin"),
]

# ------------------------------------------------------------------------- hostile input on the newer features
def _skin_file(folder):
    from test_skin import first_order_skin
    first_order_skin().save(folder / "skin.npz")


def _free_port() -> str:
    from taxel.explore.browser import free_port
    return str(free_port())


PROBE_LOAD = '[load]\nkind = "probe"\ncontact = true\nradius = "1 mm"\n'
HOSTILE = [
    Case("skin-dataset-too-large", ["skin", "dataset", "skin.npz", "-o", "d.h5", "--presses", "1000000",
                                    "--duration", "60"], ("--presses 1000000", "GB", "half this machine's memory",
                                                          "give at most --presses"), setup=_skin_file, out="d.h5"),
    Case("skin-dataset-empty-skin-file", ["skin", "dataset", "empty.npz", "-o", "d.h5"],
         ("empty.npz", "not a skin file"), {"empty.npz": b""}, out="d.h5"),
    option("skin-checks-0", ["skin", "thesis-pzt-3x3-2d", "-o", "s.npz"], "--checks", "0", ">= 1", out="s.npz"),
    Case("explore-out-cannot-be-created", ["explore", "--port", _free_port(), "--out", "f/explore"],
         ("f/explore", "Not a directory"), {"f": "a file, not a folder\n"}),
    scene("friction-1e9", ARRAY + PROBE_LOAD + "friction = 1e9\n", "load.friction", "sticking"),
    scene("force-negative", ARRAY + '[load]\nforce = "-1 N"\n', "load.force", ">= 0"),
    scene("gap-negative-one-taxel", ARRAY + 'gap = "-1 mm"\n', "array.gap", ">= 0"),
    scene("width-5000-digits", ARRAY + f'taxel_width = "{"1" * 5000} mm"\n', "array.taxel_width", "at most 100"),
]

# ------------------------------------------------------------------------- a tolerance study's [requirements]
TOLERANCE = ('base = "thesis-pzt-3x3-2d"\nsampling = "tolerance"\nsamples = 2\n[overrides]\n"mesh.size" = "1 mm"\n'
             '[[parameters]]\npath = "array.gap"\ntolerance = "0.2 mm"\n')
REQUIREMENTS = [study(f"requirement-{id}", TOLERANCE + f"[requirements]\n{line}\n", *words) for id, line, words in [
    ("grammar", 'sensitivity = "big"', ("requirements.sensitivity", "<= value")),
    ("strict-inequality", 'crosstalk = "< 2 %"', ("requirements.crosstalk", "<= value")),
    ("no-number", 'crosstalk = "<= lots"', ("requirements.crosstalk", "no number")),
    ("unknown-output", 'stiffness = "<= 2"', ("requirements.stiffness", "not an output", "sensitivity")),
    ("crosstalk-in-volts", 'crosstalk = "<= 2 V"', ("requirements.crosstalk", "a ratio")),
    ("sensitivity-in-newtons", 'sensitivity = ">= 0.7 N"', ("requirements.sensitivity", "V/N")),
    ("sensitivity-without-unit", 'sensitivity = ">= 0.7"', ("requirements.sensitivity", "missing unit")),
    ("sensitivity-in-percent", 'sensitivity = ">= 70 %"', ("requirements.sensitivity", "percentage")),
    ("snr-in-volts", 'snr = ">= 40 V"', ("requirements.snr", "dB")),
    ("unknown-unit", 'min_detectable_force = "<= 2 furlongs"', ("requirements.min_detectable_force",)),
    ("a-number", "crosstalk = 0.02", ("requirements.crosstalk",)),
]] + [
    study("requirements-on-a-grid", STUDY + '[requirements]\ncrosstalk = "<= 2 %"\n', "requirements",
          "tolerance"),
]


CASES = (SCENES + MORE_SCENES + CONTACT + MATERIALS + SOLVE + STUDIES + STUDY_FILES + OPTIMIZE + OPTIMIZE_FILES
         + FIT + FIT_MORE + REPORTS + MEASURE + RANGES + HOSTILE + REQUIREMENTS)


def test_the_table_is_large_covers_every_command_and_has_no_duplicate():
    assert len(CASES) >= 300
    commands = {c.argv[0] for c in CASES if c.argv}
    assert {"solve", "mesh", "lumped", "study", "optimize", "material", "report", "demo", "examples",
            "measure", "work-precision", "reduce", "explore"} <= commands
    assert len({c.id for c in CASES}) == len(CASES)
    inputs = [(tuple(c.argv), tuple(sorted(c.files.items()))) for c in CASES if c.setup is None]
    assert len(set(inputs)) == len(inputs), "two rows with the same command and files"


def _tree(root):
    return {p.relative_to(root) for p in root.rglob("*")}


@pytest.mark.parametrize("case", [pytest.param(c, id=c.id, marks=[pytest.mark.slow] if c.slow else [])
                                  for c in CASES])
def test_bad_input_exits_2_with_one_line_and_writes_nothing(case, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    for name, content in case.files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        (path.write_bytes if isinstance(content, bytes) else path.write_text)(content)
    if case.setup:
        case.setup(tmp_path)
    capsys.readouterr()
    before = _tree(tmp_path)
    code = main(list(case.argv))
    out, err = capsys.readouterr()
    lines = err.splitlines()
    assert code == case.code, f"exit {code}; stderr {err!r}"
    assert len(lines) == 1 and err.endswith("\n") and lines[0].startswith("taxel: error:"), f"stderr: {err!r}"
    assert "Traceback" not in err
    for w in case.words:
        assert w in lines[0], f"{w!r} not in {lines[0]!r}"
    assert out == "", f"bad input printed on stdout: {out!r}"
    new = _tree(tmp_path) - before
    assert not new, f"a failed command left files behind: {sorted(map(str, new))[:5]}"
    assert case.out is None or not (tmp_path / case.out).exists()


# ------------------------------------------------------------------------- the Python API
API_CASES = [
    ({"array": {"rows": True}}, "array.rows"),
    ({"array": {"taxel_width": -4e-3}}, "array.taxel_width"),
    ({"array": {"taxel_width": float("nan")}}, "array.taxel_width"),
    ({"array": {"piezo": "PZT-99"}}, "PZT-99"),
    ({"array": {}, "load": {"force": "1 mm"}}, "load.force"),
    ({"array": {}, "name": "../x"}, "name"),
    ({"array": {}, "materials": {"g": {"kind": "solid", "E": 1e5, "nu": 0.5, "rho": 1}}}, "materials.g"),
]


@pytest.mark.parametrize("data, words", API_CASES)
def test_the_python_api_refuses_bad_scenes_with_one_line(data, words):
    import taxel
    from taxel.scene import SceneError
    with pytest.raises(SceneError) as err:
        taxel.load(data)
    assert words in str(err.value) and "\n" not in str(err.value)


def test_replace_refuses_a_path_that_is_not_in_the_scene():
    import taxel
    from taxel.scene import SceneError
    scene = taxel.load("thesis-pzt-single-2d")
    with pytest.raises(SceneError, match="array.nope"):
        scene.replace(**{"array.nope": 1})
    with pytest.raises(SceneError, match="array.gap"):
        scene.replace(**{"array.gap": "abc"})


# ------------------------------------------------------------------------- studies: every point checked
def test_a_large_study_with_one_invalid_value_is_refused_before_it_runs(tmp_path):
    """Beyond CHECK_ALL points each parameter value is checked (not each of the
    product's points): 60 x 50 = 3000 points, one force value in millimetres."""
    from taxel.studies.spec import CHECK_ALL, StudyError, load_study
    forces = [f'"{0.01 * (i + 1):.2f} N"' for i in range(59)] + ['"0.3 mm"']
    f = tmp_path / "big.toml"
    f.write_text('base = "thesis-pzt-single-2d"\n[[parameters]]\npath = "load.force"\nvalues = ['
                 + ", ".join(forces) + ']\n[[parameters]]\npath = "array.silicone_above"\nstart = "0.1 mm"\n'
                 'stop = "5 mm"\nstep = "0.1 mm"\n')
    with pytest.raises(StudyError) as err:
        load_study(f)
    assert 60 * 50 > CHECK_ALL
    assert "point " in str(err.value) and "of 3000" in str(err.value) and "load.force" in str(err.value)


def test_a_combination_that_is_invalid_at_run_time_is_counted_failed(tmp_path):
    """A point invalid only in combination (two taxels with no gap), in a study built
    in Python (no load_study check): stored failed with its reason, and counted, so
    the run does not look clean."""
    from taxel.studies.execute import run
    from taxel.studies.spec import Study, StudySpec
    spec = StudySpec.model_validate({"base": "x", "outputs": ["voltage"],
                                     "overrides": {"mesh.size": "1 mm", "mesh.piezo_size": "0.5 mm"},
                                     "parameters": [{"path": "array.cols", "values": [1, 2]},
                                                    {"path": "array.gap", "values": ["3 mm", "0 mm"]}]})
    base = {"model": {"type": "plane_strain"}, "array": {}}
    s = run(Study(spec, base, tmp_path), tmp_path / "o", workers=1, progress=False)
    assert (s.total, s.failed, s.done) == (4, 1, 3)


# ------------------------------------------------------------------------- an estimate with a part it cannot compute
CYLINDER = ('[model]\ntype = "plane_strain"\n[mesh]\nsize = "2 mm"\npiezo_size = "0.5 mm"\n[array]\n'
            '[load]\nkind = "probe"\nradius = "1 mm"\ncontact = true\nshape = "cylinder"\nforce = "0.2 N"\n')


@pytest.mark.slow          # three nested meshes of a press: about 15 s
def test_a_2d_cylinder_press_estimate_names_the_part_it_cannot_compute_and_the_solve_succeeds(tmp_path, capsys):
    """A plane-strain cylinder has no 3D counterpart (infinitely long): the estimate's model-form
    part is not computed and says why; the discretisation and material parts are; exit 0.
    Through the Python API the same, without a traceback."""
    import taxel
    (tmp_path / "cyl.toml").write_text(CYLINDER)
    assert main(["solve", str(tmp_path / "cyl.toml"), "--estimate"]) == 0
    out, err = capsys.readouterr()
    assert "model form: not estimated: a cylinder" in out and "3d" not in err
    res = taxel.solve(str(tmp_path / "cyl.toml"), estimate=True)
    assert res.success
    parts = res.error.outputs["sensitivity"]
    assert parts.model_form is None and parts.discretisation > 0 and parts.material > 0
    assert any("model form: not estimated" in line for line in res.error.lines())


def test_the_python_api_refuses_a_simulated_record_that_would_not_fit():
    """taxel.measure.simulate checks the record's size before any work, as the CLI does."""
    from taxel import measure as tm
    with pytest.raises(ValueError) as err:
        tm.simulate("thesis-bench", "thesis-pzt-3x3-2d", "step", seconds=1e9)
    msg = str(err.value)
    assert msg.startswith("seconds = 1e+09:") and "GB" in msg and "half this machine's memory" in msg
    assert "\n" not in msg
