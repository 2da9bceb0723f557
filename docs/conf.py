"""Sphinx configuration of the setsmooth documentation site (``make docs``).

The site's own machinery (the namespace page, the gallery pages, how the docstrings' plain-text
notation is read) is the local extension ``_ext/setsmooth_docs.py``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS.parent))   # the package of this checkout, installed or not
sys.path.insert(0, str(DOCS / "_ext"))
os.environ.setdefault("MPLBACKEND", "Agg")

import setsmooth  # noqa: E402
import setsmooth_docs  # noqa: E402

project = "setsmooth"
author = "the setsmooth developers"
copyright = "the setsmooth developers"
release = version = setsmooth.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "myst_parser",
    "setsmooth_docs",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store"]
templates_path = ["_templates"]
root_doc = "index"

# -- API reference: one page per public module, from the NumPy-style docstrings ----------------------
autosummary_generate = True
autosummary_imported_members = False
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_preserve_defaults = True
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_custom_sections = [("Attributes", "params_style")]
default_role = "py:obj"   # `name` in the docstrings is a cross-reference, resolved where it can be

# Each module's page documents the names it defines (and those a package exports from its private
# modules), as listed here for _templates/autosummary/module.rst.
autosummary_context = {"documented_members": setsmooth_docs.documented_members_by_module()}

# -- Markdown pages (the design note) ----------------------------------------------------------------
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3

# -- HTML --------------------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"setsmooth {release}"
html_static_path: list[str] = []
