"""The documentation site (docs/) builds offline with warnings as errors, its references hold every name of the
API and every command of the command line, and its pages open from disk without a network request.

The examples on its pages are executed by test_documentation_examples.py, with the README's.
"""
from __future__ import annotations

import importlib
import inspect
import os
import subprocess
import sys
from html import unescape
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site built once, as the README's command builds it: warnings are errors, every one is reported."""
    out = tmp_path_factory.mktemp("site")
    result = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                             "-d", str(out / "doctrees"), str(DOCS), str(out / "html")],
                            capture_output=True, text=True, cwd=ROOT, timeout=600,
                            env=dict(os.environ, MPLBACKEND="Agg"))
    return out / "html", result


def test_the_site_builds_with_no_warning(site):
    html, result = site
    assert result.returncode == 0 and not result.stderr.strip(), result.stderr[-6000:]
    assert (html / "index.html").is_file()


def inventory(html: Path) -> set[str]:
    """The names the site documents (Sphinx's objects.inv): 'py:function:course_dynamics.core.x.f', …"""
    from sphinx.util.inventory import InventoryFile

    with open(html / "objects.inv", "rb") as handle:
        data = InventoryFile.load(handle, "", os.path.join)
    return {f"{kind}:{name}" for kind, entries in data.items() for name in entries}


def api_names() -> list[str]:
    """Every name the API offers where it is defined, and the public methods of its classes."""
    from test_docstrings import API_MODULES, imported_from

    names = []
    for module_name in API_MODULES:
        module = importlib.import_module(module_name)
        for attribute in module.__all__:
            obj = getattr(module, attribute)
            if inspect.ismodule(obj):
                continue
            if (inspect.isclass(obj) or inspect.isroutine(obj)) and obj.__module__ != module_name or (
                    imported_from(module, attribute) is not None):
                continue  # documented where it is defined
            names.append(f"{module_name}.{attribute}")
            if inspect.isclass(obj):
                names += [f"{module_name}.{attribute}.{m}" for m, member in vars(obj).items()
                          if not m.startswith("_") and (inspect.isfunction(member) or isinstance(
                              member, (property, staticmethod, classmethod)))]
    return names


def test_every_name_of_the_api_is_in_the_reference(site):
    html, _ = site
    documented = {entry.split(":", 2)[2] for entry in inventory(html) if entry.startswith("py:")}
    missing = [name for name in api_names() if name not in documented]
    assert len(api_names()) > 100 and not missing, missing


def test_every_command_is_in_the_cli_reference_with_its_help_and_an_example(site, monkeypatch):
    from course_dynamics.cli import build_parser
    from course_dynamics.cli.commands import COMMANDS

    html, _ = site
    page = unescape((html / "cli.html").read_text())
    monkeypatch.setenv("COLUMNS", "80")  # the width the reference shows --help at
    parser = build_parser()
    commands = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction").choices
    assert sorted(commands) == sorted(name.replace("_", "-") for name in COMMANDS)
    for name, sub in commands.items():
        assert f'id="cli-{name}"' in page or f'id="course-dynamics-{name}"' in page, name
        for line in sub.format_help().splitlines():
            assert line.strip() in page, (name, line)



def test_every_command_has_an_example_that_the_tests_run():
    """The CLI reference lists each command's examples from the pages (each page's ``sh`` blocks); every one of
    them is among the commands the examples test executes, and every command has at least one."""
    from test_documentation_examples import example_blocks

    from course_dynamics.cli.commands import COMMANDS

    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        extension = importlib.import_module("course_dynamics_docs")
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    listed = extension.page_examples(DOCS)
    executed = {" ".join(command.split()) for block in example_blocks() for command, _ in block}
    for name in COMMANDS:
        examples = listed.get(name.replace("_", "-"), [])
        assert examples, f"course-dynamics {name} has no example on any page"
        shown = {line.partition("  #")[0].strip() for _, line in examples}
        assert shown <= executed, shown - executed


def test_the_layer_picture_is_the_package_as_it_is():
    sys.path.insert(0, str(DOCS))
    try:
        layers = importlib.import_module("layers")
    finally:
        sys.path.remove(str(DOCS))
    assert (DOCS / "_static" / "layers.svg").read_text() == layers.svg(), "run python3 docs/layers.py"


GUIDES = ["index.html", "guides/student.html", "guides/instructor.html", "guides/engineer.html", "cli.html",
          "api/core.html"]


@pytest.mark.parametrize("page", GUIDES)
def test_a_page_opens_from_disk_with_no_network_request(site, browser, page):
    html, result = site
    assert (html / page).is_file(), result.stderr[-2000:]
    tab = browser.new_page(viewport={"width": 1200, "height": 900})
    requests, errors = [], []
    tab.on("request", lambda request: requests.append(request.url))
    tab.on("pageerror", lambda error: errors.append(str(error)))
    tab.goto((html / page).as_uri())
    tab.wait_for_load_state("load")
    title = tab.title()
    text = tab.inner_text("main") if tab.query_selector("main") else tab.inner_text("body")
    # The theme's stylesheet loaded (from disk): its colour variables are set on the page.
    styled = tab.evaluate("() => getComputedStyle(document.body).getPropertyValue('--color-foreground-primary')")
    tab.close()
    assert all(url.startswith(("file:", "data:")) for url in requests), [u for u in requests if
                                                                         not u.startswith(("file:", "data:"))]
    assert not errors and "course-dynamics" in title and len(text) > 300 and styled.strip(), (title, errors)


def test_the_readme_is_a_front_door_whose_links_lead_somewhere():
    """Under 300 lines, linking into the site; every relative link of it names a file that exists."""
    import re

    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) < 300
    links = [target.split("#")[0] for target in re.findall(r"\]\(([^)\s]+)\)", readme)
             if not target.startswith(("http:", "https:", "#", "mailto:"))]
    assert sum(link.startswith("docs/") for link in links) >= 5, links
    missing = [link for link in links if not (ROOT / link).exists()]
    assert not missing, missing


def test_the_search_page_finds_a_function_from_disk(site, browser):
    html, _ = site
    tab = browser.new_page(viewport={"width": 1200, "height": 900})
    requests, errors = [], []
    tab.on("request", lambda request: requests.append(request.url))
    tab.on("pageerror", lambda error: errors.append(str(error)))
    tab.goto((html / "search.html").as_uri() + "?q=inverse_dynamics")
    tab.wait_for_selector("#search-results li", timeout=20_000)
    tab.wait_for_timeout(500)
    found = tab.inner_text("#search-results")
    tab.close()
    assert "inverse_dynamics" in found and not errors, errors
    assert all(url.startswith(("file:", "data:")) for url in requests), requests
