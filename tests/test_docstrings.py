"""The library's docstring examples run and show what they print (doctest over every module of course_dynamics),
and every public function and class of the core has one."""
from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil

import pytest

import course_dynamics

# The native loop's extension (core.compiled._looped, built at installation) is private: its functions are
# documented where they are used, on core.compiled.looped.Looped and in core.compiled.steps.
MODULES = sorted(name for _, name, _ in pkgutil.walk_packages(course_dynamics.__path__, "course_dynamics.")
                 if not name.endswith("__main__") and not name.split(".")[-1].startswith("_")) + ["course_dynamics"]
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


# ---- The API reference: every module says what it offers, and every offered name is documented in numpydoc ----
# The API is each module's ``__all__``: what a user's script, a notebook or another layer's user calls. Names used
# only between the package's own modules stay out of it (and out of the reference). The CLI's Python API is
# ``course_dynamics.cli`` (main, build_parser); its commands are documented by the CLI reference, from the parsers.
API_LAYERS = ("base", "core", "tools", "output", "grading", "teaching")
API_MODULES = ["course_dynamics", "course_dynamics.cli"] + [
    name for name in MODULES if name.split(".")[1:2] and name.split(".")[1] in API_LAYERS]


def bare_entries(doc: str) -> list[str]:
    """The entries of Parameters, Returns, Yields and Raises that say nothing: a parameter without `` : type``,
    or any entry without an indented description below it; and such a section with no entry at all."""
    import re

    lines = inspect.cleandoc(doc or "").splitlines()
    wrong, title = [], None
    entries: dict[str, int] = {}
    for here, line in enumerate(lines):
        underline = lines[here + 1] if here + 1 < len(lines) else ""
        if line.strip() and re.fullmatch(r"-{3,}", underline.strip()):
            title = line.strip()
            entries[title] = 0
            continue
        if title not in ("Parameters", "Returns", "Yields", "Raises") or not line or line[0].isspace() or \
                re.fullmatch(r"-{3,}", line.strip()):
            continue
        entries[title] += 1
        described = here + 1 < len(lines) and lines[here + 1][:1].isspace() and lines[here + 1].strip()
        if title == "Parameters" and " : " not in line and not line.rstrip().endswith(" :"):
            wrong.append(f"Parameters entry '{line.strip()}' gives no type")
        elif not described and not (title == "Parameters" and " — " in line):
            wrong.append(f"{title} entry '{line.strip()}' has no description")
    wrong += [f"an empty {t} section" for t, n in entries.items()
              if n == 0 and t in ("Parameters", "Returns", "Yields", "Raises")]
    return wrong


def sections(doc: str) -> dict[str, list[str]]:
    """A numpydoc docstring's sections: {title: the entries' names}, an entry being a line at the section's indent
    (``name : type`` or ``name, other : type``; ``*args`` and ``**kwargs`` as written)."""
    import re

    lines = inspect.cleandoc(doc or "").splitlines()
    found: dict[str, list[str]] = {}
    title = None
    for here, line in enumerate(lines):
        underline = lines[here + 1] if here + 1 < len(lines) else ""
        if line.strip() and re.fullmatch(r"-{3,}", underline.strip()) and len(underline.strip()) >= len(line.strip()):
            title = line.strip()
            found[title] = []
        elif title and line and not line[0].isspace() and not re.fullmatch(r"-{3,}", line.strip()):
            head = line.split(" : ")[0].split(" — ")[0].strip()
            found[title] += [n.strip() for n in head.split(",") if n.strip()]
    return found


def _raises(node) -> bool:
    """The function's own body raises something (a bare ``raise`` re-raises; nested functions are not its body)."""
    import ast

    stack = list(node.body)
    while stack:
        here = stack.pop()
        if isinstance(here, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
            continue
        if isinstance(here, ast.Raise) and here.exc is not None:
            return True
        stack.extend(ast.iter_child_nodes(here))
    return False


def _returns_a_value(node) -> bool:
    import ast

    stack = list(node.body)
    while stack:
        here = stack.pop()
        if isinstance(here, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
            continue
        if isinstance(here, ast.Return) and here.value is not None and not (
                isinstance(here.value, ast.Constant) and here.value.value is None):
            return True
        if isinstance(here, (ast.Yield, ast.YieldFrom)):
            return True
        stack.extend(ast.iter_child_nodes(here))
    return False


def function_problems(function, is_method: bool = False) -> list[str]:
    """What the numpydoc docstring of a function (or method) lacks: a summary, a Parameters entry for each
    parameter (and none for a parameter it does not have), Returns (or Yields) when it returns a value, Raises
    when its own body raises."""
    import ast
    import textwrap

    function = inspect.unwrap(function)
    doc = function.__doc__ or ""
    if not doc.strip():
        return ["no docstring"]
    found = sections(doc)
    problems = bare_entries(doc)
    signature = inspect.signature(function)
    names = []
    for i, parameter in enumerate(signature.parameters.values()):
        if is_method and i == 0 and parameter.name in ("self", "cls"):
            continue
        names.append({inspect.Parameter.VAR_POSITIONAL: "*", inspect.Parameter.VAR_KEYWORD: "**"}.get(
            parameter.kind, "") + parameter.name)
    listed = found.get("Parameters", [])
    missing = [n for n in names if n not in listed and n.lstrip("*") not in listed]
    unknown = [n for n in listed if n not in names and "*" + n not in names and "**" + n not in names]
    if missing:
        problems.append(f"Parameters lacks {', '.join(missing)}")
    if unknown:
        problems.append(f"Parameters lists {', '.join(unknown)}, which it does not take")
    try:
        node = ast.parse(textwrap.dedent(inspect.getsource(function))).body[0]
    except (OSError, TypeError, IndexError):
        return problems
    if _returns_a_value(node) and not ({"Returns", "Yields"} & set(found)):
        problems.append("no Returns section")
    if _raises(node) and "Raises" not in found:
        problems.append("no Raises section")
    return problems


def class_problems(cls) -> list[str]:
    """What a class's docstring lacks: a summary; for a dataclass, a Parameters (or Attributes) entry per field;
    for a class with its own ``__init__``, that method's parameters; and what each public method lacks."""
    import dataclasses

    doc = cls.__doc__ or ""
    if not doc.strip() or (dataclasses.is_dataclass(cls) and doc.startswith(cls.__name__ + "(")):
        return ["no docstring"]
    problems = bare_entries(doc)
    found = sections(doc)
    listed = found.get("Parameters", []) + found.get("Attributes", [])
    fields = [f.name for f in dataclasses.fields(cls) if f.init] if dataclasses.is_dataclass(cls) else list(
        getattr(cls, "_fields", ())) if issubclass(cls, tuple) else None  # a dataclass's or a NamedTuple's
    if fields is not None:
        missing = [name for name in fields if name not in listed]
        if missing:
            problems.append(f"Parameters/Attributes lacks the fields {', '.join(missing)}")
    elif "__init__" in vars(cls) and not issubclass(cls, BaseException):
        init = vars(cls)["__init__"]
        init_doc = init.__doc__ if (init.__doc__ or "").strip() else doc
        problems += [f"__init__: {p}" for p in function_problems(_with_doc(init, init_doc), is_method=True)
                     if not p.startswith("no Re")]
    for name, member in vars(cls).items():
        if name.startswith("_"):
            continue
        if isinstance(member, (staticmethod, classmethod)):
            problems += [f"{name}: {p}" for p in function_problems(member.__func__,
                                                                   is_method=isinstance(member, classmethod))]
        elif inspect.isfunction(member):
            problems += [f"{name}: {p}" for p in function_problems(member, is_method=True)]
        elif isinstance(member, property) and not (member.__doc__ or "").strip():
            problems.append(f"{name}: no docstring")
    return problems


def _with_doc(function, doc):
    """The function itself when it carries the doc; otherwise a stand-in with its signature and the class's doc."""
    if function.__doc__ == doc:
        return function

    def stand_in(*args, **kwargs):
        pass
    stand_in.__signature__ = inspect.signature(function)
    stand_in.__doc__ = doc
    return stand_in


def constant_has_doc(module, name: str) -> bool:
    """A module-level value in ``__all__`` carries a ``#:`` comment above it or a string below it (autodoc shows
    both)."""
    import ast

    source = inspect.getsource(module)
    lines = source.splitlines()
    tree = ast.parse(source)
    for i, node in enumerate(tree.body):
        targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(
            node, ast.AnnAssign) else []
        if any(getattr(t, "id", None) == name for t in targets):
            above = lines[node.lineno - 2].strip() if node.lineno >= 2 else ""
            after = tree.body[i + 1] if i + 1 < len(tree.body) else None
            below = isinstance(after, ast.Expr) and isinstance(getattr(after, "value", None), ast.Constant) and \
                isinstance(after.value.value, str)
            return above.startswith("#:") or below
    origin = imported_from(module, name)
    return origin is not None and constant_has_doc(origin, name)


def imported_from(module, name: str):
    """The module of ours a ``from … import name`` line of the module takes the name from, or None."""
    import ast

    for node in ast.parse(inspect.getsource(module)).body:
        if isinstance(node, ast.ImportFrom) and any(a.name == name and a.asname is None for a in node.names):
            base = module.__name__ if module.__file__.endswith("__init__.py") else module.__name__.rpartition(".")[0]
            for _ in range(node.level - 1):
                base = base.rpartition(".")[0]
            target = f"{base}.{node.module}" if node.level and node.module else base if node.level else node.module
            return importlib.import_module(target) if target.startswith("course_dynamics") else None
    return None


@pytest.mark.parametrize("name", API_MODULES)
def test_every_module_declares_its_api(name):
    module = importlib.import_module(name)
    assert isinstance(getattr(module, "__all__", None), (list, tuple)), f"{name} has no __all__"
    absent = [n for n in module.__all__ if not hasattr(module, n)]
    assert not absent, f"{name}.__all__ names what the module lacks: {absent}"


@pytest.mark.parametrize("name", API_MODULES)
def test_every_name_of_the_api_has_a_numpydoc_docstring(name):
    module = importlib.import_module(name)
    if not (module.__doc__ or "").strip():
        pytest.fail(f"{name} has no module docstring")
    problems = []
    for attribute in getattr(module, "__all__", ()):
        obj = getattr(module, attribute)
        defined_here = getattr(obj, "__module__", None) == name
        if inspect.isclass(obj) and defined_here:
            problems += [f"{attribute}: {p}" for p in class_problems(obj)]
        elif inspect.isfunction(inspect.unwrap(obj)) and defined_here:
            problems += [f"{attribute}: {p}" for p in function_problems(obj)]
        elif not (inspect.isclass(obj) or callable(obj) or inspect.ismodule(obj)) and not constant_has_doc(
                module, attribute):
            problems.append(f"{attribute}: a value with neither a '#:' comment above it nor a string below it")
    assert not problems, f"{name}:\n  " + "\n  ".join(problems)
