"""The shared libraries a Python and its allowed packages load, found as the dynamic loader finds them.

A sandbox that shows only some folders must still show every shared library
the submission's interpreter loads: the interpreter's own ``libpython``, what
the standard library's compiled modules need (on conda, ``libz``, ``libffi``
and ``libssl`` live in the installation's ``lib/``, not in the system's), and
what numpy's compiled modules need (a wheel's bundled OpenBLAS in
``numpy.libs``, or conda's ``libcblas``). Binding all of ``lib/`` would show
whatever else is installed there, so each library is found the loader's way:
the ``DT_NEEDED`` names of each ELF file, looked up in its ``DT_RUNPATH`` (or
``DT_RPATH``) with ``$ORIGIN`` expanded, then in the interpreter's ``LIBDIR``;
a name found nowhere there comes from the system's own folders, which the
sandbox shows anyway. Only the ELF headers are read, never executed.
"""
from __future__ import annotations

import os
import struct
from pathlib import Path

PT_LOAD, PT_DYNAMIC = 1, 2
DT_NEEDED, DT_STRTAB, DT_STRSZ, DT_RPATH, DT_RUNPATH = 1, 5, 10, 15, 29
# struct formats after e_ident, of a program header and of a dynamic entry, per ELF class (1: 32-bit, 2: 64-bit)
HEADER = {1: "HHIIIIIHHHHHH", 2: "HHIQQQIHHHHHH"}
PROGRAM = {1: "IIIIIIII", 2: "IIQQQQQQ"}
DYNAMIC = {1: "iI", 2: "qQ"}


def dynamic_section(path: Path) -> tuple[list[str], list[str]] | None:
    """(needed library names, search folders as written) of an ELF file; None for anything else.

    The search folders are ``DT_RUNPATH``'s, else ``DT_RPATH``'s (the loader ignores RPATH when RUNPATH is there).

    Parameters
    ----------
    path : pathlib.Path
        The file; only its headers are read.

    Returns
    -------
    tuple of (list of str, list of str) or None
        The ``DT_NEEDED`` names and the search folders (empty for a static executable), or None for a file that is
        not ELF or cannot be read.
    """
    try:
        with open(path, "rb") as handle:
            ident = handle.read(16)
            if len(ident) < 16 or ident[:4] != b"\x7fELF" or ident[4] not in HEADER or ident[5] not in (1, 2):
                return None
            order = "<" if ident[5] == 1 else ">"
            header = struct.unpack(order + HEADER[ident[4]], handle.read(struct.calcsize(order + HEADER[ident[4]])))
            phoff, phentsize, phnum = header[4], header[8], header[9]
            program = order + PROGRAM[ident[4]]
            segments = []
            for index in range(phnum):
                handle.seek(phoff + index * phentsize)
                fields = struct.unpack(program, handle.read(struct.calcsize(program)))
                if ident[4] == 2:
                    kind, offset, vaddr, filesz = fields[0], fields[2], fields[3], fields[5]
                else:
                    kind, offset, vaddr, filesz = fields[0], fields[1], fields[2], fields[4]
                segments.append((kind, offset, vaddr, filesz))
            dynamic = [(offset, size) for kind, offset, _, size in segments if kind == PT_DYNAMIC]
            if not dynamic:
                return [], []  # a static executable
            handle.seek(dynamic[0][0])
            table = handle.read(dynamic[0][1])
            entry = order + DYNAMIC[ident[4]]
            tags: dict[int, list[int]] = {}
            for tag, value in struct.iter_unpack(entry, table[: len(table) // struct.calcsize(entry)
                                                                * struct.calcsize(entry)]):
                if tag == 0:
                    break
                tags.setdefault(tag, []).append(value)
            strtab, strsz = tags.get(DT_STRTAB, [None])[0], tags.get(DT_STRSZ, [0])[0]
            where = [offset + strtab - vaddr for kind, offset, vaddr, size in segments
                     if kind == PT_LOAD and strtab is not None and vaddr <= strtab < vaddr + size]
            if not where:
                return [], []
            handle.seek(where[0])
            strings = handle.read(strsz)
    except (OSError, struct.error):
        return None

    def text(offset: int) -> str:
        return strings[offset: strings.find(b"\0", offset)].decode("utf-8", "surrogateescape")

    folders = tags.get(DT_RUNPATH) or tags.get(DT_RPATH) or []
    return [text(o) for o in tags.get(DT_NEEDED, [])], [f for o in folders for f in text(o).split(":") if f]


def shared_libraries(objects, search=(), shown=()) -> tuple[Path, ...]:
    """The libraries ``objects`` (ELF files) load, directly or not, that lie outside the ``shown`` folders.

    ``search`` is where the loader looks after an object's own run path (the interpreter's ``LIBDIR``). Each
    library is given by the path the loader opens (a link's name, not its target), so binding that path in a
    sandbox is what makes it load there.

    Parameters
    ----------
    objects : iterable of str or os.PathLike
        The ELF files.
    search : iterable of str or os.PathLike
        Where the loader looks after an object's own run path.
    shown : iterable of str or os.PathLike
        The folders the sandbox shows anyway.

    Returns
    -------
    tuple of pathlib.Path
        The libraries, each by the path the loader opens.
    """
    shown = tuple(Path(folder).resolve() for folder in shown)
    found: dict[Path, None] = {}
    pending = [Path(o) for o in objects]
    seen: set[Path] = set()
    while pending:
        obj = pending.pop()
        if obj.resolve() in seen:
            continue
        seen.add(obj.resolve())
        section = dynamic_section(obj)
        if section is None:
            continue
        needed, run_path = section
        origin = str(obj.parent)
        folders = ([f.replace("${ORIGIN}", origin).replace("$ORIGIN", origin) for f in run_path]
                   + [str(s) for s in search])
        for name in needed:
            candidates = [Path(name)] if "/" in name else [Path(folder) / name for folder in folders]
            library = next((Path(os.path.normpath(c)) for c in candidates if c.is_file()), None)
            if library is None:
                continue  # the system's default folders (or missing on the host too)
            if not any(library.resolve().is_relative_to(folder) for folder in shown):
                found[library] = None
            pending.append(library)  # what a shown library needs may lie elsewhere (numpy.libs' own needs)
    return tuple(found)


def elf_files(folder: Path) -> list[Path]:
    """The compiled modules and libraries in ``folder`` (a package, lib-dynload), in a stable order.

    Parameters
    ----------
    folder : pathlib.Path
        A folder, or a single file.

    Returns
    -------
    list of pathlib.Path
        The ``.so`` files (links left out), sorted.
    """
    if folder.is_file():
        return [folder] if ".so" in folder.name else []
    return sorted(p for p in folder.rglob("*.so*") if p.is_file() and not p.is_symlink())


__all__ = ["dynamic_section", "elf_files", "shared_libraries"]
