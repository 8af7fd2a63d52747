"""The package's layers: every import of ours goes down (or stays within its layer), and the oracle stays apart.

Layers, lowest first: base, core, tools, output, grading, teaching, cli (see each subpackage's docstring).
Every ``import``/``from … import`` in every module is read with ``ast`` (lazy imports inside functions
included) and resolved to the module it names.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "course_dynamics"
LAYERS = ("base", "core", "tools", "output", "grading", "teaching", "cli")
# Where the Pinocchio oracle may be imported: the report and validate commands and the options that serve them.
ORACLE_USERS = {"cli/commands/report.py", "cli/commands/validate.py", "cli/commands/crosscheck.py"}
# Code that runs beside student code, in the student's interpreter: nothing of ours at all.
STANDALONE = {"grading/harness.py", "grading/integrity.py", "grading/launcher.py"}


def modules():
    return sorted(p for p in PACKAGE.rglob("*.py"))


def layer_of(relative: Path) -> str | None:
    return relative.parts[0] if len(relative.parts) > 1 and relative.parts[0] in LAYERS else None


def imported(path: Path):
    """(line, absolute dotted name) of every import in ``path``."""
    relative = path.relative_to(PACKAGE.parent)
    package = list(relative.with_suffix("").parts)[:-1]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - node.level + 1]
                module = ".".join(base + (node.module.split(".") if node.module else []))
            else:
                module = node.module or ""
            yield node.lineno, module
            for alias in node.names:  # ``from . import io`` names a module
                yield node.lineno, f"{module}.{alias.name}"


def layer_of_name(name: str) -> str | None:
    parts = name.split(".")
    return parts[1] if len(parts) > 1 and parts[0] == "course_dynamics" and parts[1] in LAYERS else None


@pytest.mark.parametrize("path", modules(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_go_down_the_layers(path):
    relative = path.relative_to(PACKAGE)
    here = layer_of(relative)
    wrong = []
    for line, name in imported(path):
        if name == "course_dynamics" and here is not None and here != "cli":
            wrong.append((line, name, "the package's top (its public API) sits above every layer"))
        there = layer_of_name(name)
        if here is not None and there is not None and LAYERS.index(there) > LAYERS.index(here):
            wrong.append((line, name, f"{there} is above {here}"))
        if name.startswith("course_dynamics_reference") and str(relative) not in ORACLE_USERS:
            wrong.append((line, name, "only report, validate and their options import the oracle"))
        if str(relative) in STANDALONE and name.startswith("course_dynamics"):
            wrong.append((line, name, "runs beside student code: imports nothing of ours"))
    assert not wrong, wrong


def test_import_course_dynamics_loads_only_the_errors_and_the_top_level_help_no_command():
    """``import course_dynamics`` loads its errors alone (not numpy); every name it gives (the chapter's API, the
    tools) loads when first asked for, each the very object its module defines; ``course-dynamics --help`` imports
    no command, no numpy and no dynamics, and a command imports its own module only."""
    import importlib
    import subprocess
    import sys

    code = "import course_dynamics, sys; print(sorted(m for m in sys.modules if m.startswith('course_dynamics')))"
    loaded = ast.literal_eval(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                             check=True).stdout)
    assert set(loaded) == {"course_dynamics", "course_dynamics.base", "course_dynamics.base.errors"}, loaded
    code = ("import sys; from course_dynamics.cli import main; sys.argv = ['course-dynamics', '--help']\n"
            "try: main()\nexcept SystemExit: pass\n"
            "print(sorted(m for m in sys.modules if m.startswith(('course_dynamics', 'numpy'))), file=sys.stderr)")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = ast.literal_eval(run.stderr.strip().splitlines()[-1])
    assert "usage: course-dynamics" in run.stdout and "identify" in run.stdout
    assert not [m for m in loaded if m.startswith(("numpy", "course_dynamics.cli.commands.", "course_dynamics.tools",
                                                   "course_dynamics.core.model"))], loaded
    code = ("import sys; from course_dynamics.cli import main; main(['info', 'ur5'])\n"
            "print(sorted(sys.modules), file=sys.stderr)")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = ast.literal_eval(run.stderr.strip().splitlines()[-1])
    assert "shoulder_pan_joint" in run.stdout    # a command loads what it uses, not the heavy libraries of others
    heavy = {"scipy", "sympy", "matplotlib", "cvxpy", "pinocchio", "course_dynamics_reference"}
    assert not heavy & {m.split(".")[0] for m in loaded} and "trimesh.base" not in loaded  # trimesh: a placeholder
    others = {"course_dynamics.tools.simulation", "course_dynamics.tools.motion", "course_dynamics.output.viewer"}
    assert not others & set(loaded), others & set(loaded)  # the flags' choices of other commands are read later

    import course_dynamics

    assert set(course_dynamics.LAZY) <= set(course_dynamics.__all__) <= set(dir(course_dynamics))
    for name, module in course_dynamics.LAZY.items():
        assert getattr(course_dynamics, name) is getattr(importlib.import_module(module), name), name
    with pytest.raises(AttributeError, match="has no attribute 'inverse_dynamic'"):
        course_dynamics.inverse_dynamic  # noqa: B018


def test_every_layer_is_a_package_with_its_rule():
    for layer in LAYERS:
        doc = ast.get_docstring(ast.parse((PACKAGE / layer / "__init__.py").read_text()))
        assert doc and "import" in doc, layer


def test_no_private_name_is_imported_across_modules():
    wrong = []
    for path in modules():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith("course_dynamics")):
                wrong += [(str(path.relative_to(PACKAGE)), node.lineno, a.name) for a in node.names
                          if a.name.startswith("_") and not a.name.startswith("__")]
    assert not wrong, wrong


def test_the_oracle_never_loads_with_the_library():
    import subprocess
    import sys

    code = ("import sys, course_dynamics, course_dynamics.tools.logs, course_dynamics.tools.simulation, "
            "course_dynamics.grading, course_dynamics.teaching.exercises\n"
            "print(sorted(m for m in sys.modules if m.startswith(('pinocchio', 'course_dynamics_reference'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]", out


MAX_LINES = 450  # a module with more lines of code than this is two modules
MAX_LINES_WITH_DOCS = 800  # and its docstrings (numpydoc sections for the API reference) do not make it a book


def docstring_lines(source: str) -> int:
    """How many lines of the source are the docstrings of the module, its classes and its functions."""
    count = 0
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(
                    first.value.value, str):
                count += first.end_lineno - first.lineno + 1
    return count


@pytest.mark.parametrize("path", modules(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_module_is_too_long_to_read(path):
    source = path.read_text()
    lines = len(source.splitlines())
    assert lines - docstring_lines(source) <= MAX_LINES and lines <= MAX_LINES_WITH_DOCS


def test_imports_of_our_own_modules_sit_at_the_top_outside_the_command_line():
    """Only the command line imports inside functions: each command loads what it alone needs (start-up time)."""
    wrong = []
    for path in modules():
        relative = path.relative_to(PACKAGE)
        if relative.parts[0] == "cli" or str(relative) in STANDALONE:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.col_offset > 0 and (
                    node.level or (node.module or "").startswith("course_dynamics")):
                wrong.append((str(relative), node.lineno))
    assert not wrong, wrong


def test_every_subpackage_is_installed():
    """A subpackage missing from pyproject's explicit list works in the checkout and fails when installed."""
    import tomllib

    listed = set(tomllib.loads((PACKAGE.parent / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    found = {".".join(p.parent.relative_to(PACKAGE.parent).parts) for p in PACKAGE.rglob("__init__.py")}
    assert found <= listed, found - listed


def _table_names(package: Path) -> set[str]:
    """The names a package's docstring table lists: each row starts with ````name````."""
    import re

    doc = ast.get_docstring(ast.parse((package / "__init__.py").read_text())) or ""
    return set(re.findall(r"^``([\w.]+)``\s", doc, re.MULTILINE))


@pytest.mark.parametrize("package", sorted(p.parent for p in PACKAGE.rglob("__init__.py") if p.parent != PACKAGE),
                         ids=lambda p: str(p.relative_to(PACKAGE)))
def test_every_module_has_a_row_in_its_packages_table(package):
    """A newcomer finds every module, and subpackage, in its package's table (or, as ``sub.module``, its parent's)."""
    names = {p.stem for p in package.glob("*.py") if p.stem not in ("__init__", "__main__")}
    names |= {p.parent.name for p in package.glob("*/__init__.py")}
    parent = _table_names(package.parent) if package.parent != PACKAGE else set()
    missing = {n for n in names if n not in _table_names(package) and f"{package.name}.{n}" not in parent}
    assert not missing, sorted(missing)


MAX_LINE = 120  # pyproject.toml's [tool.ruff] line-length: a module cannot meet MAX_LINES by packing its lines


def test_no_line_is_longer_than_the_limit():
    root = PACKAGE.parent
    paths = [*PACKAGE.rglob("*.py"), *(root / "reference").rglob("*.py")]
    long = [f"{path.relative_to(root)}:{number}: {len(line)} characters"
            for path in sorted(paths)
            for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1) if len(line) > MAX_LINE]
    assert not long, "\n".join(long)
