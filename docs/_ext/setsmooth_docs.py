"""The documentation site's own machinery, a local Sphinx extension (docs/conf.py loads it).

* the page of the public namespace (``api/namespace.rst``), written from ``setsmooth.__all__``;
* the gallery's pages (``gallery/generated/``), written from the examples' docstrings and figures;
* which members each module's page documents (`documented_members_by_module`, for the autosummary
  template);
* how the docstrings' plain-text notation is read as reST (`adapt_docstring`), and which bare
  symbols stay unlinked (`PythonDomain`).
"""

from __future__ import annotations

import ast
import importlib
import inspect
import pkgutil
import re
from pathlib import Path

from sphinx.domains.python import PythonDomain as _SphinxPythonDomain
from sphinx.pycode import ModuleAnalyzer
from sphinx.util import logging

import setsmooth

DOCS = Path(__file__).resolve().parent.parent
logger = logging.getLogger(__name__)


def _public_home(modname: str) -> str:
    """The module whose page documents what ``modname`` defines: itself, or for a private module
    (``setsmooth.sets.reduction._base``) the public package that exports its names."""
    parts = modname.split(".")
    while any(part.startswith("_") for part in parts):
        parts.pop()
    return ".".join(parts)


def documented_members(modname: str) -> str:
    """The members the page of ``modname`` documents, comma-separated: each public name once, where
    it is defined, or in the public package that exports it from a private module."""
    module = importlib.import_module(modname)
    exported = getattr(module, "__all__", None)
    names = exported if exported is not None else [n for n in vars(module) if not n.startswith("_")]
    attr_docs = ModuleAnalyzer.for_module(modname).find_attr_docs()
    try:
        source = inspect.getsource(module)
    except (OSError, TypeError):
        source = ""
    keep = []
    for name in dict.fromkeys(names):
        obj = getattr(module, name, None)
        if obj is None or inspect.ismodule(obj):
            continue
        home = getattr(obj, "__module__", None) if (inspect.isclass(obj) or inspect.isroutine(obj)) else None
        if home is not None:
            documented = exported is not None or obj.__doc__
            if _public_home(home) == modname and documented:
                keep.append(name)
        elif ("", name) in attr_docs or (exported is not None and
                                          re.search(rf"^{re.escape(name)}\b\s*(:[^=\n]*)?=", source, re.M)):
            keep.append(name)
    return ", ".join(keep)



def documented_members_by_module() -> dict[str, str]:
    """`documented_members` of every public module of setsmooth, as data (a picklable config value)."""
    names = ["setsmooth"] + [info.name for info in pkgutil.walk_packages(setsmooth.__path__, "setsmooth.")]
    return {name: documented_members(name) for name in names
            if not any(part.startswith("_") for part in name.split("."))}

def _data_home(name: str, obj: object) -> str:
    """The public module whose page documents the constant ``name`` (the same object)."""
    for modname, members in documented_members_by_module().items():
        if name in members.split(", ") and getattr(importlib.import_module(modname), name, None) is obj:
            return modname
    raise LookupError(f"setsmooth.{name} is documented in no public module")


def _namespace_page(app) -> None:
    """Write ``api/namespace.rst``: every name of ``import setsmooth as ss``, linked to its module."""
    rows = []
    for name in dict.fromkeys(setsmooth.__all__):          # one row per name, in the namespace's order
        obj = getattr(setsmooth, name)
        if isinstance(obj, type(setsmooth)):               # a module exposed as a name
            rows.append((name, f":py:mod:`{obj.__name__}`", "module"))
            continue
        module = getattr(obj, "__module__", None)
        qualname = getattr(obj, "__qualname__", None)
        if module and qualname:
            module = _public_home(module)
            kind = "class" if isinstance(obj, type) else "function"
            rows.append((name, f":py:obj:`{module}.{qualname}`", kind))
        else:                                              # a constant (a reduction pipeline)
            rows.append((name, f":py:data:`{_data_home(name, obj)}.{name}`", type(obj).__name__))
    lines = [
        ".. This page is written by docs/_ext/setsmooth_docs.py from setsmooth.__all__; do not edit it.",
        "",
        "The public namespace",
        "====================",
        "",
        "``import setsmooth as ss`` exposes the names below (imported on first use). Each is defined, and",
        "documented, in the module it links to.",
        "",
        ".. list-table::",
        "   :header-rows: 1",
        "   :widths: 25 55 20",
        "",
        "   * - ``ss.`` name",
        "     - defined in",
        "     - kind",
    ]
    for name, target, kind in rows:
        lines += [f"   * - ``{name}``", f"     - {target}", f"     - {kind}"]
    _write_if_changed(DOCS / "api" / "namespace.rst", "\n".join(lines) + "\n")


# The docstrings are written to read as plain text (``help()``), with the papers' notation: |ξ| ≤ h,
# `ConvexSet`s. Two habits of that notation mean something else in reST; the docstrings stay as they
# are and are adapted here, outside literal and doctest blocks and inline literals: a bar is a bar, not
# a substitution reference, and a plural `Name`s is the reference plus "s".
_INLINE_LITERAL = re.compile(r"(``.+?``)")
_PLURAL = re.compile(r"(`[^`\s][^`]*`)(s\b)")


def _plain_text_notation(line: str) -> str:
    parts = _INLINE_LITERAL.split(line)
    for i in range(0, len(parts), 2):                       # the even parts are outside inline literals
        text = parts[i].replace("|", "\\|")
        parts[i] = _PLURAL.sub(r"\1\\ \2", text)
    return "".join(parts)


def adapt_docstring(app, what, name, obj, options, lines: list[str]) -> None:
    literal_indent = None            # indentation of the line that opened a literal block ("::")
    in_doctest = False
    for i, line in enumerate(lines):
        stripped = line.strip()
        indent = len(line) - len(line.lstrip())
        if literal_indent is not None:
            if not stripped or indent > literal_indent:
                continue
            literal_indent = None
        if in_doctest:
            if stripped:
                continue
            in_doctest = False
        if stripped.startswith(">>>"):
            in_doctest = True
            continue
        lines[i] = _plain_text_notation(line)
        if stripped.endswith("::"):
            literal_indent = indent


def _write_if_changed(path: Path, text: str) -> None:
    if not path.exists() or path.read_text() != text:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def _docstring_as_rst(doc: str) -> list[str]:
    """An example's docstring as reST: its plain-text notation adapted, indented formulas literal."""
    lines, out = [_plain_text_notation(line) for line in doc.splitlines()], []
    paragraph_start = ""
    for i, line in enumerate(lines):
        opens_block = (line.startswith(" ") and i > 0 and not lines[i - 1].strip()
                       and not paragraph_start.lstrip().startswith(("* ", "- ")))
        if opens_block and (not out or out[-2:] != ["::", ""]):
            out += ["::", ""]
        if line.strip() and (i == 0 or not lines[i - 1].strip()) and not line.startswith(" "):
            paragraph_start = line
        out.append(line)
    return out


def _gallery_pages(app) -> None:
    """Write ``gallery/generated/<example>.rst`` for every example whose figure is in gallery/images.

    The figures are the examples' own output (``make examples`` writes them to examples/out/), copied
    to docs/gallery/images/ so that the site builds without running the examples.
    """
    examples = DOCS.parent / "examples"
    for image in sorted((DOCS / "gallery" / "images").glob("*.png")):
        source = examples / f"{image.stem}.py"
        if not source.exists():
            continue
        tree = ast.parse(source.read_text(encoding="utf-8"))
        doc = ast.get_docstring(tree) or image.stem
        code_from = tree.body[0].end_lineno + 1 if ast.get_docstring(tree) else 1   # the docstring is above
        title, _, body = doc.partition("\n")
        lines = [
            ".. This page is written by docs/_ext/setsmooth_docs.py from the example's docstring; do not edit it.",
            "",
            title, "=" * len(title) * 2, "",
            *_docstring_as_rst(body.strip()), "",
            f".. image:: ../images/{image.name}",
            f"   :alt: the figure of examples/{source.name}",
            "",
            f"Run it with ``python examples/{source.name}`` (it writes ``examples/out/{image.name}``).",
            "",
            f".. literalinclude:: ../../../examples/{source.name}",
            "   :language: python",
            f"   :lines: {code_from}-",
            "",
        ]
        _write_if_changed(DOCS / "gallery" / "generated" / f"{image.stem}.rst", "\n".join(lines))


class PythonDomain(_SphinxPythonDomain):
    """The Python domain, with two readings of the docstrings' bare `names`.

    * A class or constant named from another module (`ConvexSet` in a filter's docstring, `Girard`
      in the reduction package's) links to its definition when exactly one object of that name is
      documented; likewise a dotted name (`ConvexSet.interval_hull`).
    * A symbol of one or two characters (the ``n`` and ``ng`` of ``shape (n, ng)``, ``lo``, ``hi``)
      that several classes' attributes would answer is left unlinked: it names a dimension or a
      bound, not one of those attributes.
    """

    def find_obj(self, env, modname, classname, name, type, searchmode=0):
        matches = super().find_obj(env, modname, classname, name, type, searchmode)
        if searchmode == 1 and len(matches) > 1 and len(name) <= 2:
            return []
        if not matches and searchmode == 0 and (name[:1].isupper() or "." in name):
            fuzzy = super().find_obj(env, modname, classname, name, type, 1)
            if len(fuzzy) == 1:
                return fuzzy
        return matches

def _check_api_index(app) -> None:
    """Warn (an error under ``-W``) when a public module of setsmooth is missing from api/index.rst."""
    listed = set(re.findall(r"^\s+(setsmooth\.\w+)\s*$", (DOCS / "api" / "index.rst").read_text(), re.M))
    for info in pkgutil.iter_modules(setsmooth.__path__, "setsmooth."):
        if not info.name.rsplit(".", 1)[-1].startswith("_") and info.name not in listed:
            logger.warning(f"{info.name} is missing from the API reference (docs/api/index.rst)")


def setup(app):
    app.add_domain(PythonDomain, override=True)
    app.connect("builder-inited", _namespace_page, priority=400)   # before autosummary's stubs
    app.connect("builder-inited", _gallery_pages, priority=400)
    app.connect("builder-inited", _check_api_index, priority=400)
    app.connect("autodoc-process-docstring", adapt_docstring, priority=600)   # after napoleon
    return {"parallel_read_safe": True, "parallel_write_safe": True}
