"""Modules imported at their first use, not at the importer's: ``optimize = lazy("scipy.optimize", globals())``
reads like the module and imports it when an attribute is first asked for, then puts the module itself in the importer's
namespace under the same name (``optimize``), so that later uses are plain global lookups with nothing in between.
scipy.optimize, .special, .interpolate and .integrate take about half a second to import, and most commands (``list``,
a reproduction whose rows fit nothing, ``--help``) use none. No other module of ours is imported here (layer 0)."""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["HEAVY", "LazyModule", "lazy", "preload"]

# the subpackages imported at first use; ``preload`` them before forking workers that will all need them
HEAVY = ("scipy.optimize", "scipy.special", "scipy.interpolate", "scipy.integrate")


class LazyModule:
    """Stands for the module ``name`` in ``namespace`` until its first attribute is asked for."""

    __slots__ = ("_alias", "_name", "_namespace")

    def __init__(self, name: str, namespace: dict[str, Any]) -> None:
        self._name = name
        self._namespace = namespace
        self._alias = name.rpartition(".")[2]

    def __getattr__(self, attr: str) -> Any:  # called only for names that are not slots: the module's own
        if attr.startswith("__") or attr in LazyModule.__slots__:  # copy, pickle, introspection: no import
            raise AttributeError(attr)
        module = importlib.import_module(self._name)
        if self._namespace.get(self._alias) is self:
            self._namespace[self._alias] = module  # from now on the importer reads the module itself
        return getattr(module, attr)

    def __repr__(self) -> str:
        return f"<lazy module {self._name!r}>"


def lazy(name: str, namespace: dict[str, Any]) -> Any:
    """A stand-in for ``import name`` bound in ``namespace`` (the importer's ``globals()``) under the last part of
    ``name``; typed Any: it reads as the module."""
    return LazyModule(name, namespace)


def preload(*names: str) -> None:
    """Import ``names`` now: in a parent before it forks workers that all use them (imported once, shared by the
    forks), or before a measurement that must not include them."""
    for name in names:
        importlib.import_module(name)
