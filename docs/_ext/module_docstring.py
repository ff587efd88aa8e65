"""Sphinx extension: ``{module-docstring} taxel.fem.assembly`` shows a module's
docstring (its physics: weak form, equations, units, assumptions) as preformatted
text, read at build time from the installed package, so a theory page cannot
drift from the code it describes. A caption names the module and its file."""

import importlib
import inspect
from pathlib import Path

from docutils import nodes
from sphinx.util.docutils import SphinxDirective


class ModuleDocstring(SphinxDirective):
    required_arguments = 1
    has_content = False

    def run(self):
        name = self.arguments[0]
        module = importlib.import_module(name)
        doc = inspect.getdoc(module)
        if not doc:
            raise self.error(f"{name} has no docstring")
        where = Path(inspect.getfile(module))
        parts = where.parts
        top = max(i for i, p in enumerate(parts) if p in ("fem", "meshing", "taxel", "optimize", "studies", "reports"))
        rel = "/".join(parts[top:])
        caption = nodes.paragraph()
        caption += nodes.strong(text=name)
        caption += nodes.Text(f" ({rel}), from its docstring:")
        block = nodes.literal_block(doc, doc)
        block["language"] = "text"
        return [caption, block]


def setup(app):
    app.add_directive("module-docstring", ModuleDocstring)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
