"""Sphinx configuration of the taxel documentation (`make docs`).

Pages are MyST Markdown; the gallery (`gallery/plot_*.py`) runs at every build
(sphinx-gallery); the key reference of the four TOML file kinds is written from
the pydantic schemas at every build (`_ext/schema_reference.py`); the API
reference comes from the docstrings (autodoc + napoleon, numpy style).
Warnings are errors (`make docs` passes -W --keep-going).
"""

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
os.environ.setdefault("MPLBACKEND", "agg")

project = "taxel"
author = "the taxel authors"
copyright = "the taxel authors"
release = version = "0.1.0"

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
    "schema_reference",
    "module_docstring",
    "bench_json",
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "gallery/**", "examples/**", "Thumbs.db", ".DS_Store"]

myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

autodoc_typehints = "description"
autodoc_member_order = "bysource"
napoleon_google_docstring = False
napoleon_numpy_docstring = True

html_theme = "alabaster"
html_title = "taxel"
html_static_path = []
html_theme_options = {"page_width": "1200px", "sidebar_width": "260px", "fixed_sidebar": False}

# Gallery: every docs/gallery/plot_*.py runs at build time; a failing example fails the build.
sphinx_gallery_conf = {
    "examples_dirs": "gallery",
    "gallery_dirs": "auto_gallery",
    "filename_pattern": r"/plot_",
    "ignore_pattern": r"__init__\.py",
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "abort_on_example_error": False,
    "only_warn_on_example_error": False,
    "remove_config_comments": True,
    "plot_gallery": os.environ.get("TAXEL_DOCS_GALLERY", "True"),
    "image_scrapers": ("matplotlib",),
    "reset_modules": ("matplotlib",),
    "show_memory": False,
    "min_reported_time": 1,
}


def _escape_bars(app, what, name, obj, options, lines):
    """Docstrings write magnitudes as |V| (plain text, as the CLI prints them);
    reStructuredText would read |V| as a substitution: escape the bars."""
    for i, line in enumerate(lines):
        if "|" in line and not line.lstrip().startswith(("|", "+")):
            lines[i] = line.replace("|", "\\|")


def setup(app):
    app.connect("autodoc-process-docstring", _escape_bars, priority=600)
