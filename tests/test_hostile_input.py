"""A corpus of hostile and unusual inputs across every command.

Every case must end with exit code 2 and exactly one line on stderr that starts
with "taxel: error:" and contains the words that name the key or file and the fix;
no traceback; nothing written outside the command's output folder, and a failed
command leaves no partial output.

A case: the command line (relative paths, run in an empty folder), the files to
create first, the words the message must contain, and the output folder the
command is allowed to create (None: none).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import pytest

from taxel.cli import main


@dataclass
class Case:
    id: str
    argv: list[str]
    words: tuple[str, ...]
    files: dict[str, str | bytes] = field(default_factory=dict)
    out: str | None = None          # the folder this command may write; must not exist after a failure
    setup: object = None            # callable(tmp_path) for cases files cannot express


# ------------------------------------------------------------------------- scenes
FAST = '[model]\ntype = "plane_strain"\n[mesh]\nsize = "1 mm"\npiezo_size = "0.25 mm"\n'
ARRAY = FAST + "[array]\n"


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
    scene("negative-gap", ARRAY + 'cols = 2\ngap = "-1 mm"\n', "array.gap"),
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
    scene("taxel-negative", ARRAY + "[load]\ntaxel = [-1, 0]\n", "load.taxel"),
    scene("taxel-three-numbers", ARRAY + "[load]\ntaxel = [0, 0, 0]\n", "load.taxel"),
    scene("indenter-without-radius", ARRAY + '[load]\nkind = "indenter"\n', "load.radius"),
    scene("indenter-wider-than-part", ARRAY + '[load]\nkind = "indenter"\nradius = "50 mm"\n', "load"),
    scene("indenter-offset-outside", ARRAY + '[load]\nkind = "indenter"\nradius = "1 mm"\n'
          'offset = ["40 mm", "0 mm"]\n', "load"),
    scene("between-without-neighbour", ARRAY + 'cols = 2\n[load]\nkind = "between"\n', "load.neighbour"),
    scene("between-not-adjacent", ARRAY + 'cols = 3\n[load]\nkind = "between"\nneighbour = [0, 2]\n',
          "load.neighbour"),
    scene("pressure-without-value", ARRAY + '[load]\nkind = "pressure"\n', "load.pressure"),
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
    scene("axisym-offset", ARRAY.replace('"plane_strain"', '"axisymmetric"')
          + '[load]\nkind = "indenter"\nradius = "1 mm"\noffset = ["1 mm", "0 mm"]\n', "axisymmetric"),
    scene("tolerance-2", ARRAY.replace('"plane_strain"', '"plane_strain"\ntolerance = 2'), "model.tolerance"),
    scene("fidelity-typo", ARRAY.replace('"plane_strain"', '"plane_strain"\nfidelity = "best"'), "model.fidelity"),
    scene("fidelity-auto-frequency", ARRAY.replace('"plane_strain"', '"plane_strain"\nfidelity = "auto"')
          + '[analysis]\ntype = "frequency"\n', "model.fidelity"),
    scene("outputs-crosstalk-one-taxel", ARRAY.replace('"plane_strain"', '"plane_strain"\noutputs = ["crosstalk"]'),
          "crosstalk"),
    scene("outputs-typo", ARRAY.replace('"plane_strain"', '"plane_strain"\noutputs = ["voltage"]'), "model.outputs"),
    scene("free-free", ARRAY + '[supports]\nbottom = "free"\nedges = "free"\n', "supports"),
    scene("support-typo", ARRAY + '[supports]\nbottom = "glued"\n', "supports.bottom", "glued"),
    scene("electrode-unknown", ARRAY + '[electrodes]\ntaxel_9_9 = "open"\n', "electrodes.taxel_9_9"),
    scene("electrode-bad-state", ARRAY + '[electrodes]\ntaxel_0_0 = "floating"\n', "electrodes.taxel_0_0"),
    scene("electrode-none-grounded", ARRAY + '[electrodes]\nground = "open"\n', "electrodes", "ground"),
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
          'thickness = "1 mm"}]\n[load]\nkind = "indenter"\nradius = "20 mm"\n', "load.radius", "plate"),
    scene("plate-indenter-offset-off", FAST + '[plate]\nwidth = "10 mm"\nlayers = [{material = "PVDF", '
          'thickness = "1 mm"}]\n[load]\nkind = "indenter"\nradius = "2 mm"\noffset = ["4 mm", "0 mm"]\n',
          "load.radius", "offset"),
    scene("disk-indenter-wider", FAST.replace('"plane_strain"', '"axisymmetric"') + '[plate]\nshape = "disk"\n'
          'radius = "5 mm"\nlayers = [{material = "PVDF", thickness = "1 mm"}]\n[load]\nkind = "indenter"\n'
          'radius = "6 mm"\n', "load.radius", "disk"),
    scene("3d-plate-indenter-longer", FAST.replace('"plane_strain"', '"3d"') + '[plate]\nwidth = "20 mm"\n'
          'length = "4 mm"\nlayers = [{material = "PVDF", thickness = "1 mm"}]\n[load]\nkind = "indenter"\n'
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
    Case("solve-missing-file", ["solve", "nope.toml"], ("nope.toml",)),
    Case("solve-directory", ["solve", "d"], ("d",), setup=lambda p: (p / "d").mkdir()),
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
         "tcp://127.0.0.1:9", "--quiet"], ("scheduler", "127.0.0.1:9"), {"st.toml": STUDY}, out="o"),
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
    opt("unknown-path", OPT.replace("array.gap", "array.gapp"), "gapp"),
    opt("unknown-metric", OPT.replace('"crosstalk"', '"beauty"'), "objective"),
    opt("two-objectives", OPT.replace('minimize = "crosstalk"', 'minimize = "crosstalk"\nmaximize = "sensitivity"'),
        "objective"),
    opt("constraint-syntax", OPT + '[constraints]\ngap = "= 2 mm"\n', "constraints.gap"),
    opt("constraint-nan", OPT + '[constraints]\ncrosstalk = "<= nan"\n', "constraints.crosstalk"),
    opt("constraint-abc", OPT + '[constraints]\ncrosstalk = "<= abc"\n', "constraints.crosstalk"),
    opt("constraint-infeasible", OPT + '[constraints]\ngap = ">= 10 mm"\n', "constraints.gap", "cannot be met"),
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
    opt("constraint-percent-unit", OPT + '[constraints]\ncrosstalk = "<= 5 mm"\n', "constraints.crosstalk"),
    opt("not-toml", "[[[", "op.toml"),
    Case("opt-missing-file", ["optimize", "nope.toml"], ("nope",)),
]

# ------------------------------------------------------------------------- Yeoh fit
GOOD_CSV = "strain,stress_Pa\n" + "".join(f"{e},{2e4 * e}\n" for e in (0.1, 0.2, 0.3, 0.4, 0.5))


def fit(id, content, *words, args=("--max-strain", "0.5")):
    return Case(f"fit-{id}", ["material", "fit-yeoh", "t.csv", *args], words, {"t.csv": content})


FIT = [
    fit("no-header", "1,2\n3,4\n", "t.csv", "header"),
    fit("only-strain", "strain\n0.1\n0.2\n", "t.csv", "stress"),
    fit("huge-values", "strain,stress_Pa\n" + "".join(f"{e},1e308\n" for e in (0.1, 0.2, 0.3, 0.4)), "t.csv"),
    fit("one-strain-value", "strain,stress_Pa\n" + "0.1,1000\n" * 10, "t.csv", "strain"),
    fit("invalid-rows", "strain,stress_Pa\n0.1,1\nabc,2\n0.2,x\n0.3,3\n0.4,4\n", "t.csv", "row"),
    fit("too-few", "strain,stress_Pa\n0.1,1\n0.2,2\n", "t.csv"),
    fit("negative-max-strain", GOOD_CSV, "--max-strain", args=("--max-strain", "-1")),
    fit("abc-max-strain", GOOD_CSV, "--max-strain", args=("--max-strain", "abc")),
    fit("nan-max-strain", GOOD_CSV, "--max-strain", args=("--max-strain", "nan")),
    fit("plot-missing-folder", GOOD_CSV, "no/dir", args=("--max-strain", "0.5", "--plot", "no/dir/p.png")),
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
    Case("report-not-a-result", ["report", "d", "--out", "r"], ("d",), setup=lambda p: (p / "d").mkdir(), out="r"),
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


CASES = SCENES + MATERIALS + SOLVE + STUDIES + OPTIMIZE + FIT + REPORTS


def test_the_corpus_is_large_and_covers_every_command():
    assert len(CASES) >= 150
    commands = {c.argv[0] for c in CASES if c.argv}
    assert {"solve", "mesh", "lumped", "study", "optimize", "material", "report", "demo", "examples"} <= commands
    assert len({c.id for c in CASES}) == len(CASES)


def _tree(root):
    return {p.relative_to(root) for p in root.rglob("*")}


@pytest.mark.parametrize("case", [pytest.param(c, id=c.id) for c in CASES])
def test_hostile_input_exits_2_with_one_line_and_writes_nothing(case, tmp_path, monkeypatch, capsys):
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
    assert code == 2, f"exit {code}; stderr {err!r}"
    assert len(lines) == 1 and lines[0].startswith("taxel: error:"), f"stderr: {err!r}"
    assert "Traceback" not in err
    for w in case.words:
        assert w.lower() in lines[0].lower(), f"{w!r} not in {lines[0]!r}"
    new = _tree(tmp_path) - before
    assert not new, f"a failed command left files behind: {sorted(map(str, new))[:5]}"


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
