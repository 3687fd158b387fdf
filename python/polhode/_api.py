"""The public API, module by module: what the API reference documents and the tests hold to
having an Examples section each.

The names of ``polhode.__all__`` are documented at the top level (``polhode.Body``), whichever
module defines them. Every other module of the package whose name does not start with ``_``
contributes the names of its own ``__all__`` that the top level does not re-export
(``polhode.torque.Gravity``, ``polhode.dask.simulate``), so that a new module or a new name in
an ``__all__`` is documented without a list to update here. Two modules are tools rather than
API, and are described in the user guide instead: :data:`NOT_API`.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import types
from typing import Any

#: Modules of the package that are not part of the documented API, and why.
NOT_API = {
    "polhode.cli": "the `polhode` command (its options are in the user guide)",
    "polhode.bench": "the benchmark suite behind `polhode bench` and benchmarks/",
    "polhode.__main__": "`python -m polhode`",
}


def modules() -> list[str]:
    """The names of the package's public modules, ``polhode`` first."""
    import polhode

    names = ["polhode"]
    for info in pkgutil.iter_modules(polhode.__path__, "polhode."):
        leaf = info.name.rsplit(".", 1)[1]
        if not leaf.startswith("_") and info.name not in NOT_API:
            names.append(info.name)
    return names


def public_names() -> dict[str, list[str]]:
    """``{module: names}``: each public name under the module it is documented in.

    ``polhode`` holds ``polhode.__all__`` (less the modules in it); every other public module
    holds the names of its ``__all__`` that ``polhode`` does not re-export, and appears only if
    there are any.
    """
    import polhode

    top = [n for n in polhode.__all__ if not isinstance(getattr(polhode, n), types.ModuleType)]
    out = {"polhode": sorted(top, key=str.lower)}
    for name in modules()[1:]:
        module = importlib.import_module(name)
        own = [
            n
            for n in getattr(module, "__all__", [])
            if getattr(polhode, n, None) is not getattr(module, n)
        ]
        if own:
            out[name] = sorted(own, key=str.lower)
    return out


def objects() -> list[tuple[str, Any]]:
    """``(qualified name, object)`` of every public function and class."""
    found = []
    for module_name, names in public_names().items():
        module = importlib.import_module(module_name)
        for n in names:
            value = getattr(module, n)
            if inspect.isclass(value) or inspect.isfunction(value):
                found.append((f"{module_name}.{n}", value))
    return found
