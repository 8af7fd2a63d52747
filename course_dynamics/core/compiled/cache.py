"""The compiled-model cache: entries trusted only from a private folder of the user, behind a keyed hash.

See :mod:`course_dynamics.core.compiled` for the rule; everything here is opened
relative to the checked folder's descriptor, and nothing in an entry runs before
its keyed hash (HMAC-SHA256 with the folder's private secret) is verified.
"""
from __future__ import annotations

import hashlib
import hmac
import marshal
import os
import stat
import warnings
from pathlib import Path

from ...base.errors import CourseDynamicsWarning

#: The value of ``COURSE_DYNAMICS_CACHE`` that turns the compiled-model cache off.
CACHE_OFF = "off"            # COURSE_DYNAMICS_CACHE=off: no cache
MAX_ENTRY_BYTES = 64 * 2**20  # a cached entry larger than this is not read (it is far above MAX_OPERATIONS' size)


class CacheWarning(CourseDynamicsWarning):
    """The cache folder cannot be trusted with code (the message says why): compiled in memory instead.

    Given once per folder and process; ``warnings.simplefilter("error", CacheWarning)`` makes it fatal.
    """


def cache_folder() -> Path | None:
    """The cache folder (module docstring); None when ``COURSE_DYNAMICS_CACHE=off``.

    ``$COURSE_DYNAMICS_CACHE``, else ``$XDG_CACHE_HOME/course-dynamics``, else ``~/.cache/course-dynamics``;
    nothing is made or checked here.

    Returns
    -------
    pathlib.Path or None
        The folder, or None when the cache is turned off.

    Examples
    --------
    >>> import os
    >>> from unittest import mock
    >>> with mock.patch.dict(os.environ, {"COURSE_DYNAMICS_CACHE": "off"}):
    ...     print(cache_folder())
    None
    """
    chosen = os.environ.get("COURSE_DYNAMICS_CACHE")
    if chosen == CACHE_OFF:
        return None
    if chosen:
        return Path(chosen)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "course-dynamics"


_warned_folders: set[str] = set()


def _only_ours(st, path, above: bool) -> str | None:
    """Why a folder with stat ``st`` could be changed by another user, or None.

    A folder ``above`` the cache may be writable by its group (``~/.cache`` under ``umask 002``) and by anyone
    if sticky (``/tmp``): the cache folder itself is checked through its own descriptor, so whatever its
    parent's group does to the path, what is opened is a private folder of this user or nothing.
    """
    what = f"the folder {path} above it" if above else "it"
    if st.st_uid not in (os.getuid(), 0):
        return f"{what} belongs to another user (uid {st.st_uid})"
    writable = st.st_mode & (0o002 if above else 0o022)
    if writable and not (above and st.st_mode & stat.S_ISVTX):
        fix = f"chmod o-w {path}" if above else f"chmod 700 {path}"
        return f"other users can write to {what} (mode {stat.S_IMODE(st.st_mode):o}; {fix})"
    return None


def _distrust(folder: Path) -> str | None:
    """Why the way to ``folder`` could be changed by another user, or None (module docstring).

    Every folder on the path as written and as resolved is checked, and every symbolic link on it
    must be ours or root's: a link is only as safe as the folder it sits in and its owner.
    """
    folder = Path(os.path.abspath(folder))
    try:
        for path in [*reversed(folder.parents), folder]:
            st = os.lstat(path)
            if stat.S_ISLNK(st.st_mode):
                if st.st_uid not in (os.getuid(), 0):
                    return f"the link {path} on its way belongs to another user (uid {st.st_uid})"
                continue
            if path != folder:
                reason = _only_ours(st, path, above=True)
                if reason:
                    return reason
        for path in folder.resolve().parents:
            reason = _only_ours(os.stat(path), path, above=True)
            if reason:
                return reason
    except OSError as exc:
        return f"it cannot be inspected ({exc.strerror})"
    return None


def _open_folder(folder: Path) -> tuple[int | None, str | None]:
    """A descriptor of ``folder`` once it is known to be only this user's, or (None, why not).

    Everything in the cache is then opened relative to this descriptor, so swapping a folder or a
    link on the way after the checks changes nothing.
    """
    reason = _distrust(folder)
    if reason:
        return None, reason
    try:
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        return None, f"it cannot be opened ({exc.strerror})"
    st = os.fstat(fd)
    reason = "it belongs to another user" if st.st_uid != os.getuid() else \
        _only_ours(st, folder, above=False)
    if reason:
        os.close(fd)
        return None, reason
    return fd, None


def _make_private(folder: Path) -> None:
    """Make ``folder`` and every missing folder above it, each mode 0700 whatever the umask (a new folder is
    set by its descriptor, never followed through a link); folders that exist are left as they are."""
    missing, path = [], Path(os.path.abspath(folder))
    while not os.path.lexists(path):
        missing.append(path)
        path = path.parent
    for path in reversed(missing):
        try:
            os.mkdir(path, 0o700)
        except FileExistsError:  # made meanwhile: checked below like any other
            continue
        fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0))
        try:
            if os.fstat(fd).st_uid == os.getuid():
                os.fchmod(fd, 0o700)
        finally:
            os.close(fd)


def _read_private(folder_fd: int, name: str, private_mode: int, limit: int) -> bytes | None:
    """The bytes of ``name`` in the folder if it is a regular file of ours, no link, no bits of ``private_mode``."""
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0), dir_fd=folder_fd)
    except OSError:
        return None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_uid != os.getuid() or st.st_mode & private_mode \
                or st.st_size > limit:
            return None
        with os.fdopen(fd, "rb", closefd=False) as handle:
            data = handle.read(limit + 1)
        return data if len(data) <= limit else None
    except OSError:
        return None
    finally:
        os.close(fd)


#: How many entries this process has written to a cache, or native libraries it has taken up from one ([count])
#: a choice remembered from before (the evaluator's one-state shortcut) is made again after either.
WRITES = [0]


def _write_private(folder_fd: int, name: str, data: bytes) -> bool:
    """Write ``name`` in the folder whole, mode 0600: a new file (O_EXCL, no link followed) renamed over it.

    The same rule as :func:`course_dynamics.output.io.output`, but relative to the checked folder's descriptor,
    which a writer of paths cannot be: a folder or link swapped on the way after the check changes nothing.
    """
    temporary = f".{name}.{os.getpid()}.{os.urandom(6).hex()}.partial"
    try:
        fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0),
                     0o600, dir_fd=folder_fd)
    except OSError:
        return False
    try:
        os.fchmod(fd, 0o600)  # whatever the umask
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
        os.replace(temporary, name, src_dir_fd=folder_fd, dst_dir_fd=folder_fd)  # a rename never follows a link
        WRITES[0] += 1
        return True
    except OSError:
        try:
            os.unlink(temporary, dir_fd=folder_fd)
        except OSError:
            pass
        return False


SECRET_BYTES = 32


def _secret(folder_fd: int) -> bytes | None:
    """The folder's 32 secret bytes, made on first use (readable by this user alone)."""
    secret = _read_private(folder_fd, "secret", 0o077, SECRET_BYTES)
    if secret is not None and len(secret) == SECRET_BYTES:
        return secret
    try:
        os.lstat("secret", dir_fd=folder_fd)
        return None  # not ours, not private, or damaged: never replaced behind the user's back
    except FileNotFoundError:
        pass
    except OSError:
        return None
    try:
        fd = os.open("secret", os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600, dir_fd=folder_fd)
    except OSError:
        return None
    with os.fdopen(fd, "wb") as handle:
        os.fchmod(fd, 0o600)  # whatever the umask
        handle.write(os.urandom(SECRET_BYTES))
    secret = _read_private(folder_fd, "secret", 0o077, SECRET_BYTES)
    return secret if secret is not None and len(secret) == SECRET_BYTES else None


class Cache:
    """Entries ``<key>.entry`` in a trusted folder: HMAC (32 bytes), source length (8), source, marshalled code.

    Used as a context manager: the folder's descriptor is closed at the end.

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as folder, Cache(Path(folder) / "cache") as cache:
    ...     path = cache.store("key", "x = 1", compile("x = 1", "<key>", "exec"))
    ...     print(path.name, cache.load("key")[0], cache.load("other"))
    key.entry x = 1 None
    """

    def __init__(self, folder: Path | None, make: bool = True):
        self.folder, self.fd, self.secret = folder, None, None
        if folder is None:
            return
        try:
            if make:
                _make_private(folder)
            elif not folder.is_dir():  # gone (deleted meanwhile): not made again
                raise FileNotFoundError(folder)
        except OSError:
            self.folder = None  # cannot be made: no cache, as documented
            return
        self.fd, reason = _open_folder(folder)
        if reason is None:
            self.secret = _secret(self.fd)
            if self.secret is None:
                reason = f"its secret file {folder / 'secret'} is not a private file of this user"
        if reason is not None:
            self.close()
            self.folder = None
            if str(folder) not in _warned_folders:
                _warned_folders.add(str(folder))
                warnings.warn(f"the compiled-model cache {folder} is not used: {reason}; compiling in memory "
                              f"(or set COURSE_DYNAMICS_CACHE={CACHE_OFF})",
                              CacheWarning, stacklevel=3)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self) -> None:
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None

    def path(self, key: str) -> Path | None:
        return None if self.folder is None else self.folder / f"{key}.entry"

    def _mac(self, key: str, body: bytes) -> bytes:
        return hmac.new(self.secret, key.encode() + b"\0" + body, hashlib.sha256).digest()

    def load(self, key: str) -> tuple[str, object] | None:
        """(source, code) of a checked entry, or None."""
        if self.folder is None:
            return None
        data = _read_private(self.fd, f"{key}.entry", 0o022, MAX_ENTRY_BYTES)
        if data is None or len(data) < 40 or not hmac.compare_digest(data[:32], self._mac(key, data[32:])):
            return None
        length = int.from_bytes(data[32:40], "little")
        try:
            return data[40:40 + length].decode("utf-8"), marshal.loads(data[40 + length:])
        except (ValueError, EOFError, TypeError, UnicodeDecodeError):
            return None

    def load_bytes(self, name: str) -> bytes | None:
        """The body of the checked file ``name`` (HMAC, then the bytes), or None: a native library."""
        if self.folder is None:
            return None
        data = _read_private(self.fd, name, 0o022, MAX_ENTRY_BYTES)
        if data is None or len(data) < 32 or not hmac.compare_digest(data[:32], self._mac(name, data[32:])):
            return None
        return data[32:]

    def store_bytes(self, name: str, body: bytes) -> Path | None:
        if self.folder is None:
            return None
        return self.folder / name if _write_private(self.fd, name, self._mac(name, body) + body) else None

    def remove(self, name: str) -> None:
        """Remove the file ``name`` from the folder, if there (never through a link: it is the link that goes)."""
        if self.folder is not None:
            try:
                os.unlink(name, dir_fd=self.fd)
            except OSError:
                pass

    def store(self, key: str, source: str, code) -> Path | None:
        if self.folder is None:
            return None
        text = source.encode("utf-8")
        body = len(text).to_bytes(8, "little") + text + marshal.dumps(code)
        return self.path(key) if _write_private(self.fd, f"{key}.entry", self._mac(key, body) + body) else None


__all__ = ["CACHE_OFF", "CacheWarning", "cache_folder"]
