"""Output folders: a command's files written into a folder that may already hold other things.

:func:`write_folder` replaces only what the same command wrote there itself (a
manifest in the folder, :data:`MANIFEST`, says what that is, with sizes and
checksums); :func:`check_folder` says before long work whether it will be able
to. Anything else in the way is an error naming it, before anything is written.
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import stat
from collections.abc import Mapping
from pathlib import Path

from ..base.errors import InputError
from ..base.files import kind_of_file, open_regular, read_small
from .io import whole_file

#: The name of the manifest in an output folder, which lists the files each command wrote there (sizes, sha256).
MANIFEST = ".course-dynamics-files.json"
MANIFEST_FORMAT = 1
#: The largest manifest read, bytes; a larger one is refused rather than trusted.
MANIFEST_MAX_BYTES = 16 * 2**20  # some 100 000 entries: a class of thousands with three files each fits
_HEX64 = re.compile(r"[0-9a-f]{64}")


def _name_parts(name, where: str) -> tuple[str, ...]:
    """The parts of a relative file name inside a folder; InputError for anything that could leave it."""
    if not isinstance(name, str) or not name or "\x00" in name or name.startswith("/"):
        raise InputError(f"{where}: '{name}' is not a plain relative file name")
    parts = tuple(name.split("/"))
    if any(part in ("", ".", "..") for part in parts):
        raise InputError(f"{where}: '{name}' is not a plain relative file name (no '..', '.' or empty parts)")
    return parts


def _manifest_refused(path: Path, why: str) -> InputError:
    return InputError(f"{path}: {why}, so it is not a list course-dynamics wrote; nothing was written (remove it "
                      "together with the files it lists, or choose another folder)")


def _read_manifest(folder: Path) -> dict[str, dict]:
    """The folder's manifest: file name → ``{"command": …, "versions": [{"bytes": …, "sha256": …}, …]}``.

    A manifest that is a link, too large, not JSON, of another shape, or that names a file outside
    the folder is refused (InputError): trusting any part of it could let it authorise a replacement.
    """
    path = folder / MANIFEST
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return {}
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    if not stat.S_ISREG(mode):
        raise _manifest_refused(path, "is not a regular file" + (" (a symbolic link)" if stat.S_ISLNK(mode) else ""))
    try:
        raw = read_small(path, MANIFEST_MAX_BYTES, "course-dynamics manifest", follow=False)
    except InputError as exc:
        raise _manifest_refused(path, str(exc).removeprefix(f"{path}: ")) from None
    try:
        document = json.loads(raw.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError):
        raise _manifest_refused(path, "is not JSON") from None
    files = document.get("files") if isinstance(document, dict) else None
    if (not isinstance(document, dict) or document.get("course-dynamics") != MANIFEST_FORMAT
            or not isinstance(files, dict)):
        raise _manifest_refused(path, "does not have the manifest's shape")
    for name, entry in files.items():
        try:
            _name_parts(name, str(path))
        except InputError:
            raise _manifest_refused(path, f"names '{name[:80]}', which is not a file inside the folder") from None
        versions = entry.get("versions") if isinstance(entry, dict) else None
        if (not isinstance(entry, dict) or not isinstance(entry.get("command"), str) or not isinstance(versions, list)
                or not versions or not all(isinstance(v, dict) and isinstance(v.get("bytes"), int) and v["bytes"] >= 0
                                           and isinstance(v.get("sha256"), str) and _HEX64.fullmatch(v["sha256"])
                                           for v in versions)):
            raise _manifest_refused(path, f"has an entry for '{name[:80]}' of the wrong shape")
    return files


def _digest(path: Path, size_wanted: set[int]) -> str | None:
    """sha256 of the regular file ``path`` (not followed if a link), or None when its size is none of
    ``size_wanted``."""
    handle, size = open_regular(path, "file", follow=False)
    with handle:
        if size not in size_wanted:
            return None
        digest = hashlib.sha256()
        for block in iter(lambda: handle.read(2**20), b""):
            digest.update(block)
    return digest.hexdigest()


def _plan_folder(folder: Path, names, owner: str) -> tuple[dict[str, dict], dict[str, dict]]:
    """Check that every one of ``names`` may be written in ``folder`` by ``owner``, before anything is.

    Returns the folder's manifest and, for the names that replace a file of ours, the version found.
    """
    if not isinstance(owner, str) or not owner.strip():
        raise ValueError("an output folder's owner must be the name of the command writing it")
    parts = {name: _name_parts(name, str(folder)) for name in names}
    for name, path_parts in parts.items():
        if path_parts[0] == MANIFEST:
            raise InputError(f"{folder}: '{name}' is the name of the folder's manifest")
        for depth in range(1, len(path_parts)):
            if "/".join(path_parts[:depth]) in parts:
                raise InputError(f"{folder}: '{'/'.join(path_parts[:depth])}' is named as a file and as a folder")
    try:
        st = os.stat(folder)
    except FileNotFoundError:
        probe = folder.parent
        while not os.path.lexists(probe) and probe != probe.parent:
            probe = probe.parent
        if not probe.is_dir():
            raise InputError(f"{folder}: cannot make the folder: {probe}: Not a directory") from None
        if not os.access(probe, os.W_OK | os.X_OK):
            raise InputError(f"{folder}: cannot make the folder: {probe} is not writable") from None
        return {}, {}
    except OSError as exc:
        raise InputError(f"{folder}: {exc.strerror}") from None
    if not stat.S_ISDIR(st.st_mode):
        raise InputError(f"{folder}: exists and is not a directory")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"{folder}: not writable")
    manifest = _read_manifest(folder)
    refusals, replacing = [], {}
    for name, path_parts in parts.items():
        problem = _folder_chain_problem(folder, path_parts)
        if problem:
            refusals.append(problem)
            continue
        path = folder.joinpath(*path_parts)
        try:
            mode = os.lstat(path).st_mode
        except FileNotFoundError:
            continue
        entry = manifest.get(name)
        if not stat.S_ISREG(mode):
            refusals.append(f"{path}: is {kind_of_file(mode)}, not a file course-dynamics wrote; "
                            "refusing to replace it")
        elif entry is None:
            refusals.append(f"{path}: exists and was not written by course-dynamics")
        elif entry["command"] != owner:
            refusals.append(f"{path}: was written by course-dynamics {entry['command']}, not {owner}")
        else:
            versions = {v["bytes"]: v for v in entry["versions"]}
            found = _digest(path, set(versions))
            match = next((v for v in entry["versions"] if v["sha256"] == found), None)
            if match is None:
                refusals.append(f"{path}: was changed since course-dynamics {owner} wrote it")
            else:
                replacing[name] = match
    if refusals:
        more = f" (and {len(refusals) - 1} more file{'s' if len(refusals) > 2 else ''})" if len(refusals) > 1 else ""
        raise InputError(f"{refusals[0]}{more}; nothing was written (move {'them' if more else 'it'} away, or choose "
                         "another folder)")
    return manifest, replacing


def _folder_chain_problem(folder: Path, parts: tuple[str, ...]) -> str | None:
    """Why the folders on the way to ``folder/parts`` cannot be written through (a link, a file), or None."""
    path = folder
    for part in parts[:-1]:
        path = path / part
        try:
            mode = os.lstat(path).st_mode
        except FileNotFoundError:
            return None
        except OSError as exc:
            return f"{path}: {exc.strerror}"
        if not stat.S_ISDIR(mode):
            return f"{path}: is not a plain folder (a link or a file); refusing to write through it"
    return None


def _write_manifest(folder: Path, files: dict[str, dict]) -> None:
    document = {"course-dynamics": MANIFEST_FORMAT,
                "about": "the files course-dynamics wrote in this folder; it replaces only these, and only unchanged",
                "files": dict(sorted(files.items()))}
    with whole_file(folder / MANIFEST, binary=False) as handle:
        handle.write(json.dumps(document, indent=1) + "\n")


def written_by(folder, owner: str) -> list[str]:
    """The names of the files ``owner`` wrote in ``folder`` by its manifest (none for a missing folder).

    Parameters
    ----------
    folder : str or pathlib.Path
        The output folder.
    owner : str
        The command that wrote the files (``"report"``, ``"grade"``, …).

    Returns
    -------
    list of str
        The files' names relative to ``folder`` (``/`` between sub-folders), sorted.

    Raises
    ------
    InputError
        If the folder's manifest is not one course-dynamics wrote (a link, not JSON, another shape, too
        large, or naming a file outside the folder).

    Examples
    --------
    >>> written_by("/no/such/folder", "grade")
    []
    """
    folder = Path(folder)
    if not folder.is_dir():
        return []
    return sorted(name for name, entry in _read_manifest(folder).items() if entry["command"] == owner)


def check_folder(folder, names, owner: str) -> None:
    """Fail before long work unless :func:`write_folder` could write ``names`` (relative file names) into
    ``folder`` for the command ``owner`` now: InputError naming the first file in the way.

    Parameters
    ----------
    folder : str or pathlib.Path
        The output folder (it need not exist yet).
    names : iterable of str
        The relative file names to be written (``/`` makes sub-folders).
    owner : str
        The command that will write them (``"report"``, ``"grade"``, …).

    Raises
    ------
    InputError
        If a file in the way was not written by ``owner`` or was changed since, a name is not a plain
        relative file name, the folder cannot be made or written, or its manifest is not one
        course-dynamics wrote.
    ValueError
        If ``owner`` is not the name of a command.
    """
    _plan_folder(Path(folder), list(names), owner)


def write_folder(folder, files: Mapping[str, str | bytes], owner: str) -> list[Path]:
    """Write ``files`` (relative name → text or bytes; ``/`` makes sub-folders) into ``folder``, made if missing.

    ``owner`` is the command writing them (``"report"``, ``"grade"``, …). The folder keeps a manifest,
    :data:`MANIFEST`, of the files each command wrote there with their size and sha256. A file is
    written only where none exists, or over a regular file that the manifest lists as written by the
    same command and that is unchanged since (same size and sha256). Anything else in the way — a file
    course-dynamics did not write, one another command wrote, one changed since, a link, a folder, a
    sub-folder that is a link — is an InputError naming it, raised before anything is written. A
    manifest that is not one course-dynamics wrote (a link, not JSON, another shape, too large, or
    naming a file outside the folder) is refused the same way rather than trusted or ignored.

    Nothing is ever deleted: a file an earlier run wrote that this run does not write stays, and so
    does its manifest entry (a later run may still replace it). Deleting would be tidier, but a file
    may have gained a meaning for someone since (linked from a page, picked up by a script), and a
    stale page costs less than a lost one.

    Every file is written whole or not at all (:func:`~course_dynamics.output.io.output`). The
    manifest is written first, listing both the old and the new version of every file about to be
    replaced, and again at the end with the new ones only: a run interrupted half way leaves every
    file recognisable, so the next run can replace it. Sub-folders are made where missing and never
    followed if they are links.

    Parameters
    ----------
    folder : str or pathlib.Path
        The output folder, made (with its parents) if missing.
    files : Mapping of str to str or bytes
        Relative file name → contents (text is written as UTF-8).
    owner : str
        The command writing them (``"report"``, ``"grade"``, …).

    Returns
    -------
    list of pathlib.Path
        The paths written, in the order of ``files``.

    Raises
    ------
    InputError
        If anything is in the way (see above), a name is not a plain relative file name, or a file or
        folder cannot be written; raised before anything is written, except for a failure of the file
        system itself during the writing.
    ValueError
        If ``owner`` is not the name of a command.
    """
    folder = Path(folder)
    contents = {name: data.encode("utf-8") if isinstance(data, str) else bytes(data) for name, data in files.items()}
    manifest, replacing = _plan_folder(folder, list(contents), owner)
    versions = {name: {"bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}
                for name, data in contents.items()}
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{folder}: cannot make the folder: {exc.strerror}") from None
    kept = {name: entry for name, entry in manifest.items()
            if name not in contents and os.path.lexists(folder.joinpath(*name.split("/")))}
    pending = dict(kept)
    for name in contents:
        pending[name] = {"command": owner,
                         "versions": [versions[name]] + ([replacing[name]] if name in replacing else [])}
    _write_manifest(folder, pending)
    written = []
    for name, data in contents.items():
        parts = tuple(name.split("/"))
        path = folder
        for part in parts[:-1]:
            path = path / part
            try:
                os.mkdir(path)
            except FileExistsError:
                pass
            except OSError as exc:
                raise InputError(f"{path}: cannot make the folder: {exc.strerror}") from None
        problem = _folder_chain_problem(folder, parts)  # again: a link may have been planted since the check
        if problem:
            raise InputError(problem)
        target = folder.joinpath(*parts)
        with whole_file(target, binary=True) as handle:
            handle.write(data)
        written.append(target)
    _write_manifest(folder, {**kept, **{name: {"command": owner, "versions": [versions[name]]} for name in contents}})
    return written


__all__ = ["MANIFEST", "MANIFEST_MAX_BYTES", "check_folder", "write_folder", "written_by"]
