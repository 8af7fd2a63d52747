"""What of the disk a submission sees in the sandbox: its mounts, worked out from the layout of the Python build.

Builds keep what is installed in different places, most of them inside the
standard library's own folder, so binding the standard library binds every
package installed there:

=======================  ==================================  ==============================================
build                    standard library                    packages
=======================  ==================================  ==============================================
pyenv, python.org, uv    ``PREFIX/lib/python3.X``            ``PREFIX/lib/python3.X/site-packages``
conda                    ``PREFIX/lib/python3.X``            ``PREFIX/lib/python3.X/site-packages`` (shared
                                                             libraries in ``PREFIX/lib``)
Debian, Ubuntu           ``/usr/lib/python3.X``              ``/usr/lib/python3/dist-packages``,
                                                             ``/usr/local/lib/python3.X/dist-packages``
Fedora                   ``/usr/lib64/python3.X``            ``/usr/lib64/python3.X/site-packages``
a venv (``pyvenv.cfg``)  its base's                          ``VENV/lib/python3.X/site-packages``
=======================  ==================================  ==============================================

The view (:func:`view`, in bubblewrap's order: later mounts cover earlier
ones) binds read-only the system folders a Python needs, the interpreter, the
shared libraries outside them that it and the allowed packages load
(:mod:`~course_dynamics.grading.libraries`: conda's ``lib/`` entries one by one,
never the whole folder), the folders of the interpreter's own import path
(started ``-I -S``: the standard library and lib-dynload) and the few files of
``/etc`` the dynamic loader reads. Then every ``site-packages`` or
``dist-packages`` folder inside anything bound is covered by an empty,
read-only folder that no one may list or enter (mode 0000), and each allowed
package alone is bound into :data:`~course_dynamics.grading.environment.SITE`.
A virtual environment's own folder is never bound: the submission runs on its
base.
"""
from __future__ import annotations

import functools
import os
import sys
from dataclasses import dataclass
from pathlib import Path

from .environment import PACKAGE_FOLDERS, SITE, TOP_FOLDERS, Environment, system_folders

ETC_FILES = ("/etc/ld.so.cache", "/etc/ld.so.conf", "/etc/ld.so.conf.d", "/etc/alternatives", "/etc/localtime")
#: How deep below a bound folder a site-packages or dist-packages folder is looked for.
SEARCH_DEPTH = 3  # how deep below a bound folder a site folder is looked for (/usr/lib64/python3.X/site-packages: 2)


@dataclass(frozen=True)
class Mount:
    """One mount of the view: ``bind`` (``source`` read-only at ``target``; ``optional`` when it may be missing),
    ``link`` (a symbolic link to ``source``) or ``hidden`` (an empty read-only folder no one may list or enter).

    Parameters
    ----------
    kind : str
        ``"bind"``, ``"link"`` or ``"hidden"``.
    target : str
        Where it is in the sandbox.
    source : str
        What is bound there, or what the link points to.
    optional : bool
        For a bind, whether the source may be missing.
    """

    kind: str
    target: str
    source: str = ""
    optional: bool = False


def site_folders(folders) -> list[Path]:
    """Every site-packages or dist-packages folder at most :data:`SEARCH_DEPTH` deep inside ``folders`` (real paths),
    and any on this grader's import path that lies inside them; the outermost only, links not followed.

    Parameters
    ----------
    folders : iterable of str or os.PathLike
        The folders bound.

    Returns
    -------
    list of pathlib.Path
        The site folders, sorted.
    """
    folders = [Path(folder) for folder in folders]
    found: set[Path] = set()
    pending = [(folder, 0) for folder in folders if folder.is_dir()]
    while pending:
        folder, depth = pending.pop()
        try:
            entries = list(os.scandir(folder))
        except OSError:
            continue
        for entry in entries:
            if not entry.is_dir(follow_symlinks=False):
                continue
            if entry.name in PACKAGE_FOLDERS:
                found.add(Path(entry.path))
            elif depth + 1 < SEARCH_DEPTH:
                pending.append((Path(entry.path), depth + 1))
    for entry in sys.path:  # a folder this grader imports from, if a bound folder holds it deeper
        path = Path(os.path.realpath(entry)) if entry else None
        while path is not None and path != path.parent:
            if path.name in PACKAGE_FOLDERS and path.is_dir() and any(path.is_relative_to(f) for f in folders):
                found.add(path)
            path = path.parent
    return sorted(p for p in found if not any(p != q and p.is_relative_to(q) for q in found))


def _inside(path: Path, folders) -> bool:
    return any(path.is_relative_to(folder) for folder in folders)


@functools.lru_cache(maxsize=None)
def view(environment: Environment, roots: tuple[str, ...] | None = None) -> tuple[Mount, ...]:
    """The sandbox's read-only view for ``environment`` (module docstring); ``roots`` the system folders bound
    whole (default :func:`~course_dynamics.grading.environment.system_folders`).

    Parameters
    ----------
    environment : Environment
        The submission's environment.
    roots : tuple of str or None
        The system folders bound whole.

    Returns
    -------
    tuple of Mount
        The mounts, in bubblewrap's order (later ones cover earlier ones).
    """
    roots = tuple(system_folders()) if roots is None else roots
    mounts = [Mount("bind", folder, folder) for folder in roots]
    mounts += [Mount("link", top, os.readlink(top)) for top in TOP_FOLDERS if os.path.islink(top)]
    bound = [Path(folder) for folder in roots]  # merged /usr: the same link as on the host leads to what is bound
    for path in [environment.interpreter, *environment.libraries, environment.stdlib, *environment.path]:
        if not _inside(Path(path), bound):
            mounts.append(Mount("bind", str(path), str(path)))
            bound.append(Path(path))
    mounts += [Mount("bind", path, path, optional=True) for path in ETC_FILES]
    # no installed package is seen ...
    mounts += [Mount("hidden", str(folder)) for folder in site_folders(p for p in bound if p.is_dir())]
    mounts += [Mount("bind", f"{SITE}/{name}", str(source)) for name, source in environment.packages]  # ... but these
    return tuple(mounts)


def bwrap_arguments(mounts) -> list[str]:
    """The bubblewrap options that make ``mounts``.

    Parameters
    ----------
    mounts : iterable of Mount
        The mounts, in order.

    Returns
    -------
    list of str
        The options.
    """
    args = []
    for mount in mounts:
        if mount.kind == "bind":
            args += ["--ro-bind-try" if mount.optional else "--ro-bind", mount.source, mount.target]
        elif mount.kind == "link":
            args += ["--symlink", mount.source, mount.target]
        else:
            args += ["--perms", "0000", "--size", "4096", "--tmpfs", mount.target, "--remount-ro", mount.target]
    return args


__all__ = ["SEARCH_DEPTH", "Mount", "bwrap_arguments", "site_folders", "view"]
