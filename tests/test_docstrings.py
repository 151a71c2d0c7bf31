"""Docs as scipy writes them (issue "Codebase 2"): every public function and method of `reference`,
`contact_model`, `records` and `analysis` has a numpydoc docstring whose Parameters section names
each of its parameters.

The walk: every public module of the packages (a leading underscore makes a module private;
`__main__` is the command line and is walked), imported in-process; in each, the public
functions and classes whose ``__module__`` is that module (a re-export, such as
`reference.solve_collision`, is checked where it is defined, once), and the public methods,
static and class methods and properties of those classes. Decorated functions are unwrapped
(`functools.lru_cache`'s ``__wrapped__``, numba's ``py_func``). A function that takes no parameter
besides self/cls needs no Parameters section. Only a function's own ``__doc__`` counts, not one
inherited from the method it overrides. Unit tier: imports only, no process.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re

import pytest

PACKAGES = ("reference", "contact_model", "records", "analysis")

#: A numpydoc section header: a title line, then a line of dashes as long as it.
_HEADER = re.compile(r"^(?P<title>[A-Z][A-Za-z ]*)\n(?P<dashes>-+)$", re.M)


def public_modules(package: str) -> list[str]:
    """The package and its public submodules (no leading underscore, `__main__` included)."""
    pkg = importlib.import_module(package)
    names = [package]
    for info in pkgutil.iter_modules(pkg.__path__):
        if info.name == "__main__" or not info.name.startswith("_"):
            names.append(f"{package}.{info.name}")
    return sorted(names)


def _unwrap(obj):
    """The Python function behind a decorator (lru_cache, numba), or None when it is none."""
    obj = getattr(obj, "py_func", obj)  # a numba dispatcher
    obj = inspect.unwrap(obj) if callable(obj) else obj
    return obj if inspect.isfunction(obj) else None


def public_functions() -> list[tuple[str, object, bool]]:
    """(module.qualname, function, is_method) of every public function and method defined in the
    packages, each once."""
    found = {}
    for package in PACKAGES:
        for name in public_modules(package):
            module = importlib.import_module(name)
            for attr, obj in vars(module).items():
                if attr.startswith("_") or getattr(obj, "__module__", None) != name:
                    continue  # private, or a re-export (checked where it is defined)
                if inspect.isclass(obj):
                    for member, value in vars(obj).items():
                        if member.startswith("_"):
                            continue
                        if isinstance(value, property):
                            value = value.fget
                        elif isinstance(value, (staticmethod, classmethod)):
                            value = value.__func__
                        fn = _unwrap(value)
                        if fn is not None:
                            found[f"{name}.{attr}.{member}"] = (fn, True)
                else:
                    fn = _unwrap(obj)
                    if fn is not None:
                        found[f"{name}.{attr}"] = (fn, False)
    return [(key, fn, is_method) for key, (fn, is_method) in sorted(found.items())]


def parameters_of(fn, is_method: bool) -> list[str]:
    """The names of `fn`'s parameters, a method's self/cls left out."""
    names = list(inspect.signature(fn).parameters)
    if is_method and names and names[0] in ("self", "cls"):
        names = names[1:]
    return names


def documented_parameters(doc: str) -> set[str] | None:
    """The names the Parameters section of a numpydoc docstring describes ('a, b : float' gives
    both, '*args' gives 'args'); None when it has no Parameters section."""
    doc = inspect.cleandoc(doc or "")
    headers = [m for m in _HEADER.finditer(doc) if len(m["dashes"]) >= len(m["title"].strip())]
    for i, m in enumerate(headers):
        if m["title"].strip() != "Parameters":
            continue
        end = headers[i + 1].start() if i + 1 < len(headers) else len(doc)
        names = set()
        for line in doc[m.end():end].splitlines():
            if not line.strip() or line[0].isspace():
                continue  # a description line (indented) or a blank one
            for name in line.split(" : ")[0].split(","):
                names.add(name.strip().lstrip("*"))
        return names
    return None


def missing_parameters(key: str, fn, is_method: bool) -> list[str]:
    """Why `fn`'s docstring falls short ([] when it does not), each sentence naming `key`."""
    wanted = parameters_of(fn, is_method)
    if not wanted:
        return []
    described = documented_parameters(fn.__doc__)
    if described is None:
        return [f"{key}: its docstring has no numpydoc Parameters section (it takes {', '.join(wanted)})"]
    return [f"{key}: parameter {name!r} is missing from its Parameters section"
            for name in wanted if name not in described]


FUNCTIONS = public_functions()


@pytest.mark.parametrize("key, fn, is_method", FUNCTIONS, ids=[key for key, _, _ in FUNCTIONS])
def test_parameters_are_documented(key, fn, is_method):
    problems = missing_parameters(key, fn, is_method)
    assert not problems, "\n".join(problems)


def test_the_walk_finds_what_it_must():
    keys = {key for key, _, _ in FUNCTIONS}
    assert len(keys) >= 120, len(keys)
    # plain functions, methods, properties, lru_cache-wrapped functions and the command lines
    for key in ("reference.collision_ode.solve_collisions", "reference.collision_ode.CollisionTable.row",
                "reference.series.paper_series_terms", "contact_model.keywords.yade_vstar",
                "contact_model.contact_pair.ContactPair.scales", "contact_model.contact_pair.ContactPair.R",
                "contact_model.damping_forms.HalfPower.solve", "reference.__main__.main",
                "contact_model.viscosity_for_k.main"):
        assert key in keys, key
    # a re-export is checked where it is defined, and nothing private is walked
    assert "reference.solve_collision" not in keys
    assert not [key for key in keys if any(part.startswith("_") and part != "__main__" for part in key.split("."))]


def _documented(K, criterion="x0"):
    """A stand-in.

    Parameters
    ----------
    K, criterion : float, str
        Both described on one line [-].
    """


def _undocumented(K, eps, *args):
    """A stand-in.

    Parameters
    ----------
    K : float
        The dissipation parameter [-].

    Returns
    -------
    eps : float
        Named here, in Returns: that does not describe the parameter.
    """


def test_the_check_names_the_function_and_the_missing_parameter():
    assert missing_parameters("m._documented", _documented, False) == []
    assert missing_parameters("m._undocumented", _undocumented, False) == [
        "m._undocumented: parameter 'eps' is missing from its Parameters section",
        "m._undocumented: parameter 'args' is missing from its Parameters section"]
    assert missing_parameters("m.f", lambda x: x, False) == [
        "m.f: its docstring has no numpydoc Parameters section (it takes x)"]
    # no parameter besides self: no section needed
    assert missing_parameters("m.C.p", lambda self: 0, True) == []
