"""Sphinx configuration of the gyrobias documentation (`make docs`).

Stack: Sphinx + numpydoc (the docstrings are NumPy style) + autosummary (API reference read
from each module's ``__all__`` at build time, docs/_ext/apiref.py) + pydata-sphinx-theme +
sphinx-gallery (executed examples in docs/examples) + MyST Markdown (guides and explanations,
whose ```python doctest blocks are executed while the page is read, docs/_ext/mdexamples.py).
"""

from __future__ import annotations

import logging
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
os.environ.setdefault("MPLBACKEND", "Agg")

import gyrobias  # noqa: E402

project = "gyrobias"
author = "the gyrobias authors"
copyright = "the gyrobias authors, MIT OR Apache-2.0"  # noqa: A001
release = gyrobias.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "apiref_ext",
    "cliref",
    "mdexamples",
    "explore_shots",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "examples",
    "**.ipynb_checkpoints",
    "auto_examples/*.ipynb",
    "auto_examples/*.py",
]
templates_path = ["_templates"]
# Pages written by several people (and the included CHANGELOG) may skip a heading level; that is
# a style matter, not a broken page.
suppress_warnings = ["myst.header"]

# --- autodoc / autosummary / numpydoc
autosummary_generate = True
autosummary_imported_members = True
autodoc_typehints = "none"  # numpydoc's Parameters section states the types
autodoc_default_options = {"inherited-members": False}
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_show_inherited_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()
add_module_names = False

# --- MyST
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# --- sphinx-gallery: every example runs at every build; a failing example fails the build
sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "min_reported_time": 0,
    "show_signature": False,
    "write_computation_times": False,
    "matplotlib_animations": False,
    "image_scrapers": ("matplotlib",),
}

# --- HTML
html_theme = "pydata_sphinx_theme"
html_title = f"gyrobias {release}"
html_static_path: list[str] = []
html_theme_options = {
    "navigation_depth": 3,
    "show_toc_level": 2,
    "header_links_before_dropdown": 7,
    "secondary_sidebar_items": ["page-toc"],
}
html_sidebars = {"index": []}
html_show_sourcelink = False


class _EmptyGlob(logging.Filter):
    """Pages other parts of the project add (install.md, architecture.md, errors.md, guides/*)
    are picked up by glob patterns in the toctrees; a pattern with no page yet is not an error.
    (Sphinx logs this warning without a type, so ``suppress_warnings`` cannot select it.)"""

    def filter(self, record: logging.LogRecord) -> bool:
        return "didn't match any documents" not in record.getMessage()


def setup(app: object) -> None:
    logging.getLogger("sphinx.sphinx.directives.other").addFilter(_EmptyGlob())
