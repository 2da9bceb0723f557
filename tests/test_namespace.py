"""The public namespace `setsmooth` is one list (`setsmooth.__all__`), each name taken from the
``__all__`` of the submodule that defines it, and the static view (the ``TYPE_CHECKING`` imports that
IDEs and type checkers read) names the same things."""

from __future__ import annotations

import ast
from importlib import import_module
from pathlib import Path

import setsmooth as ss


def test_every_public_name_resolves_to_its_submodules_export():
    assert len(ss.__all__) == len(set(ss.__all__))  # no name listed twice
    for name, module in ss._EXPORTS.items():
        sub = import_module(module, "setsmooth")
        assert name in sub.__all__, (name, module)
        assert getattr(ss, name) is getattr(sub, name)
    for name, module in ss._MODULES.items():
        assert getattr(ss, name) is import_module(module, "setsmooth")


def test_the_static_imports_name_the_same_public_names():
    tree = ast.parse(Path(ss.__file__).read_text())
    guarded = next(node for node in tree.body if isinstance(node, ast.If)
                   and getattr(node.test, "id", None) == "TYPE_CHECKING")
    static = {alias.asname or alias.name for node in guarded.body
              if isinstance(node, ast.ImportFrom) for alias in node.names}
    assert static == set(ss.__all__)


def test_star_import_gives_exactly_the_namespace():
    scope: dict = {}
    exec("from setsmooth import *", scope)
    assert set(scope) - {"__builtins__"} == set(ss.__all__)
