"""Sphinx extension: the key reference pages of the four TOML file kinds.

At every build (before Sphinx reads the sources) it writes
`reference/keys/<kind>.md` from the pydantic schemas through
`taxel.cli.schema.markdown`, the generator behind `taxel schema`: the pages
cannot drift from the code. A page is rewritten only when its text changed (so an
unchanged schema does not force a rebuild).
"""

from pathlib import Path

from taxel.cli.schema import KINDS, markdown


def write_pages(app) -> None:
    folder = Path(app.srcdir) / "reference" / "keys"
    folder.mkdir(parents=True, exist_ok=True)
    for kind in KINDS:
        page = folder / f"{kind}.md"
        text = markdown(kind)
        if not page.exists() or page.read_text(encoding="utf-8") != text:
            page.write_text(text, encoding="utf-8")


def setup(app):
    app.connect("builder-inited", write_pages)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
