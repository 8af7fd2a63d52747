"""Reading tables and writing files, the one way the project does both.

Writing: :func:`output` (and :func:`write_text`, :func:`write_bytes`,
:func:`write_csv` on top of it) writes a whole file or nothing. The data goes
to a temporary file made with ``mkstemp`` (O_EXCL, so a planted file or link
is never followed) in the target's folder, given the mode the target would
have had (the replaced file's, or the umask's), and renamed onto the target
only when complete; on any exception, Ctrl-C included, it is removed. The
rename never follows a link: a symbolic link at the target is replaced, not
written through. ``-`` means standard output, and a target that is not a
regular file (a terminal, a pipe, ``/dev/stdout``) is streamed into, never
replaced. :func:`write_new` writes a file only where none exists (a student's
notebook is never replaced), and :func:`keep_backup` keeps a copy of a file
before it is replaced on request.

A temporary file's name carries its writer's process id; one left behind by a
killed writer (SIGKILL cannot be caught) is removed by the next write to the
same target.

Output folders: :func:`write_folder` writes a command's files into a folder
that may already hold other things, and replaces only what course-dynamics
wrote there itself (a manifest in the folder says what that is);
:func:`check_folder` says before long work whether it will be able to.

Reading: :func:`open_regular` opens an input that must be a regular file (a
device, pipe or socket is refused without waiting on it); :func:`read_table`
reads a delimited numeric table as logs come (comma, semicolon or tab; UTF-8
with or without BOM, UTF-16, Latin-1; CRLF; ``#`` comment lines), refuses a
number it could read two ways, and names the file, line and column of anything
it cannot use; :func:`read_columns` picks and checks named columns from it.
"""
from __future__ import annotations

import csv
import errno
import hashlib
import io as text_io
import itertools
import json
import os
import re
import shutil
import stat
import sys
import tempfile
import time
from array import array
from collections.abc import Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import InputError

STDOUT = "-"
STREAMED_ROOTS = ("/dev/", "/proc/")  # special files and links to them: written in place


def _is_streamed(path: Path) -> bool:
    """True for ``-`` and for targets that must be written in place rather than replaced."""
    if str(path) == STDOUT or str(path).startswith(STREAMED_ROOTS):
        return True
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return False
    except OSError as exc:
        raise InputError(f"{path}: cannot write: {exc.strerror}") from None
    if stat.S_ISDIR(mode):
        raise InputError(f"{path}: is a directory")
    if stat.S_ISLNK(mode):
        try:
            target = os.stat(path).st_mode
        except OSError:
            return False  # a dangling link: replaced like a missing file
        return not (stat.S_ISREG(target) or stat.S_ISDIR(target))
    return not stat.S_ISREG(mode)


def check_distinct(inputs, outputs) -> None:
    """InputError when an output would overwrite an input or another output (the same file by any name)."""
    def key(path):
        path = Path(path)
        try:
            st = os.stat(path)
            return ("inode", st.st_dev, st.st_ino) if stat.S_ISREG(st.st_mode) else None
        except OSError:
            return ("path", str(path.resolve()))

    seen = {}
    for role, paths in (("input", inputs), ("output", outputs)):
        for path in paths:
            if path is None or str(path) == STDOUT or _is_streamed(Path(path)):
                continue
            k = key(path)
            if k is None:
                continue
            if k in seen and role == "output":
                first_role, first = seen[k]
                raise InputError(f"{path}: the output would overwrite the input {first}" if first_role == "input"
                                 else f"{path}: named for two outputs ({first} and {path} are the same file)")
            seen.setdefault(k, (role, path))


def check_writable(path) -> None:
    """Fail before long work if ``path`` cannot be written (InputError naming it)."""
    path = Path(path)
    if _is_streamed(path):
        return
    directory = path.parent
    if not directory.is_dir():
        raise InputError(f"{path}: directory {directory} does not exist")
    if not os.access(directory, os.W_OK | os.X_OK):
        raise InputError(f"{path}: not writable (directory {directory})")


def _new_file_mode(path: Path) -> int:
    try:
        st = os.lstat(path)
        if stat.S_ISREG(st.st_mode):
            return stat.S_IMODE(st.st_mode)
    except OSError:
        pass
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


TEMP_SUFFIX = ".partial"
LINKS_UNSUPPORTED = {errno.EPERM, errno.EOPNOTSUPP, errno.ENOTSUP, errno.EMLINK, errno.ENOSYS, errno.EXDEV}


def _remove_stale_temporaries(path: Path) -> None:
    """Remove ``.NAME.PID.*.partial`` files beside ``path`` whose writer no longer runs (killed with SIGKILL)."""
    prefix = f".{path.name}."
    try:
        candidates = [p for p in path.parent.iterdir() if p.name.startswith(prefix) and p.name.endswith(TEMP_SUFFIX)]
    except OSError:
        return
    for candidate in candidates:
        pid = candidate.name[len(prefix):].split(".", 1)[0]
        if not pid.isdigit() or int(pid) == os.getpid():
            continue
        try:
            os.kill(int(pid), 0)
        except ProcessLookupError:
            try:
                if stat.S_ISREG(os.lstat(candidate).st_mode):
                    candidate.unlink()
            except OSError:
                pass
        except OSError:
            pass  # the process exists (owned by someone else): not ours to clean


class _Exists(Exception):
    """The target of a write that must not replace anything appeared (or was there)."""


def _link_new(temporary: str, path: Path) -> None:
    """Give the finished ``temporary`` the name ``path`` only if no file has it (FileExistsError otherwise).

    A hard link is made atomically and never replaces; where the file system has none, the name is
    checked and the file renamed, which leaves a moment in which another writer could slip in.
    """
    try:
        os.link(temporary, path, follow_symlinks=False)
    except FileExistsError:
        raise
    except OSError as exc:
        if exc.errno not in LINKS_UNSUPPORTED:
            raise
        if os.path.lexists(path):
            raise FileExistsError(errno.EEXIST, "File exists", str(path)) from None
        os.replace(temporary, path)
    else:
        os.unlink(temporary)


@contextmanager
def _whole_file(path: Path, binary: bool, replace: bool = True, mode: int | None = None):
    """A temporary file beside ``path`` that becomes ``path`` when the block ends without an exception.

    ``replace``: renamed onto ``path`` (a link there is replaced, not followed); otherwise it takes
    the name only if nothing has it, else :class:`_Exists`. ``mode``: the new file's permission bits
    (default: the replaced file's, or the umask's).
    """
    check_writable(path)
    try:
        _remove_stale_temporaries(path)
        fd, temporary = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}.", suffix=TEMP_SUFFIX, dir=path.parent)
    except OSError as exc:
        raise InputError(f"{path}: cannot write: {exc.strerror}") from None
    try:
        os.fchmod(fd, _new_file_mode(path) if mode is None else mode)
        with os.fdopen(fd, "wb" if binary else "w", **({} if binary else {"newline": "", "encoding": "utf-8"})) as handle:
            yield handle
        if replace:
            os.replace(temporary, path)
        else:
            _link_new(temporary, path)
    except BaseException as exc:
        Path(temporary).unlink(missing_ok=True)
        if isinstance(exc, FileExistsError) and not replace:
            raise _Exists(str(path)) from None
        if isinstance(exc, OSError):
            raise InputError(f"{path}: cannot write: {exc.strerror}") from None
        raise


@contextmanager
def output(path, binary: bool = False):
    """A handle to write ``path`` whole or not at all (module docstring); ``-`` is standard output."""
    path = Path(path) if str(path) != STDOUT else STDOUT
    if path == STDOUT:
        stream = sys.stdout.buffer if binary else sys.stdout
        yield stream
        stream.flush()
        return
    if _is_streamed(path):
        try:
            handle = open(path, "wb" if binary else "w", **({} if binary else {"newline": ""}))
        except OSError as exc:
            raise InputError(f"{path}: cannot write: {exc.strerror}") from None
        try:
            with handle:
                yield handle
        except OSError as exc:
            raise InputError(f"{path}: cannot write: {exc.strerror or exc}") from None
        return
    with _whole_file(path, binary) as handle:
        yield handle


def write_text(path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path``, whole or not at all."""
    with output(path) as handle:
        handle.write(text)


def write_bytes(path, data: bytes) -> None:
    """Write ``data`` to ``path``, whole or not at all."""
    with output(path, binary=True) as handle:
        handle.write(data)


def write_new(path, data: str | bytes) -> bool:
    """Write ``data`` to ``path`` whole, only if nothing is there: True if written, False if something was.

    Nothing that exists at ``path`` (a file, a link, a folder, a pipe) is replaced or written through,
    even if it appears while the data is being written.
    """
    path = Path(path)
    if os.path.lexists(path):
        return False
    try:
        with _whole_file(path, binary=True, replace=False) as handle:
            handle.write(data.encode("utf-8") if isinstance(data, str) else data)
    except _Exists:
        return False
    return True


def keep_backup(path) -> Path:
    """Copy the regular file ``path`` to ``NAME.bak-YYYYmmdd-HHMMSS`` beside it (``-2``, ``-3``, … when taken).

    An existing file is never replaced: the backup takes the first free name. The copy keeps the
    file's mode and times, and is a file of its own (not a second link to the same one), so whatever
    is done to ``path`` afterwards cannot reach it. Returns the backup's path.
    """
    path = Path(path)
    stamp = time.strftime("%Y%m%d-%H%M%S")
    source, _ = open_regular(path, "file to back up", follow=False)
    with source:
        st = os.fstat(source.fileno())
        for count in range(1, 1000):
            backup = path.with_name(f"{path.name}.bak-{stamp}" + (f"-{count}" if count > 1 else ""))
            if os.path.lexists(backup):
                continue
            source.seek(0)
            try:
                with _whole_file(backup, binary=True, replace=False, mode=stat.S_IMODE(st.st_mode)) as handle:
                    shutil.copyfileobj(source, handle)
                    handle.flush()
                    os.utime(handle.fileno(), ns=(st.st_atime_ns, st.st_mtime_ns))
            except _Exists:
                continue
            return backup
    raise InputError(f"{path}: more than 999 backups named {path.name}.bak-{stamp}-N: remove some")


CSV_CHUNK = 10_000  # rows formatted at a time: memory stays bounded for long tables


def write_csv(path, header: list[str], data: np.ndarray, comments: list[str] = ()) -> None:
    """A header row and float rows (``repr``, so values read back exactly), whole or not at all.

    ``comments`` become ``# …`` lines before the header (what :func:`read_table` skips).
    """
    data = np.asarray(data, dtype=float)
    with output(path) as handle:
        for line in comments:
            handle.write("# " + " ".join(str(line).split()) + "\n")
        csv.writer(handle, lineterminator="\n").writerow(header)
        for start in range(0, len(data), CSV_CHUNK):
            rows = data[start:start + CSV_CHUNK].tolist()  # Python floats: repr gives the shortest exact form
            handle.write("".join(",".join(map(repr, row)) + "\n" for row in rows))


# ---------------------------------------------------------------------------- inputs that must be regular files

KINDS_OF_FILE = ((stat.S_ISFIFO, "a named pipe"), (stat.S_ISCHR, "a character device"),
                 (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def _kind_of_file(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISLNK(mode):
        return "a symbolic link"
    return next((name for test, name in KINDS_OF_FILE if test(mode)), "a special file")


def _not_regular(path, mode: int, what: str) -> InputError:
    if stat.S_ISDIR(mode) or stat.S_ISLNK(mode):
        return InputError(f"{path}: is {_kind_of_file(mode)}, not a {what}")
    return InputError(f"{path}: not a regular file ({_kind_of_file(mode)}), not a {what}")


def open_regular(path, what: str = "file", follow: bool = True):
    """``(binary handle, size in bytes)`` of ``path``, which must be a regular file.

    A directory, device, named pipe or socket is refused before it is opened, and the opened file
    is checked again (fstat): the open is non-blocking, so a pipe put in its place meanwhile is
    refused rather than waited on. ``follow=False`` refuses a symbolic link too.

    Raises
    ------
    InputError
        Naming the file: missing, unreadable, or not a regular file (saying what it is).
    """
    path = Path(path)
    try:
        mode = (os.stat if follow else os.lstat)(path).st_mode
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    if not stat.S_ISREG(mode):
        raise _not_regular(path, mode, what)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | (0 if follow else os.O_NOFOLLOW))
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        os.close(fd)
        raise _not_regular(path, st.st_mode, what)
    os.set_blocking(fd, True)
    return os.fdopen(fd, "rb"), st.st_size


def read_small(path, limit: int, what: str = "file", follow: bool = True) -> bytes:
    """The bytes of the regular file ``path`` (:func:`open_regular`), refused when larger than ``limit``."""
    handle, size = open_regular(path, what, follow)
    with handle:
        if size > limit:
            raise InputError(f"{path}: {_format_bytes(size)} is more than a {what} may be ({_format_bytes(limit)})")
        try:
            data = handle.read(limit + 1)
        except OSError as exc:
            raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    if len(data) > limit:  # it grew while being read
        raise InputError(f"{path}: more than a {what} may be ({_format_bytes(limit)})")
    return data


def _format_bytes(count: float) -> str:
    from .render import format_bytes

    return format_bytes(count)


def _memory_budget() -> int:
    # The one budget of the project (half the machine's memory), kept with the simulation's own check.
    from .simulation import memory_budget

    return memory_budget()


def check_memory(needed: float, what: str) -> None:
    """InputError ``"{what} would need about … of memory, more than half of this machine's …"`` when it would."""
    budget = _memory_budget()
    if not needed <= budget:
        raise InputError(f"{what} would need about {_format_bytes(needed)} of memory, more than half of this "
                         f"machine's {_format_bytes(2 * budget)}")


# ---------------------------------------------------------------------------- output folders

MANIFEST = ".course-dynamics-files.json"
MANIFEST_FORMAT = 1
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
    if not isinstance(document, dict) or document.get("course-dynamics") != MANIFEST_FORMAT or not isinstance(files, dict):
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
    """sha256 of the regular file ``path`` (not followed if a link), or None when its size is none of ``size_wanted``."""
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
            refusals.append(f"{path}: is {_kind_of_file(mode)}, not a file course-dynamics wrote; refusing to replace it")
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
    with _whole_file(folder / MANIFEST, binary=False) as handle:
        handle.write(json.dumps(document, indent=1) + "\n")


def check_folder(folder, names, owner: str) -> None:
    """Fail before long work unless :func:`write_folder` could write ``names`` (relative file names) into
    ``folder`` for the command ``owner`` now: InputError naming the first file in the way."""
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

    Every file is written whole or not at all (:func:`output`). The manifest is written first, listing
    both the old and the new version of every file about to be replaced, and again at the end with
    the new ones only: a run interrupted half way leaves every file recognisable, so the next run can
    replace it. Sub-folders are made where missing and never followed if they are links.

    Returns the paths written, in the order of ``files``.
    """
    folder = Path(folder)
    contents = {name: data.encode("utf-8") if isinstance(data, str) else bytes(data) for name, data in files.items()}
    manifest, replacing = _plan_folder(folder, list(contents), owner)
    versions = {name: {"bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()} for name, data in contents.items()}
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{folder}: cannot make the folder: {exc.strerror}") from None
    kept = {name: entry for name, entry in manifest.items()
            if name not in contents and os.path.lexists(folder.joinpath(*name.split("/")))}
    pending = dict(kept)
    for name in contents:
        pending[name] = {"command": owner, "versions": [versions[name]] + ([replacing[name]] if name in replacing else [])}
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
        with _whole_file(target, binary=True) as handle:
            handle.write(data)
        written.append(target)
    _write_manifest(folder, {**kept, **{name: {"command": owner, "versions": [versions[name]]} for name in contents}})
    return written


# ---------------------------------------------------------------------------- tables

DELIMITERS = (",", ";", "\t")
DELIMITER_NAMES = {",": "commas", ";": "semicolons", "\t": "tabs"}
DECIMALS = ("point", "comma")
SAMPLE_ROWS = 10               # data rows read ahead to choose the delimiter and estimate the memory needed
MAX_LINE_CHARS = 16 * 2**20    # longer is no table (a header of 10 000 joints' columns is under 1 MiB)
# Peak memory of `course-dynamics torques ur5` per value (cell) of its log, measured with /usr/bin/time -v on
# generated logs of t and six positions (7 values a row, full-precision floats, 130 bytes a row) of 20 and
# 80 MiB (1.13 and 4.52 million values): peaks of 211 and 394 MB, i.e. 55 bytes per value (2.9 per byte of
# log) beyond what the imports take; 75 bytes per value with --with-state. Before the rows were streamed
# and tau computed in blocks it was 115 bytes per value (6.2 per byte: an 80 MiB log peaked at 657 MB),
# and reading alone took 72 bytes per value where it now takes 11. Budgeted with a margin for a model
# with more joints than the log has columns.
BYTES_PER_VALUE = 100


@dataclass(frozen=True)
class Table:
    """A numeric table read from a delimited text file.

    ``header``: the column names, stripped; ``data``: float array (rows, columns);
    ``lines``: the file line number of each data row (for messages); ``path``: the file.
    """

    path: str
    header: tuple[str, ...]
    data: np.ndarray
    lines: np.ndarray

    def column(self, name: str) -> np.ndarray:
        return self.data[:, self.header.index(name)]

    def columns(self) -> dict[str, np.ndarray]:
        return {name: self.data[:, c] for c, name in enumerate(self.header)}


# A number as written in a log: ASCII digits only (Python's float() also takes '1_000', '١٢٣', '１２３'
# and surrounding Unicode spaces; numpy's reader, which the fast path uses, takes none of them).
_POINT_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_COMMA_NUMBER = re.compile(r"[+-]?(?:[0-9]+,[0-9]*|,[0-9]+)(?:[eE][+-]?[0-9]+)?")
_GROUPED = re.compile(r"[+-]?[1-9][0-9]{0,2},[0-9]{3}")   # 1,234: 1.234, or 1234 with a thousands separator
_NON_FINITE = re.compile(r"[+-]?(?:inf|infinity|nan)", re.IGNORECASE)


class _NotUTF8(Exception):
    """The file is not UTF-8 after all: read it again as Latin-1."""


def _split(line: str, delimiter: str) -> list[str]:
    """The cells of a line; a quoted cell may hold the delimiter (as the csv module writes it)."""
    return next(csv.reader([line], delimiter=delimiter)) if '"' in line else line.split(delimiter)


def _lines(path, text, comment: str, encoding: str):
    """(line number, line without its end) of every line that is neither blank nor a comment."""
    number = 0
    while True:
        try:
            line = text.readline(MAX_LINE_CHARS + 1)
        except UnicodeDecodeError:
            if encoding == "utf-16":
                raise InputError(f"{path}: not valid UTF-16 (line {number + 1})") from None
            raise _NotUTF8 from None
        if not line:
            return
        number += 1
        if len(line) > MAX_LINE_CHARS and not line.endswith("\n"):
            raise InputError(f"{path}: line {number} is longer than {MAX_LINE_CHARS // 2**20} MiB: not a table")
        stripped = line.strip()
        if stripped and not stripped.startswith(comment):
            yield number, line.rstrip("\r\n")


def _sniff(path, line_number: int, header_line: str, sample: list[str]) -> str:
    """The delimiter: the one of comma, semicolon and tab in the header (comma when none).

    When the header holds several, the one that splits the header and the first rows alike (and leaves
    none of the others in the rows, a comma excepted, which may be a decimal comma); when that does not
    settle it, the one the header uses most. A header and rows that split alike at spaces only are refused:
    spaces do not separate columns here, since a column's name may hold them.
    """
    present = [d for d in DELIMITERS if d in header_line]
    if not present:
        names = header_line.split()
        if len(names) > 1 and sample and all(len(row.split()) == len(names) for row in sample):
            raise InputError(f"{path}: line {line_number}: the columns look separated by spaces; only a comma, a "
                             "semicolon or a tab separates columns (a column's name may hold spaces)")
        return ","
    if len(present) == 1:
        return present[0]

    def fits(d):
        width = len(_split(header_line, d))
        others = [o for o in DELIMITERS if o not in (d, ",")]
        return width > 1 and all(len(_split(row, d)) == width and not any(o in row for o in others) for row in sample)

    fitting = [d for d in present if sample and fits(d)]
    if len(fitting) > 1:
        raise InputError(f"{path}: line {line_number}: the header and the rows split into columns alike at "
                         f"{' and at '.join(DELIMITER_NAMES[d] for d in fitting)}: which separates the columns is "
                         "ambiguous")
    return fitting[0] if fitting else max(present, key=header_line.count)


def _header(path, line_number: int, header_line: str, delimiter: str) -> tuple[str, ...]:
    # The header as the csv module writes it: a name holding the delimiter or a quote is quoted.
    header = tuple(name.strip() for name in next(csv.reader([header_line], delimiter=delimiter)))
    seen = set()
    for c, name in enumerate(header):
        if not name:
            raise InputError(f"{path}: line {line_number}: column {c + 1} has no name")
        if name in seen:
            raise InputError(f"{path}: line {line_number}: column '{name}' appears twice")
        seen.add(name)
    return header


def _cell_error(path, line: int, name: str, cell: str, delimiter: str, decimal: str | None) -> InputError:
    """Why a cell (stripped, unquoted) is not read: empty, a comma where none may be, not finite, not a number."""
    where = f"{path}: line {line}, column '{name}'"
    if cell == "":
        return InputError(f"{where}: empty cell")
    if _POINT_NUMBER.fullmatch(cell):
        return InputError(f"{where}: '{cell}' has a decimal point, but the decimal separator was given as a comma "
                          "(a point as a thousands separator is not read)")
    if _COMMA_NUMBER.fullmatch(cell):
        if delimiter == ",":
            return InputError(f"{where}: '{cell}' holds a comma in a comma-separated file: a decimal comma needs "
                              "semicolons or tabs between the columns")
        return InputError(f"{where}: '{cell}' has a comma, but the decimal separator was given as a point "
                          "(thousands separators are not read)")
    if _NON_FINITE.fullmatch(cell):
        return InputError(f"{where}: value is {float(cell)} (must be finite)")
    return InputError(f"{where}: '{cell[:40]}' is not a number{_why_not_a_number(cell)}")


def _why_not_a_number(cell: str) -> str:
    if "." in cell and "," in cell:
        return " (it has both a point and a comma: one of them would be a thousands separator, which is not read)"
    if cell.count(",") > 1 or cell.count(".") > 1:
        return " (thousands separators are not read)"
    if "_" in cell:
        return " ('_' between digits is not read)"
    if any(c.isdigit() and not c.isascii() for c in cell):
        return " (only the digits 0-9 are read)"
    if cell.lower().lstrip("+-").startswith("0x"):
        return " (hexadecimal is not read)"
    if re.fullmatch(r"[+-]?[0-9.,]+(?:\s+[0-9.,]+)+", cell):
        return " (a space inside a number, as a thousands separator, is not read)"
    return ""


_INTEGER_OR_COMMA = r"{pad}[+-]?(?:[0-9]+(?:,[0-9]*)?|,[0-9]+)(?:[eE][+-]?[0-9]+)?{pad}"
_INTEGER_OR_POINT = r"{pad}[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?{pad}"
BLOCK_ROWS = 8192  # rows whose cells are all plain numbers are handed to numpy's reader this many at a time


def _parse_rows(path, header, rows, delimiter: str, decimal: str | None) -> np.ndarray:
    """Row by row: the first cell that is not a number, or could be read two ways, is an error naming it.

    With ``decimal`` None a comma is a decimal comma (outside comma-separated files), unless the
    file also has a decimal point somewhere (one file, one separator), or every comma in the file is
    followed by exactly three digits (1,234 is 1.234, or 1234 with a thousands separator). A row
    whose cells are all plain numbers of one kind is checked by one pattern and read by numpy; any
    other row is read cell by cell, which finds and names what is wrong.
    """
    width = len(header)
    values, block = array("d"), []
    point = comma = grouped = None  # (line, column, cell) of the first cell with a point, a comma, a 1,234
    commas = delimiter != "," and decimal != "point"
    separator, pad = re.escape(delimiter), "[ ]*" if delimiter == "\t" else "[ \t]*"
    comma_cell, point_cell = _INTEGER_OR_COMMA.format(pad=pad), _INTEGER_OR_POINT.format(pad=pad)
    comma_row = re.compile(f"{comma_cell}(?:{separator}{comma_cell}){{{width - 1}}}")
    point_row = re.compile(f"{point_cell}(?:{separator}{point_cell}){{{width - 1}}}")

    def flush():
        if block:
            values.extend(np.loadtxt(block, delimiter=delimiter, ndmin=2, dtype=float, comments=None).ravel())
            block.clear()

    def mixed(line, c, cell, first, kind):
        there, column, seen = first
        other = "comma" if kind == "point" else "point"
        return InputError(f"{path}: line {line}, column '{header[c]}': '{cell}' has a decimal {kind}, but line "
                          f"{there}, column '{header[column]}' has '{seen}' with a {other}: a file has one decimal "
                          "separator, so one of the two is a thousands separator, and which one is ambiguous")

    for line_number, line in rows:
        has_comma, has_point = "," in line, "." in line
        if not has_comma and not (has_point and (comma or grouped or decimal == "comma")) and point_row.fullmatch(line):
            if has_point and point is None:
                c, cell = next((c, cell.strip()) for c, cell in enumerate(line.split(delimiter)) if "." in cell)
                point = (line_number, c, cell)
            block.append(line)
        elif commas and not has_point and point is None and comma_row.fullmatch(line):
            if comma is None:  # until a comma is seen that cannot be a thousands separator
                for c, cell in enumerate(line.split(delimiter)):
                    cell = cell.strip()
                    if "," in cell and comma is None:
                        if _GROUPED.fullmatch(cell):
                            grouped = grouped or (line_number, c, cell)
                        else:
                            comma = (line_number, c, cell)
            block.append(line.replace(",", "."))
        else:  # cell by cell
            flush()
            cells = _split(line, delimiter)
            if len(cells) != width:
                raise InputError(f"{path}: line {line_number} has {len(cells)} values, the header has {width}")
            for c, raw in enumerate(cells):
                cell = raw.strip()
                if '"' in cell:
                    cell = cell.strip('"')
                if _POINT_NUMBER.fullmatch(cell) and not ("." in cell and decimal == "comma"):
                    if "." in cell:
                        if comma or grouped:
                            raise mixed(line_number, c, cell, comma or grouped, "point")
                        point = point or (line_number, c, cell)
                    values.append(float(cell))
                elif commas and _COMMA_NUMBER.fullmatch(cell):
                    if point:
                        raise mixed(line_number, c, cell, point, "comma")
                    if comma is None:
                        if _GROUPED.fullmatch(cell):
                            grouped = grouped or (line_number, c, cell)
                        else:
                            comma = (line_number, c, cell)
                    values.append(float(cell.replace(",", ".")))
                else:
                    raise _cell_error(path, line_number, header[c], cell, delimiter, decimal)
        if len(block) >= BLOCK_ROWS:
            flush()
    flush()
    if grouped and not comma and decimal != "comma":
        line, c, cell = grouped
        raise InputError(f"{path}: line {line}, column '{header[c]}': '{cell}' could be {cell.replace(',', '.')} with "
                         f"a decimal comma or {cell.replace(',', '')} with a thousands separator, and no other number "
                         "in the file settles which; say it is a decimal comma (decimal='comma'; torques: --decimal "
                         "comma), or write the log with decimal points")
    return np.frombuffer(values, dtype=float).reshape(-1, width)


@dataclass(frozen=True)
class _RowLimit:
    rows: int
    message: str


def _row_limit(path, size: int, encoding: str, width: int, sample) -> _RowLimit:
    """Refuse a log whose estimated memory need (:data:`BYTES_PER_VALUE`) exceeds the budget; the rows it may have."""
    bytes_per_row = sum(len(line) + 1 for _, line in sample) / len(sample) * (2 if encoding == "utf-16" else 1)
    rows = size / max(bytes_per_row, 2.0)
    check_memory(rows * width * BYTES_PER_VALUE,
                 f"{path}: {_format_bytes(size)}, about {rows:.3g} rows of {width} values: reading and using them")
    budget = _memory_budget()
    limit = int(budget // (width * BYTES_PER_VALUE))
    return _RowLimit(limit, f"{path}: more than {limit} rows of {width} values: reading and using them would need more "
                            f"than {_format_bytes(budget)} of memory, half of this machine's {_format_bytes(2 * budget)}")


def _rows(lines, cut, numbers: array, limit: _RowLimit):
    """The data rows as (number, line) with a comment and a separator after the last column cut; records numbers."""
    for number, line in lines:
        numbers.append(number)
        if len(numbers) > limit.rows:  # the estimate from the first rows was wrong: still bounded
            raise InputError(limit.message)
        yield number, cut(line)


def read_table(path, comment: str = "#", decimal: str | None = None) -> Table:
    """Read a delimited numeric table, as trajectory logs come.

    Accepted: comma, semicolon or tab as delimiter (sniffed from the header and the first
    rows; a separator after the last column is ignored), UTF-8 with or without BOM, UTF-16
    with BOM, Latin-1, CRLF or CR line ends, blank lines, lines starting with ``comment``,
    and ``comment`` after a row's last cell. Every cell must be a finite number written with
    the digits 0-9, an optional sign, decimal separator and exponent (``-1.5e-3``).

    The decimal separator: ``decimal`` "point" or "comma", or None to read it from the file.
    A point is decimal; with semicolons or tabs a comma is too, in files that have no point:
    what could be read two ways is refused, never guessed — a file with both (is ``1.500``
    1.5 or 1500?), a cell with both (``1.234,5``), a file whose every comma is followed by
    three digits (``1,234``: 1.234 or 1234?), a comma inside a quoted cell of a comma-separated
    file. Thousands separators, ``_`` between digits, other digits than 0-9, hexadecimal and
    columns separated by spaces are refused too.

    The file must be a regular file (:func:`open_regular`: never a pipe or device, which could
    block or be endless), and the memory its rows would take in use (:data:`BYTES_PER_VALUE`
    per cell, estimated from its size before it is read, then counted while reading) must fit in
    half the machine's memory. Rows are read as a stream: the text is never held whole.

    Raises
    ------
    InputError
        Naming the file, and the line and column where it can: an unreadable, special, too large
        or empty file, a header naming a column twice or an empty name, a row with another
        number of cells than the header, an empty, non-numeric, ambiguous or non-finite cell.
    """
    if decimal not in (None, *DECIMALS):
        raise InputError(f"the decimal separator must be {' or '.join(DECIMALS)}, got '{decimal}'")
    path = Path(path)
    if str(path) == STDOUT and not os.path.lexists(path):
        raise InputError("-: a table is read from a file, not from standard input")
    handle, size = open_regular(path, "table")
    with handle:
        try:
            start = handle.read(2)
        except OSError as exc:
            raise InputError(f"{path}: cannot read: {exc.strerror}") from None
        if start in (b"\xff\xfe", b"\xfe\xff"):
            return _read_table(path, handle, size, "utf-16", comment, decimal)
        try:
            return _read_table(path, handle, size, "utf-8-sig", comment, decimal)
        except _NotUTF8:  # every byte is a Latin-1 character; numbers are ASCII in all three
            return _read_table(path, handle, size, "latin-1", comment, decimal)


def _read_table(path, handle, size: int, encoding: str, comment: str, decimal: str | None) -> Table:
    readers = []

    def data_lines():
        """A fresh pass over the file's lines: the header's first, then the data rows."""
        if readers:
            readers[-1].detach()
        handle.seek(0)
        readers.append(text_io.TextIOWrapper(handle, encoding=encoding, newline=None))  # \n, \r\n and \r end lines
        return _lines(path, readers[-1], comment, encoding)

    try:
        lines = data_lines()
        first = next(lines, None)
        if first is None:
            raise InputError(f"{path}: empty file, expected a header row")
        header_number, header_line = first
        sample = list(itertools.islice(lines, SAMPLE_ROWS))
        delimiter = _sniff(path, header_number, header_line, [line for _, line in sample])
        trailing = header_line.rstrip(" \r\n").endswith(delimiter)  # a separator after the last column, as some exports write

        def cut_trailing(line):
            line = line.rstrip(" \r\n")
            return line[:-1] if trailing and line.endswith(delimiter) else line

        def cut(line):  # a data row: a comment after its last cell goes too
            return cut_trailing(line[:line.index(comment)] if comment and comment in line else line)

        header = _header(path, header_number, cut_trailing(header_line), delimiter)
        if decimal == "comma" and delimiter == ",":
            raise InputError(f"{path}: line {header_number}: the columns are separated by commas, so no comma can be a "
                             "decimal separator (decimal='comma')")
        if not sample:
            raise InputError(f"{path}: no data rows")
        limit = _row_limit(path, size, encoding, len(header), sample)
        numbers = array("q")
        data = None
        if decimal != "comma":  # numpy's C reader for the common case; the loop below finds what it could not read
            try:
                rows = (line for _, line in _rows(itertools.chain(sample, lines), cut, numbers, limit))
                data = np.loadtxt(rows, delimiter=delimiter, ndmin=2, dtype=float, quotechar='"', comments=None)
                if data.shape != (len(numbers), len(header)):
                    data = None
            except (InputError, _NotUTF8):
                raise
            except ValueError:
                data = None
        if data is None:
            lines = data_lines()
            next(lines)
            numbers = array("q")
            data = _parse_rows(path, header, _rows(lines, cut, numbers, limit), delimiter, decimal)
        finite = np.isfinite(data)
        if not finite.all():
            r, c = np.argwhere(~finite)[0]
            raise InputError(f"{path}: line {numbers[r]}, column '{header[c]}': value is {data[r, c]} (must be finite)")
        return Table(path=str(path), header=header, data=data, lines=np.array(numbers, dtype=np.int64))
    finally:
        if readers:
            readers[-1].detach()  # the handle stays open for a second pass; its owner closes it


def read_columns(path, required: list[str], optional: list[str] = (), decimal: str | None = None) -> dict[str, np.ndarray]:
    """The named columns of a table file (:func:`read_table`), checked: every required one present and no
    column that is neither required nor optional (logs with more signals go through :mod:`course_dynamics.logs`)."""
    table = read_table(path, decimal=decimal)
    missing = [c for c in required if c not in table.header]
    if missing:
        raise InputError(f"{path}: missing columns: {', '.join(missing)}")
    unknown = [c for c in table.header if c not in required and c not in optional]
    if unknown:
        raise InputError(f"{path}: unexpected columns: {', '.join(unknown)} (expected {', '.join(required)})")
    return table.columns()


def joint_columns(kinds, joints) -> list[str]:
    """Column names ``<kind>_<joint>``, kind by kind: e.g. q_theta1, q_theta2, qd_theta1, …"""
    return [f"{kind}_{j}" for kind in kinds for j in joints]


def stack_joint_columns(columns: dict, kind: str, joints) -> np.ndarray:
    """The ``<kind>_<joint>`` columns as one array (rows, n), joints in model order."""
    return np.column_stack([columns[f"{kind}_{j}"] for j in joints])
