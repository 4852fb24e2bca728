"""Sphinx configuration of the supercoil documentation.

Build (the ``docs`` extra: ``pip install '.[docs]'``)::

    sphinx-build -W -b html docs /tmp/supercoil-html

Pages are Markdown (MyST) or reStructuredText. The API reference (one page per
name of ``supercoil.__all__``), the examples gallery, the theory toctree and the
benchmark page are generated at build time into ``docs/_generated/`` (not in
git) by ``docs/_ext/docgen.py``, so that they follow the code without edits.
"""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(DOCS / "_ext"))

import docgen  # noqa: E402

import supercoil  # noqa: E402

project = "supercoil"
author = "the supercoil developers"
copyright = "2026, the supercoil developers"
version = release = supercoil.__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# The generated fragments are included by api.rst and theory/index.md, not pages of their own.
# docs/generated/ holds the README's generated blocks (`supercoil docs figures`), not pages.
exclude_patterns = ["_build", "**/.ipynb_checkpoints", "_generated/api_names.rst",
                    "_generated/traces_names.rst",
                    "_generated/theory_toctree.md", "generated/**"]
root_doc = "index"

# MyST: $...$ / $$...$$ math, heading anchors (docs/theory/li-zhao.md#slope links
# from the code and README resolve to the heading "Slope").
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
myst_dmath_double_inline = True

# numpydoc renders the docstrings; members are listed by autodoc, not numpydoc.
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
numpydoc_validation_checks = set()
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"
# Broken internal references fail the -W build.
nitpicky = False

html_theme = "alabaster"
html_static_path = []
html_title = f"supercoil {release}"
html_theme_options = {"description": "double helices of twisted filaments", "fixed_sidebar": True}

docgen.generate(DOCS / "_generated")


def _process_docstring(app, what, name, obj, options, lines):
    lines[:] = [docgen.escape_pipes(line) for line in lines]


def setup(app):
    app.connect("autodoc-process-docstring", _process_docstring, priority=400)
