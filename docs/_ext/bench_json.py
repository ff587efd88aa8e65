"""Sphinx extension: numbers in the docs read from the JSON files the benchmarks write.

A number a benchmark writes to JSON has one home, that file; the page renders it at
every build, so a re-run benchmark updates the page and no page can quote a stale
value. Two forms, in MyST Markdown:

- a table, from a renderer in TABLES named by the directive's argument:

      ```{bench-table} reference_3d.single
      ```

- one number in running text, by a path into a JSON file (relative to docs/), an
  optional factor (`*0.5`) and a format (Python's format mini-language; a trailing `%`
  prints a fraction as percent):

      {bench}`reference_3d.json:single.reference:.5f`

The files: docs/reference_3d.json (benchmarks/reference_3d.py),
docs/press_3d_reference.json and docs/press_3d_reference_through.json
(benchmarks/press_3d.py --reference, --through).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import Directive

DOCS = Path(__file__).resolve().parents[1]


def load(name: str) -> dict:
    return json.loads((DOCS / name).read_text(encoding="utf-8"))


def value(spec: str) -> str:
    """`file.json:dotted.path[:format]` -> the formatted number. A path part that is an
    integer indexes a list; a format ending in `%` prints 100 x the value with ' %'."""
    file, path, *fmt = spec.split(":", 2)
    path, _, factor = path.partition("*")          # `single.spread*0.5`: half the spread
    x = load(file)
    for part in path.split("."):
        x = x[int(part)] if isinstance(x, list) else x[part]
    if factor:
        x = x * float(factor)
    fmt = fmt[0] if fmt else ""
    if fmt.endswith("%"):
        return f"{100 * x:{fmt[:-1]}} %"
    return re.sub(r"e([+-])0(\d)", r"e\1\2", f"{x:{fmt}}")          # 2.2e-04 -> 2.2e-4


def _chains(key: str) -> tuple[list[str], list[list[str]]]:
    """The four nested chains of a 3D reference (benchmarks/reference_3d.py)."""
    ref = load("reference_3d.json")[key]
    head = ["coarse mesh (far / taxel edge / through the piezo)", "unknowns", "levels (V)", "observed order",
            "Richardson (V)"]
    timed = all("cpu_s" in f for f in ref["fits"])
    if timed:
        head.append("finest level: CPU s, peak GB")
    rows = []
    for f in ref["fits"]:
        order = f"{f['order']:.2f}" if f.get("monotone", True) else "not monotone"
        row = [f"{f['size']} / {f['piezo_size']} / {f['piezo_layers']}",
               " / ".join(str(n) for n in f["unknowns"]),
               ", ".join(f"{v:.5f}" for v in f["voltages"]), order, f"{f['reference']:.5f}"]
        if timed:
            row.append(f"{f['cpu_s'][-1]:.0f} s, {f['peak_gb'][-1]:.2f}")
        rows.append(row)
    rows.append(["**mean (the reference)**", "", "", "", f"**{ref['reference']:.5f}**"] + ([""] if timed else []))
    return head, rows


def _press_levels(file: str) -> tuple[list[str], list[list[str]]]:
    """The nested levels of the 3D press's reference (benchmarks/press_3d.py --reference,
    --through): each level's V/F at 1 N and its cost, and its distance from the
    Richardson value when the file holds one."""
    ref = load(file)
    extrapolated = ref.get("extrapolated", False)
    head = ["sizes /", "unknowns", "through the piezo", "V/F at 1 N (V/N)", "travel (mm)", "Newton iterations",
            "factorizations", "CPU s"] + (["from the Richardson value"] if extrapolated else [])
    rows = []
    for lv in ref["levels"]:
        row = [f"{lv['divide']:.2f}", f"{lv['n']:,}".replace(",", " "), f"{lv['layers']}", f"{lv['VF']:.5f}",
               f"{1e3 * lv['travel']:.3f}", f"{lv['iterations']}", f"{lv['factorizations']}", f"{lv['cpu']:,.0f}"
               .replace(",", " ")]
        if extrapolated:
            row.append(f"{100 * (lv['VF'] / ref['VF'] - 1):+.2f} %")
        rows.append(row)
    return head, rows


# name -> (the JSON file it reads, the renderer)
TABLES = {
    "reference_3d.single": ("reference_3d.json", lambda: _chains("single")),
    "reference_3d.3x3": ("reference_3d.json", lambda: _chains("3x3")),
    "press_3d_reference": ("press_3d_reference.json", lambda: _press_levels("press_3d_reference.json")),
    "press_3d_reference_through": ("press_3d_reference_through.json",
                                   lambda: _press_levels("press_3d_reference_through.json")),
}


def _paragraph(text: str) -> nodes.paragraph:
    """A cell's text; **bold** when wrapped in double stars."""
    p = nodes.paragraph()
    if text.startswith("**") and text.endswith("**") and len(text) > 4:
        p += nodes.strong(text=text[2:-2])
    else:
        p += nodes.Text(text)
    return p


def table_node(head: list[str], rows: list[list[str]]) -> nodes.table:
    table = nodes.table()
    group = nodes.tgroup(cols=len(head))
    table += group
    for _ in head:
        group += nodes.colspec(colwidth=1)
    thead = nodes.thead()
    group += thead
    body = nodes.tbody()
    group += body
    for target, cells in ((thead, [head]), (body, rows)):
        for cells_row in cells:
            row = nodes.row()
            for cell in cells_row:
                entry = nodes.entry()
                entry += _paragraph(cell)
                row += entry
            target += row
    return table


class BenchTable(Directive):
    required_arguments = 1
    has_content = False

    def run(self):
        name = self.arguments[0]
        if name not in TABLES:
            raise self.error(f"bench-table {name!r}: one of {', '.join(TABLES)}")
        file, render = TABLES[name]
        self.state.document.settings.env.note_dependency(str(DOCS / file))     # a re-run rebuilds the page
        return [table_node(*render())]


def bench_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    try:
        inliner.document.settings.env.note_dependency(str(DOCS / text.split(":", 1)[0]))
        return [nodes.Text(value(text))], []
    except (OSError, KeyError, IndexError, ValueError) as exc:
        msg = inliner.reporter.error(f"bench {text!r}: {exc}", line=lineno)
        return [inliner.problematic(rawtext, rawtext, msg)], [msg]


def setup(app):
    app.add_directive("bench-table", BenchTable)
    app.add_role("bench", bench_role)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
