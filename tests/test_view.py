"""The sandbox's view of the disk on every kind of Python build: the standard library, never what is installed.

Only one build exists on a test machine, so the others are laid out under
``tmp_path``: by hand for :func:`view` (pyenv, python.org, uv, conda, Debian,
Fedora, a venv), and as working Pythons (a copy of this interpreter's binary
beside a standard library of links to this one's) for grading through the
real sandbox.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest
from probes import found, nothing_found, probe

from course_dynamics import CourseDynamicsError
from course_dynamics.grading import load_assignment
from course_dynamics.grading.environment import SITE, Environment, base_interpreter, describe, submission_environment
from course_dynamics.grading.grade import grade_class
from course_dynamics.grading.view import bwrap_arguments, site_folders, view

VERSION = f"python{sys.version_info.major}.{sys.version_info.minor}"
STDLIB = Path(sysconfig.get_paths()["stdlib"]).resolve()
ASSIGNMENT = "robot = 'two_link'\nsamples = 2\ntime_limit = 5\nmemory_limit = 1024\n[points]\nG = 10\n"


def seen(mounts, path) -> bool:
    """Whether ``path`` is in the view: the last mount that holds it decides (later mounts cover earlier ones)."""
    shown = False
    for mount in mounts:
        if Path(path).is_relative_to(mount.target):
            shown = mount.kind == "bind"
    return shown


def package(site: Path, name: str) -> Path:
    (site / name).mkdir(parents=True)
    (site / name / "__init__.py").write_text("")
    return site / name


def stdlib_at(folder: Path) -> Path:
    (folder / "lib-dynload").mkdir(parents=True)
    (folder / "os.py").write_text("")
    return folder


def installation(prefix: Path, lib: str = "lib") -> tuple[Path, Path]:
    """(python, stdlib) of a build at ``prefix`` that installs into ``lib/python3.X/site-packages``, sympy there."""
    (prefix / "bin").mkdir(parents=True)
    (prefix / "bin" / VERSION).write_text("")
    stdlib = stdlib_at(prefix / lib / VERSION)
    package(stdlib / "site-packages", "sympy")
    package(stdlib / "site-packages" / "cmeel.prefix" / "lib" / VERSION / "site-packages", "pinocchio")
    return prefix / "bin" / VERSION, stdlib


def numpy_in(site: Path) -> tuple[tuple[str, Path], ...]:
    return (("numpy", package(site, "numpy")),)


def pyenv(root: Path, prefix="versions/3.11.7"):
    python, stdlib = installation(root / prefix)
    (root / prefix / "lib" / "libpython3.so").write_text("")
    environment = Environment(python, stdlib, (root / prefix / "lib" / "libpython3.so",),
                              numpy_in(stdlib / "site-packages"), (stdlib, stdlib / "lib-dynload"))
    return environment, (), [stdlib / "site-packages"]


def conda(root: Path):
    python, stdlib = installation(root / "miniforge3")
    lib = root / "miniforge3" / "lib"
    for name in ("libcblas.so.3", "libz.so.1", "libpinocchio_default.so"):
        (lib / name).write_text("")
    environment = Environment(python, stdlib, (lib / "libcblas.so.3", lib / "libz.so.1"),
                              numpy_in(stdlib / "site-packages"), (stdlib, stdlib / "lib-dynload"))
    return environment, (), [stdlib / "site-packages", lib / "libpinocchio_default.so", lib / "cmake"]


def debian(root: Path):
    usr = root / "usr"
    (usr / "bin").mkdir(parents=True)
    (usr / "bin" / VERSION).write_text("")
    (usr / "lib" / "x86_64-linux-gnu").mkdir(parents=True)
    stdlib = stdlib_at(usr / "lib" / VERSION)
    package(usr / "lib" / "python3" / "dist-packages", "scipy")
    package(usr / "local" / "lib" / VERSION / "dist-packages", "sympy")
    environment = Environment(usr / "bin" / VERSION, stdlib, (), numpy_in(usr / "lib" / "python3" / "dist-packages"),
                              (stdlib, stdlib / "lib-dynload"))
    return environment, (str(usr / "bin"), str(usr / "lib" / "x86_64-linux-gnu")), [
        usr / "lib" / "python3" / "dist-packages", usr / "local" / "lib" / VERSION / "dist-packages"]


def fedora(root: Path):
    """The standard library inside a folder the sandbox binds whole (``/usr/lib64``), its site-packages too."""
    python, stdlib = installation(root / "usr", lib="lib64")
    package(root / "usr" / "lib64" / "python3.9" / "site-packages", "yourdfpy")  # another Python's
    environment = Environment(python, stdlib, (), numpy_in(stdlib / "site-packages"), (stdlib, stdlib / "lib-dynload"))
    return environment, (str(root / "usr" / "bin"), str(root / "usr" / "lib64")), [
        stdlib / "site-packages", root / "usr" / "lib64" / "python3.9" / "site-packages"]


def venv(root: Path):
    """A venv over a pyenv Python: the submission runs on the base, and neither site-packages is seen."""
    environment, roots, hidden = pyenv(root / "base")
    (root / "venv" / "bin").mkdir(parents=True)
    (root / "venv" / "pyvenv.cfg").write_text(f"home = {environment.interpreter.parent}\n")
    site = root / "venv" / "lib" / VERSION / "site-packages"
    package(site, "course_dynamics")
    return Environment(environment.interpreter, environment.stdlib, environment.libraries, numpy_in(site),
                       environment.path), roots, [*hidden, site, root / "venv"]


LAYOUTS = {"pyenv": pyenv, "python.org": lambda root: pyenv(root, "usr/local"),
           "uv": lambda root: pyenv(root, ".local/share/uv/python/cpython-3.11.7-linux-x86_64-gnu"),
           "conda": conda, "debian": debian, "fedora": fedora, "venv": venv}


@pytest.mark.parametrize("layout", LAYOUTS)
def test_the_view_holds_the_standard_library_and_numpy_and_no_site_folder(tmp_path, layout):
    environment, roots, hidden = LAYOUTS[layout](tmp_path)
    mounts = view(environment, roots)
    for path in (environment.interpreter, environment.stdlib / "os.py", environment.stdlib / "lib-dynload",
                 *environment.libraries):
        assert seen(mounts, path), (layout, path)
    assert seen(mounts, f"{SITE}/numpy")
    assert [m.source for m in mounts if m.target == f"{SITE}/numpy"] == [str(environment.packages[0][1])]
    for path in hidden:
        assert not seen(mounts, path) and not seen(mounts, path / "sympy"), (layout, path)
    hidden_folders = [m.target for m in mounts if m.kind == "hidden"]
    assert all(Path(folder).name in ("site-packages", "dist-packages") for folder in hidden_folders)


def test_a_hidden_folder_is_empty_read_only_and_closed_to_everyone(tmp_path):
    environment, roots, hidden = pyenv(tmp_path)
    arguments = bwrap_arguments(view(environment, roots))
    folder = str(hidden[0])
    at = arguments.index(folder)
    assert arguments[at - 5:at + 3] == ["--perms", "0000", "--size", "4096", "--tmpfs", folder, "--remount-ro", folder]


def test_site_folders_are_found_below_what_is_bound_and_only_the_outermost(tmp_path):
    _, stdlib = installation(tmp_path / "prefix")
    package(stdlib / "test" / "data" / "more" / "site-packages", "deep")  # deeper than any layout keeps one
    assert site_folders([stdlib]) == [stdlib / "site-packages"]
    assert site_folders([tmp_path / "prefix" / "lib"]) == [stdlib / "site-packages"]


# ---------------------------------------------------------------------------------------- working builds


def link_or_copy(source, target) -> None:
    try:
        os.link(source, target)
    except OSError:  # another file system
        shutil.copy2(source, target)


def working_python(prefix: Path, path_file: str = "") -> Path:
    """A Python at ``prefix``: this interpreter's binary and standard library (hard links where they can be: no
    room taken; without what grading never imports), and a site-packages folder holding ``marker``;
    ``path_file`` the text of a ``._pth`` beside the binary."""
    (prefix / "bin").mkdir(parents=True)
    python = prefix / "bin" / VERSION
    shutil.copy2(base_interpreter(), python)
    stdlib = prefix / "lib" / VERSION
    shutil.copytree(STDLIB, stdlib, copy_function=link_or_copy, symlinks=True, ignore=shutil.ignore_patterns(
        "site-packages", "dist-packages", "test", "idlelib", "tkinter", "lib2to3", "config-*", "ensurepip"))
    package(stdlib / "site-packages", "marker")
    (stdlib / "site-packages" / "README.txt").write_text("installed here\n")
    if path_file:
        (prefix / "bin" / f"{VERSION}._pth").write_text(path_file)
    else:
        assert Path(describe(python)["stdlib"]) == stdlib  # the copy found its own standard library
    return python


def grade_probe(tmp_path: Path, interpreter: Path, sandbox: bool, folders=()) -> dict:
    (tmp_path / "assignment.toml").write_text(ASSIGNMENT)
    (tmp_path / "probe.py").write_text(probe(("marker", "sympy", "pinocchio"), folders))
    assignment = load_assignment(tmp_path / "assignment.toml")
    environment = submission_environment(interpreter=interpreter)
    grade, = grade_class(assignment, [tmp_path / "probe.py"], sandbox=sandbox, environment=environment)
    assert grade.status == "ok", (grade.status, grade.message, grade.stdout)
    return found(grade.stdout)


def test_a_python_that_installs_inside_its_standard_library_shows_none_of_it(tmp_path):
    """pyenv, python.org, conda and uv keep site-packages inside the standard library's folder."""
    python = working_python(tmp_path / "pyenv" / "versions" / "3.11.7")
    report = grade_probe(tmp_path, python, sandbox=True)
    stdlib = python.parent.parent / "lib" / VERSION
    assert report["path"][0] == SITE and str(stdlib) in report["path"] and str(stdlib / "lib-dynload") in report["path"]
    assert report["listed"][str(stdlib / "site-packages")] == "PermissionError"
    assert nothing_found(report, ("marker", "sympy", "pinocchio")) == []


def test_a_venv_runs_on_its_base_and_shows_neither_site_packages(tmp_path):
    python = working_python(tmp_path / "base")
    subprocess.run([python, "-m", "venv", "--without-pip", tmp_path / "venv"], check=True)
    site = tmp_path / "venv" / "lib" / VERSION / "site-packages"
    package(site, "sympy")
    environment = submission_environment(interpreter=tmp_path / "venv" / "bin" / "python")
    assert environment.interpreter == python and environment.stdlib == python.parent.parent / "lib" / VERSION
    report = grade_probe(tmp_path, tmp_path / "venv" / "bin" / "python", sandbox=True, folders=[site])
    assert nothing_found(report, ("marker", "sympy", "pinocchio")) == []
    assert report["listed"][str(site)] == "FileNotFoundError"


def test_a_python_whose_own_path_holds_a_site_folder_is_refused_in_one_line(tmp_path):
    """A ``._pth`` file (relocatable and embedded builds) can put site-packages on the path even under -I -S;
    without a sandbox nothing would keep what is there from the submission, so grading stops, naming it."""
    lib = f"../lib/{VERSION}"
    python = working_python(tmp_path / "relocatable", f"{lib}\n{lib}/lib-dynload\n{lib}/site-packages\n")
    for sandbox in (False, True):
        with pytest.raises(CourseDynamicsError, match="puts .*site-packages on its import path even when started"
                                                      " with -I -S") as raised:
            grade_probe(tmp_path, python, sandbox=sandbox)
        assert "\n" not in str(raised.value) and str(python) in str(raised.value)
