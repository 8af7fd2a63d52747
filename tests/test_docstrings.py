"""The library's docstring examples run and show what they print (doctest over every module of course_dynamics),
and every public function and class of the core has one."""
from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil

import pytest

import course_dynamics

MODULES = sorted(name for _, name, _ in pkgutil.walk_packages(course_dynamics.__path__, "course_dynamics.")
                 if not name.endswith("__main__")) + ["course_dynamics"]
CORE_MODULES = [name for name in MODULES if name == "course_dynamics.core" or name.startswith("course_dynamics.core.")]

# Public names of the core that need no example of their own, each with the reason.
WITHOUT_EXAMPLE = {
    "course_dynamics.core.urdf.InertiaWarning":
        "only a URDF file with a non-physical inertia shows it; an example would have to write one",
    "course_dynamics.core.compiled.cache.CacheWarning":
        "only a cache folder other users can write to shows it; an example would have to make one",
}
# Modules whose docstrings another change is writing (newton_euler, dynamics, forward_dynamics, compiled):
# their public names still without an example. Remove a name once it has one (test_exceptions_are_current).
EXAMPLES_TO_COME = {
    "course_dynamics.core.newton_euler": (),
    "course_dynamics.core.dynamics": (),
    "course_dynamics.core.forward_dynamics": (),
    "course_dynamics.core.compiled": ("traced_sources", "code_fingerprint"),
}
EXCEPTIONS = set(WITHOUT_EXAMPLE) | {f"{module}.{name}" for module, names in EXAMPLES_TO_COME.items() for name in names}


def public_definitions(module_name: str) -> dict:
    """{qualified name: object} of the public functions and classes defined in the module (not imported into it)."""
    module = importlib.import_module(module_name)
    found = {}
    for name, obj in vars(module).items():
        is_definition = inspect.isclass(obj) or (callable(obj) and inspect.isfunction(inspect.unwrap(obj)))
        if not name.startswith("_") and is_definition and getattr(obj, "__module__", None) == module_name:
            found[f"{module_name}.{name}"] = obj
    return found


def has_example(obj) -> bool:
    return bool(doctest.DocTestParser().get_examples(obj.__doc__ or ""))


def test_there_are_examples():
    found = sum(len(doctest.DocTestFinder().find(importlib.import_module(name))) for name in MODULES)
    assert found >= 3


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples in {name} failed"


@pytest.mark.parametrize("name", CORE_MODULES)
def test_core_definitions_have_examples(name):
    missing = [qualified for qualified, obj in public_definitions(name).items()
               if not has_example(obj) and qualified not in EXCEPTIONS]
    assert not missing, f"public names without a docstring example: {', '.join(missing)}"


def test_exceptions_are_current():
    """Every excepted name still exists and still lacks an example, so the lists only shrink."""
    definitions = {}
    for name in CORE_MODULES:
        definitions.update(public_definitions(name))
    gone = sorted(name for name in EXCEPTIONS if name not in definitions)
    done = sorted(name for name in EXCEPTIONS if name in definitions and has_example(definitions[name]))
    assert not gone, f"excepted but not a public definition of the core (remove from the list): {', '.join(gone)}"
    assert not done, f"excepted but has an example now (remove from the list): {', '.join(done)}"
