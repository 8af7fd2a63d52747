"""The Python a submission runs in: the standard library, numpy and the packages the assignment allows, nothing else.

A guard inside the student's interpreter can be removed by the student, and a
module name can be computed at run time, so forbidding imports from the
inside does not hold. What holds is absence: the submission runs on the base
interpreter of this installation (never a virtual environment's), started
with ``-I -S`` so that no site-packages folder is put on its path, and with
one folder of allowed packages on the path (:data:`SITE` in the sandbox).

In the sandbox the submission's file system has no site-packages folder at all
(every one inside the bound system folders is covered by an empty read-only
tmpfs), and each allowed package is bound read-only into :data:`SITE`; so
Pinocchio, course_dynamics and everything else installed are not there to be
imported, whatever the submission does. Without the sandbox (``--no-sandbox``)
the same interpreter starts with a private folder of links to the allowed
packages as its only extra path; the rest of the disk is still readable by a
submission that goes looking for it, which is why grading without a sandbox is
for trusted code only.
"""
from __future__ import annotations

import importlib.util
import os
import sys
import sysconfig
from dataclasses import dataclass
from pathlib import Path

from ..base.errors import InputError

SITE = "/site"
ALWAYS = ("numpy",)  # what every submission may use besides the standard library
PACKAGE_FOLDERS = ("site-packages", "dist-packages")


@dataclass(frozen=True)
class Environment:
    """The interpreter, what of its installation it needs, and the allowed packages as (name in SITE, path).

    ``stdlib`` is the standard library's folder (lib-dynload inside it), ``libraries`` the interpreter's
    own shared library where it has one (``libpython3.X.so``).
    """

    interpreter: Path
    stdlib: Path
    libraries: tuple[Path, ...]
    packages: tuple[tuple[str, Path], ...]

    def linked_site(self, folder: Path) -> Path:
        """``folder`` filled with links to the allowed packages (the path of a run without a sandbox)."""
        for name, source in self.packages:
            os.symlink(source, folder / name)
        return folder


def base_interpreter() -> Path:
    """The Python binary of the base installation: a virtual environment's python is only a link to it."""
    return Path(os.path.realpath(getattr(sys, "_base_executable", None) or sys.executable))


def _package_files(name: str) -> list[tuple[str, Path]]:
    """The folder (or single file) of an installed top-level module, with a ``<name>.libs`` folder beside it."""
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError):
        spec = None
    if spec is None:
        raise InputError(f"allowed_imports: '{name}' is not installed where the grader runs")
    if spec.submodule_search_locations:
        folder = Path(list(spec.submodule_search_locations)[0]).resolve()
        found = [(name, folder)]
        libs = folder.parent / f"{name}.libs"  # shared libraries of a wheel (numpy's OpenBLAS)
        if libs.is_dir():
            found.append((libs.name, libs.resolve()))
        return found
    if spec.origin and spec.origin not in ("built-in", "frozen") and Path(spec.origin).is_file():
        origin = Path(spec.origin).resolve()
        if origin.is_relative_to(Path(sys.base_prefix).resolve()) and not any(p in origin.parts for p in PACKAGE_FOLDERS):
            return []  # part of the standard library: there already
        return [(origin.name, origin)]
    return []  # built into the interpreter


def submission_environment(allowed=(), site: Path | None = None) -> Environment:
    """The environment for a submission: numpy and ``allowed`` (top-level module names) beside the standard library.

    The packages are this installation's, or with ``site`` those in that folder (a copy made for submissions,
    as the Gradescope bundle's setup makes one: :func:`copy_packages`).
    """
    packages: dict[str, Path] = {}
    for name in dict.fromkeys((*ALWAYS, *allowed)):
        found = _package_files(name) if site is None else _site_files(Path(site), name)
        for site_name, source in found:
            packages[site_name] = source
    libdir, soname = sysconfig.get_config_var("LIBDIR"), sysconfig.get_config_var("INSTSONAME")
    library = Path(libdir) / soname if libdir and soname and sysconfig.get_config_var("Py_ENABLE_SHARED") else None
    libraries = (library.resolve(),) if library is not None and library.is_file() else ()
    return Environment(base_interpreter(), Path(sysconfig.get_paths()["stdlib"]).resolve(), libraries,
                       tuple(packages.items()))


def _site_files(site: Path, name: str) -> list[tuple[str, Path]]:
    found = [(entry.name, entry.resolve()) for entry in (site / name, site / f"{name}.libs") if entry.exists()]
    found += [(entry.name, entry.resolve()) for entry in sorted(site.glob(f"{name}.*.so")) + [site / f"{name}.py"]
              if entry.is_file()]
    if not found:
        raise InputError(f"allowed_imports: '{name}' is not in {site}")
    return found


def copy_packages(allowed, site: Path) -> list[str]:
    """Copy numpy and ``allowed`` from this installation into ``site`` (readable by everyone); their names."""
    import shutil

    copied = []
    for name in dict.fromkeys((*ALWAYS, *allowed)):
        for site_name, source in _package_files(name):
            target = site / site_name
            if source.is_dir():
                shutil.copytree(source, target, ignore=shutil.ignore_patterns("__pycache__", "tests"), dirs_exist_ok=True)
            else:
                shutil.copy2(source, target)
            copied.append(site_name)
    for path in [site, *site.rglob("*")]:
        path.chmod(0o755 if path.is_dir() else 0o644 | (path.stat().st_mode & 0o111))
    return copied


def package_folders(roots) -> list[Path]:
    """Every site-packages or dist-packages folder in the usual places under ``roots``, and on this ``sys.path``."""
    found = set()
    for root in map(Path, roots):
        for pattern in ("lib*/python3*/*-packages", "lib/python3/dist-packages", "local/lib*/python3*/*-packages"):
            found |= {p for p in root.glob(pattern) if p.name in PACKAGE_FOLDERS and p.is_dir()}
    for entry in sys.path:
        path = Path(entry) if entry else None
        while path is not None and path != path.parent:
            if path.name in PACKAGE_FOLDERS and path.is_dir():
                found.add(path)
                break
            path = path.parent
    resolved = {p.resolve() for p in found}
    inside = [p for p in resolved if any(p.is_relative_to(Path(r).resolve()) for r in roots)]
    return sorted(p for p in inside if not any(p != q and p.is_relative_to(q) for q in inside))  # outermost only


def harness_arguments(environment: Environment) -> list[str]:
    """How the interpreter is started: isolated (-I: no PYTHON* variables, no user site), without site (-S), and
    unbuffered (-u: what a submission prints and what its processes print stay in order)."""
    return [str(environment.interpreter), "-I", "-S", "-u"]
