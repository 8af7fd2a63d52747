"""The Python a submission runs in: the standard library, numpy and the packages the assignment allows, nothing else.

A guard inside the student's interpreter can be removed by the student, and a
module name can be computed at run time, so forbidding imports from the
inside does not hold. What holds is absence: the submission runs on the base
interpreter of this installation (never a virtual environment's), started
with ``-I -S`` so that no site-packages folder is put on its path, and with
one folder of allowed packages on the path (:data:`SITE` in the sandbox).
What that interpreter's own path holds is asked of it, once
(:func:`describe`): the standard library's folders only, or the grader stops
with one line naming the build that puts more there.

In the sandbox the submission's file system holds the standard library with
every site-packages folder inside it made an empty folder that cannot be
listed or entered (most builds keep their packages there: pyenv, python.org,
conda, uv; see :mod:`~course_dynamics.grading.view`), and each allowed package
bound read-only into :data:`SITE`; so Pinocchio, course_dynamics and
everything else installed are not there to be imported, whatever the
submission does. Without the sandbox (``--no-sandbox``) the same interpreter
starts with a private folder of links to the allowed packages as its only
extra path; the rest of the disk is still readable by a submission that goes
looking for it, which is why grading without a sandbox is for trusted code
only.
"""
from __future__ import annotations

import functools
import importlib.util
import json
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

from ..base.errors import InputError
from .libraries import elf_files, shared_libraries

#: Where the allowed packages are bound read-only in the sandbox, the one folder added to the submission's path.
SITE = "/site"
ALWAYS = ("numpy",)  # what every submission may use besides the standard library
PACKAGE_FOLDERS = ("site-packages", "dist-packages")
TOP_FOLDERS = ("/bin", "/sbin", "/lib", "/lib32", "/lib64")  # links into /usr on a merged-/usr system
#: What a Python says of itself when started as a submission's is (its base executable, its import path, its
#: standard library and where its shared libraries are): a program for ``python -I -S -c``.
DESCRIBE = ("import json, sys, sysconfig; print(json.dumps({'executable': getattr(sys, '_base_executable', '') or "
            "sys.executable, 'path': sys.path, 'stdlib': sysconfig.get_paths()['stdlib'], "
            "'libdir': sysconfig.get_config_var('LIBDIR') or ''}))")


@dataclass(frozen=True)
class Environment:
    """The interpreter, what of its installation it needs, and the allowed packages as (name in SITE, path).

    ``stdlib`` is the standard library's folder, ``path`` the folders of the interpreter's own import path
    under ``-I -S`` (the standard library, lib-dynload), ``libraries`` the shared libraries outside the
    system's folders that it and the packages load (``libpython3.X.so``; on conda its ``lib/``'s ``libz``,
    ``libcblas`` …), each by the path the dynamic loader opens.

    Parameters
    ----------
    interpreter : pathlib.Path
        The base Python binary.
    stdlib : pathlib.Path
        The standard library's folder.
    libraries : tuple of pathlib.Path
        The shared libraries outside the system's folders that it and the packages load.
    packages : tuple of tuple of (str, pathlib.Path)
        The allowed packages: (name in :data:`SITE`, the installed folder or file).
    path : tuple of pathlib.Path
        The interpreter's own import path under ``-I -S``.
    """

    interpreter: Path
    stdlib: Path
    libraries: tuple[Path, ...]
    packages: tuple[tuple[str, Path], ...]
    path: tuple[Path, ...] = ()

    @property
    def library_path(self) -> str:
        """``LD_LIBRARY_PATH`` for the submission, the folders of ``libraries``, so that a package bound
        into SITE still finds what its run path names relative to where it was installed (conda's numpy)."""
        return ":".join(dict.fromkeys(str(library.parent) for library in self.libraries))

    def linked_site(self, folder: Path) -> Path:
        """``folder`` filled with links to the allowed packages (the path of a run without a sandbox).

        Parameters
        ----------
        folder : pathlib.Path
            An empty folder.

        Returns
        -------
        pathlib.Path
            ``folder``.
        """
        for name, source in self.packages:
            os.symlink(source, folder / name)
        return folder


def base_interpreter() -> Path:
    """The Python binary of the base installation: a virtual environment's python is only a link to it.

    Returns
    -------
    pathlib.Path
        The binary, links resolved.
    """
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
        if (origin.is_relative_to(Path(sys.base_prefix).resolve())
                and not any(p in origin.parts for p in PACKAGE_FOLDERS)):
            return []  # part of the standard library: there already
        return [(origin.name, origin)]
    return []  # built into the interpreter


def submission_environment(allowed=(), site: Path | None = None, interpreter: Path | None = None) -> Environment:
    """The environment for a submission: numpy and ``allowed`` (top-level module names) beside the standard library.

    The packages are this installation's, or with ``site`` those in that folder (a copy made for submissions,
    as the Gradescope bundle's setup makes one: :func:`copy_packages`). The interpreter is this installation's
    base Python, or the base of ``interpreter`` (a virtual environment's python names its base in
    ``pyvenv.cfg``); it must be of the same Python version as the packages.

    Parameters
    ----------
    allowed : iterable of str
        Top-level module names allowed besides numpy.
    site : pathlib.Path or None
        A folder holding the packages; this installation's when None.
    interpreter : pathlib.Path or None
        The Python whose base runs the submission; this installation's when None.

    Returns
    -------
    Environment
        The environment.

    Raises
    ------
    InputError
        If an allowed package is not installed (or not in ``site``), or the interpreter cannot run or puts a site
        folder on its path (:func:`describe`).
    """
    packages: dict[str, Path] = {}
    for name in dict.fromkeys((*ALWAYS, *allowed)):
        found = _package_files(name) if site is None else _site_files(Path(site), name)
        for site_name, source in found:
            packages[site_name] = source
    described = describe(Path(interpreter) if interpreter is not None else base_interpreter())
    executable = Path(os.path.realpath(described["executable"]))
    path = tuple(Path(os.path.realpath(entry)) for entry in described["path"])
    return Environment(executable, Path(described["stdlib"]).resolve(),
                       _libraries(executable, path, Path(described["libdir"]), tuple(packages.values())),
                       tuple(packages.items()), path)


@functools.lru_cache(maxsize=None)
def describe(interpreter: Path) -> dict:
    """What ``interpreter`` says of itself started as a submission's is (:data:`DESCRIBE`), its import path
    reduced to the folders and files that exist; InputError when it cannot run or its path holds a site folder.

    Parameters
    ----------
    interpreter : pathlib.Path
        The Python binary.

    Returns
    -------
    dict
        ``executable`` (its base executable), ``path`` (its import path under ``-I -S``), ``stdlib`` and
        ``libdir``.

    Raises
    ------
    InputError
        If it cannot run, or its import path holds a site-packages or dist-packages folder.
    """
    try:
        ran = subprocess.run([str(interpreter), "-I", "-S", "-c", DESCRIBE], capture_output=True, text=True,
                             env={"PATH": "/usr/bin:/bin", "LANG": "C.UTF-8"}, timeout=60)
        described = json.loads(ran.stdout) if ran.returncode == 0 else None
    except (OSError, ValueError, subprocess.TimeoutExpired) as exc:
        ran, described = exc, None
    if not isinstance(described, dict):
        reason = ran.stderr.strip().splitlines()[-1] if getattr(ran, "stderr", "") else str(ran)
        raise InputError(f"{interpreter}: cannot run it to learn its standard library ({reason})")
    path = [entry for entry in described["path"] if entry and os.path.exists(entry)]
    for entry in path:
        if any(part in PACKAGE_FOLDERS for part in Path(entry).parts):
            raise InputError(f"{interpreter}: puts {entry} on its import path even when started with -I -S, so a "
                             "submission would import what is installed there; grade with another Python build")
    return dict(described, path=path)


@functools.lru_cache(maxsize=None)
def _libraries(interpreter: Path, path: tuple[Path, ...], libdir: Path, packages: tuple[Path, ...]) -> tuple[Path, ...]:
    """The shared libraries outside the system's folders that the interpreter, its compiled standard modules
    and the packages load (:func:`~course_dynamics.grading.libraries.shared_libraries`)."""
    objects = [interpreter, *(p for entry in path if entry.is_dir() for p in sorted(entry.glob("*.so")))]
    objects += [p for package in packages for p in elf_files(package)]
    return shared_libraries(objects, search=[libdir], shown=[*system_folders(), *packages])


def system_folders() -> list[str]:
    """What of the system a submission's Python needs: commands, the shared libraries, the dynamic loader.

    Not all of ``/usr``: the rest holds other software, packages vendored by it, and what is installed.

    Returns
    -------
    list of str
        The folders that exist here.
    """
    import glob

    folders = ["/usr/bin", *sorted(glob.glob("/usr/lib/*-linux-gnu*")), "/usr/lib64"]
    for top in TOP_FOLDERS:
        if os.path.isdir(top) and not os.path.islink(top):
            folders.append(top)  # a system without a merged /usr: the folder itself
    return [folder for folder in folders if os.path.isdir(folder)]


def _site_files(site: Path, name: str) -> list[tuple[str, Path]]:
    found = [(entry.name, entry.resolve()) for entry in (site / name, site / f"{name}.libs") if entry.exists()]
    found += [(entry.name, entry.resolve()) for entry in sorted(site.glob(f"{name}.*.so")) + [site / f"{name}.py"]
              if entry.is_file()]
    if not found:
        raise InputError(f"allowed_imports: '{name}' is not in {site}")
    return found


def copy_packages(allowed, site: Path) -> list[str]:
    """Copy numpy and ``allowed`` from this installation into ``site`` (readable by everyone); their names.

    Parameters
    ----------
    allowed : iterable of str
        Top-level module names allowed besides numpy.
    site : pathlib.Path
        The folder to copy them into.

    Returns
    -------
    list of str
        The names copied (a wheel's ``<name>.libs`` folder too).

    Raises
    ------
    InputError
        If an allowed package is not installed.
    """
    import shutil

    copied = []
    for name in dict.fromkeys((*ALWAYS, *allowed)):
        for site_name, source in _package_files(name):
            target = site / site_name
            if source.is_dir():
                shutil.copytree(source, target, ignore=shutil.ignore_patterns("__pycache__", "tests"),
                                dirs_exist_ok=True)
            else:
                shutil.copy2(source, target)
            copied.append(site_name)
    for path in [site, *site.rglob("*")]:
        path.chmod(0o755 if path.is_dir() else 0o644 | (path.stat().st_mode & 0o111))
    return copied


def harness_arguments(environment: Environment) -> list[str]:
    """How the interpreter is started: isolated (-I: no PYTHON* variables, no user site), without site (-S), and
    unbuffered (-u: what a submission prints and what its processes print stay in order).

    Parameters
    ----------
    environment : Environment
        The submission's environment.

    Returns
    -------
    list of str
        The command's start: the interpreter and its options.
    """
    return [str(environment.interpreter), "-I", "-S", "-u"]


__all__ = ["DESCRIBE", "SITE", "Environment", "base_interpreter", "copy_packages", "describe", "harness_arguments",
           "submission_environment", "system_folders"]
