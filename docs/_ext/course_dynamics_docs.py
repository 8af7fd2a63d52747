"""Two directives that generate the site's references from the code itself, so neither can fall behind it.

``.. layer-api:: core`` — the API reference of one layer: the package's own docstring (its table of modules),
then one section per module with ``automodule`` over the names of its ``__all__`` that it defines (a name
re-exported from elsewhere is a link to where it is defined, never a second description).

``.. cli-reference::`` — one section per ``course-dynamics`` command, read from the parsers that the command
line itself builds: the command's description, its ``--help`` text verbatim, and the example commands of the
site's pages that use it (a command no page shows is a warning, and the build treats warnings as errors).
"""
from __future__ import annotations

import ast
import importlib
import inspect
import os
import pkgutil
import re
from pathlib import Path

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

LOG = logging.getLogger(__name__)
# Files a reader brings (shown for the syntax): a command naming one is not run by the tests, so it is never
# listed as an example of a command either (tests/test_documentation_examples.py reads this).
PLACEHOLDERS = ("my_robot.urdf", "torques.csv")
HELP_COLUMNS = "80"  # the width the --help texts are shown at (argparse reads $COLUMNS)


def defined_in_module(module) -> tuple[list[str], list[str]]:
    """(names of ``__all__`` the module defines, in the order of its source; names it re-exports from elsewhere)."""
    lines = {}
    try:
        for node in ast.parse(inspect.getsource(module)).body:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(
                node, ast.AnnAssign) else []
            names = [t.id for t in targets if isinstance(t, ast.Name)] + [getattr(node, "name", "")]
            lines |= {n: node.lineno for n in names if n and n not in lines}
    except (OSError, TypeError):
        pass
    own, elsewhere = [], []
    for name in getattr(module, "__all__", ()):
        obj = getattr(module, name)
        origin = getattr(obj, "__module__", None) if (inspect.isclass(obj) or inspect.isroutine(obj)) else None
        if inspect.ismodule(obj):
            continue
        if origin == module.__name__ or (origin is None and name in lines):
            own.append(name)
        elif origin is not None or imported_from(module, name) is not None:
            elsewhere.append(name)
    return sorted(own, key=lambda n: lines.get(n, 10 ** 9)), elsewhere


def imported_from(module, name: str) -> str | None:
    """The name of the module of ours that a ``from … import name`` line of the module takes it from, or None."""
    for node in ast.parse(inspect.getsource(module)).body:
        if isinstance(node, ast.ImportFrom) and any(a.name == name and a.asname is None for a in node.names):
            base = module.__name__ if module.__file__.endswith("__init__.py") else module.__name__.rpartition(".")[0]
            for _ in range(node.level - 1):
                base = base.rpartition(".")[0]
            target = f"{base}.{node.module}" if node.level and node.module else base if node.level else node.module
            return target if target.startswith("course_dynamics") else None
    return None


def target_of(module, name: str) -> str:
    """Where a re-exported name is documented: its defining module (a value: the module it is imported from)."""
    obj = getattr(module, name)
    if inspect.isclass(obj) or inspect.isroutine(obj):
        return f"{obj.__module__}.{obj.__qualname__}"
    return f"{imported_from(module, name)}.{name}"


def directive_of(obj) -> str:
    if inspect.isclass(obj):
        return "autoexception" if issubclass(obj, BaseException) else "autoclass"
    return "autofunction" if inspect.isroutine(obj) else "autodata"


def role_of(obj) -> str:
    return {"autoexception": "exc", "autoclass": "class", "autofunction": "func"}.get(directive_of(obj), "data")


def module_rst(name: str, underline: str, title: bool = True) -> list[str]:
    """The reST of one module's reference: its docstring, then each name it defines (a class with its members)."""
    module = importlib.import_module(name)
    own, elsewhere = defined_in_module(module)
    lines = [name, underline * len(name), ""] if title else []
    lines += [f".. automodule:: {name}", ""]
    for attribute in own:
        obj = getattr(module, attribute)
        lines += [f".. {directive_of(obj)}:: {name}.{attribute}"]
        lines += ["   :members:"] if inspect.isclass(obj) else []
        lines += ["   :show-inheritance:"] if inspect.isclass(obj) and obj.__bases__ != (object,) else []
        lines += ["   :no-value:"] if directive_of(obj) == "autodata" else []
        lines += [""]
    if elsewhere:
        links = ", ".join(f":{role_of(getattr(module, n))}:`~{target_of(module, n)}`" for n in elsewhere)
        lines += [f"Offered here too, documented where they are defined: {links}.", ""]
    return lines


def submodules(package: str) -> list[str]:
    path = importlib.import_module(package).__path__
    return sorted(n for _, n, _ in pkgutil.walk_packages(path, package + ".") if not n.endswith("__main__"))


class LayerApi(SphinxDirective):
    """``.. layer-api:: <layer>``: the package ``course_dynamics.<layer>`` and every module in it."""
    required_arguments = 1

    def run(self):
        package = f"course_dynamics.{self.arguments[0]}" if self.arguments[0] != "course_dynamics" else "course_dynamics"
        lines = module_rst(package, "-", title=False)
        names = [package]
        if package not in ("course_dynamics", "course_dynamics.cli"):  # the commands: see the CLI reference
            for name in submodules(package):
                lines += module_rst(name, "-")
                names.append(name)
        for name in names:  # the page is read again when any of its modules changes
            self.env.note_dependency(importlib.import_module(name).__file__)
        node = nodes.section()
        node.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, source=f"<layer-api {package}>"), node)
        return node.children


def page_examples(docs: Path) -> dict[str, list[tuple[str, str]]]:
    """{command: [(page, example line)]} from every ``sh`` block of the site's pages."""
    found: dict[str, list[tuple[str, str]]] = {}
    for page in sorted(docs.rglob("*.md")):
        if "_build" in page.parts:
            continue
        docname = page.relative_to(docs).with_suffix("").as_posix()
        for block in re.findall(r"```sh\n(.*?)```", page.read_text(), re.S):
            for line in block.replace("\\\n", " ").splitlines():
                line = line.strip()
                words = line.split()
                if len(words) >= 2 and words[0] == "course-dynamics" and not words[1].startswith("-") and not any(
                        p in line for p in PLACEHOLDERS):
                    command, sharp, comment = line.partition("  #")  # "  # exit 1": as the tests read it
                    shown = " ".join(command.split()) + (f"  #{comment}" if sharp else "")
                    found.setdefault(words[1], []).append((docname, shown))
    return found


class CliReference(SphinxDirective):
    """``.. cli-reference::``: every command of ``course-dynamics``, from ``course_dynamics.cli.build_parser``."""

    def run(self):
        from course_dynamics.cli import build_parser

        before = os.environ.get("COLUMNS")
        os.environ["COLUMNS"] = HELP_COLUMNS
        try:
            parser = build_parser()
            commands = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction").choices
            lines = [".. code-block:: text", ""] + ["   " + line for line in parser.format_help().splitlines()] + [""]
            examples = page_examples(Path(self.env.srcdir))
            import course_dynamics.cli as cli

            for path in [*Path(cli.__file__).parent.rglob("*.py"), *Path(self.env.srcdir).rglob("*.md")]:
                self.env.note_dependency(str(path))  # the parsers, and the pages the examples come from
            for name, sub in commands.items():
                title = f"course-dynamics {name}"
                lines += [f".. _cli-{name}:", "", title, "-" * len(title), "", sub.description or "", "",
                          ".. code-block:: text", ""]
                lines += ["   " + line for line in sub.format_help().splitlines()] + [""]
                shown = examples.get(name, [])
                if not shown:
                    LOG.warning(f"course-dynamics {name} has no example on any page of the site",
                                location=self.get_location())
                seen = []
                for docname, line in shown:
                    if line not in (s for _, s in seen) and len(seen) < 4:
                        seen.append((docname, line))
                if seen:
                    lines += ["Examples (each runs in the tests):", "", ".. code-block:: sh", ""]
                    lines += ["   " + line for _, line in seen] + [""]
                    pages = sorted({d for d, _ in seen})
                    lines += ["Shown with their context on " + ", ".join(f":doc:`/{d}`" for d in pages) + ".", ""]
        finally:
            if before is None:
                os.environ.pop("COLUMNS", None)
            else:
                os.environ["COLUMNS"] = before
        node = nodes.section()
        node.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, source="<cli-reference>"), node)
        return node.children


def resolve_re_export(app, env, node, contnode):
    """A reference to a name where a package re-exports it (``course_dynamics.inverse_dynamics``) leads to where
    the name is defined and documented; any other missing reference stays missing (a warning, so an error)."""
    if node.get("refdomain") != "py" or not node.get("reftarget", "").startswith("course_dynamics"):
        return None
    module_name, _, name = node["reftarget"].lstrip("~").rpartition(".")
    try:
        module = importlib.import_module(module_name)
        getattr(module, name)
    except (ImportError, AttributeError, ValueError):
        return None
    target = target_of(module, name)
    if target == node["reftarget"]:
        return None
    return env.domains["py"].resolve_xref(env, node["refdoc"], app.builder, node["reftype"], target, node, contnode)


def drop_what_no_page_uses(app, exception):
    """The built site holds what its pages use: no empty ``_sources`` folder, no source maps of the theme."""
    if exception is not None or app.builder.format != "html":
        return
    out = Path(app.outdir)
    for source_map in (out / "_static").rglob("*.map"):
        source_map.unlink()
    sources = out / "_sources"
    if sources.is_dir() and not any(sources.iterdir()):
        sources.rmdir()


def colons_are_prose(app, what, name, obj, options, lines):
    """A value's or property's first line is prose here: napoleon would read "text: more" as "type: description"
    (and cross-reference the text as a type), so it is moved down one line, where napoleon reads no type."""
    if what in ("attribute", "data", "property") and lines and ":" in lines[0]:
        lines.insert(0, "")


def setup(app):
    app.add_directive("layer-api", LayerApi)
    app.add_directive("cli-reference", CliReference)
    app.connect("missing-reference", resolve_re_export)
    app.connect("build-finished", drop_what_no_page_uses)
    app.connect("autodoc-process-docstring", colons_are_prose, priority=400)  # before napoleon's (500)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
