"""Decompression with a bound: how far a bag's compressed data may grow is decided before it grows.

rosbags decompresses whole and at once, before a message is read: a ROS1 chunk (bz2, lz4), an MCAP chunk
(zstd, lz4), a ROS2 bag's storage files (``compression_mode: file``, written to a temporary folder inside
``open()``) and each of its messages (``compression_mode: message``). Kilobytes of zeros compress to gigabytes.
Within :func:`bounded` (:func:`~course_dynamics.tools.bags.read_bag` holds it while it reads) every one of these
goes through a streaming decompressor that stops at its bound (:func:`bound`):

* :data:`RATIO` times the compressed bytes: real logs compress 2 to 10 times, past 100 it is a bomb;
* the memory budget (:func:`~course_dynamics.base.resources.memory_budget`), shared by a bag's storage files;
* for a storage file, also half the space free in the temporary folder, so the disk never fills.

Both sides are measured: the compressed bytes are those handed over, the output is counted as it comes; the sizes
a file declares are never used. Past the bound the read stops with one line naming the file and the chunk::

    run.bag: chunk 3 (at byte 8201) decompresses past 100x its 512 bytes: refused as a decompression bomb

How: rosbags' own decompressors (``rosbags.rosbag1.reader.decompressors``,
``rosbags.rosbag2.storage_mcap.DECOMPRESSORS`` and ``rosbags.rosbag2.reader.zstd``) are replaced by ours once, when
:func:`bounded` is first entered. Outside it ours
hand the call straight to rosbags' own, so nothing changes for other users of rosbags in the process; a kind of
compression that rosbags reads and we cannot bound is refused inside it (:data:`STREAMS`). A thread's or task's
:func:`bounded` is its own (a context variable), so reads in parallel do not meet.
"""
from __future__ import annotations

import bz2
import io
import mmap
import os
import shutil
import struct
import tempfile
import threading
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path

from ..base.errors import InputError
from ..base.resources import budget_text, format_bytes, memory_budget

#: The most a compressed chunk may grow, as a multiple of its compressed bytes.
RATIO = 100  # real logs compress 2-10x (a joint state's floats 3-5x); rosbags' own ROS1 bags of zeros, 400x
STEP = 2**23  # bytes a streaming decompressor gives at a time
ROS1_MAGIC, MCAP_MAGIC = b"#ROSBAG V2.0\n", b"\x89MCAP0\r\n"
ROS1_CHUNK, MCAP_CHUNK, MCAP_FOOTER = 0x05, 0x06, 0x02


class DecompressionBombError(InputError):
    """Compressed data that would grow past its bound (:func:`bound`); the message names the file and the chunk.

    An :class:`~course_dynamics.base.errors.InputError`: one line on the command line.
    """


@dataclass
class _Reading:
    path: Path
    stored: int = 0  # bytes of storage files decompressed so far (they share the memory budget)


_reading: ContextVar[_Reading | None] = ContextVar("course_dynamics_bag_being_read", default=None)
_install_lock = threading.Lock()
_installed: list = []  # rosbags' reader module once ours are in place


def _lz4():
    from lz4.frame import LZ4FrameDecompressor

    return LZ4FrameDecompressor()


def _zstd():  # the module rosbags uses: the standard library's from Python 3.14, else backports.zstd
    try:
        from compression import zstd
    except ImportError:
        from backports import zstd
    return zstd.ZstdDecompressor()


# What each kind's whole-data function does after one stream ends, which ours repeats: bz2.decompress goes on to the
# next stream and ignores what follows the first unless it is one; zstd.decompress reads every frame, strictly;
# lz4.frame.decompress reads the first frame and ignores the rest.
#: The kinds of compression bounded, each with its streaming decompressor and what may follow its first stream.
STREAMS = {"bz2": (bz2.BZ2Decompressor, "streams, then anything"), "zstd": (_zstd, "frames"),
           "lz4": (_lz4, "one frame")}


def bound(compressed: int, stored: int = 0, disk: bool = False) -> tuple[int, str]:
    """The most bytes ``compressed`` bytes may decompress to, and the bound's name for a message.

    The smallest of :data:`RATIO` × ``compressed``, the memory budget less ``stored`` (bytes already kept) and, with
    ``disk``, half the space free in the temporary folder.

    Parameters
    ----------
    compressed : int
        The compressed bytes.
    stored : int
        Bytes already kept from the bag, counted against the memory budget.
    disk : bool
        Whether the output goes to the temporary folder (a ROS2 bag's storage file).

    Returns
    -------
    limit : int
        The most bytes the data may decompress to.
    reason : str
        The bound's name, for a message.

    Examples
    --------
    >>> bound(512)
    (51200, '100x its 512 bytes: refused as a decompression bomb')
    """
    budget = memory_budget()
    bounds = [(RATIO * compressed, f"{RATIO}x its {format_bytes(compressed)}: refused as a decompression bomb"),
              (max(budget - stored, 0), f"the memory budget, {budget_text(budget)}" + (
                  f", less the {format_bytes(stored)} decompressed before" if stored else "") + ": refused")]
    if disk:
        free = shutil.disk_usage(tempfile.gettempdir()).free
        bounds.append((free // 2, f"half the {format_bytes(free)} free in the temporary folder: refused"))
    return min(bounds)


def decompress(kind: str, data: bytes, what) -> bytes:
    """``data`` decompressed as ``kind`` (bz2, lz4 or zstd) as rosbags' own decompressor would, within :func:`bound`.

    ``what`` names the data for the message (a string, or a function giving it, called only then).

    Parameters
    ----------
    kind : str
        ``"bz2"``, ``"lz4"`` or ``"zstd"``, a key of :data:`STREAMS`.
    data : bytes
        The compressed data.
    what : str or callable
        The data's name for the message, or a function giving it.

    Returns
    -------
    bytes
        The decompressed data.

    Raises
    ------
    DecompressionBombError
        ``what`` would decompress past the bound.
    ValueError
        Damaged data (or data that ends inside a stream), as rosbags' own decompressors raise it.
    OSError
        Damaged data, as rosbags' own decompressors raise it (and their other errors, unchanged).

    Examples
    --------
    >>> len(decompress("bz2", bz2.compress(os.urandom(5000)), "probe"))
    5000
    >>> decompress("bz2", bz2.compress(bytes(10**6)), "probe")
    Traceback (most recent call last):
    ...
    course_dynamics.tools.decompression.DecompressionBombError: probe decompresses past 100x its 48 bytes: refused \
as a decompression bomb
    """
    new, rest = STREAMS[kind]
    limit, past = bound(len(data))
    out, data, first = io.BytesIO(), bytes(data), True
    while True:
        stream = new()
        try:
            piece = stream.decompress(data, max_length=min(STEP, limit + 1))
        except OSError:
            if first or kind != "bz2":
                raise
            break  # not a stream: ignored after the first, as bz2.decompress does
        while True:
            out.write(piece)
            if out.tell() > limit:
                raise DecompressionBombError(f"{what() if callable(what) else what} decompresses past {past}")
            if stream.eof or stream.needs_input:
                break
            piece = stream.decompress(b"", max_length=min(STEP, limit + 1 - out.tell()))
        if not stream.eof:
            raise ValueError(f"{kind} data ended before the end of its stream")
        data, first = stream.unused_data, False
        if not data or rest == "one frame":
            break
    return out.getvalue()


class _BoundedStream:
    """A storage file's decompressed stream (zstd.open's) that stops at its bound (the file's :func:`bound`)."""

    def __init__(self, stream, file, reading: _Reading):
        self.stream, self.name, self.reading, self.produced = stream, getattr(file, "name", "storage file"), reading, 0
        size = os.fstat(file.fileno()).st_size if hasattr(file, "fileno") else os.stat(file).st_size
        self.limit, self.past = bound(size, reading.stored, disk=True)

    def read(self, size: int = -1) -> bytes:
        room = self.limit + 1 - self.produced
        data = self.stream.read(room if size is None or size < 0 else min(size, room))
        self.produced += len(data)
        self.reading.stored += len(data)
        if self.produced > self.limit:
            raise DecompressionBombError(f"{self.name}: decompresses past {self.past} (compression_mode file)")
        return data

    def close(self) -> None:
        self.stream.close()

    def __enter__(self):
        return self

    def __exit__(self, *_) -> None:
        self.close()


class _ReaderZstd:
    """What ``rosbags.rosbag2.reader`` calls ``zstd``: its ``open`` (compression_mode file) and ``decompress``
    (compression_mode message), bounded within :func:`bounded`; everything else is the zstd module's."""

    def __init__(self, module):
        self.module = module

    def __getattr__(self, name: str):
        return getattr(self.module, name)

    def open(self, file, mode="rb", *args, **kwargs):
        stream = self.module.open(file, mode, *args, **kwargs)
        reading = _reading.get()
        return stream if reading is None or "r" not in mode else _BoundedStream(stream, file, reading)

    def decompress(self, data, *args, **kwargs):
        reading = _reading.get()
        if reading is None or args or kwargs:
            return self.module.decompress(data, *args, **kwargs)
        return decompress("zstd", data, f"{reading.path}: a message (compression_mode message)")


def _bounded(kind: str, original):
    """rosbags' decompressor ``original`` of chunks of ``kind``, bounded within :func:`bounded`."""
    def chunk_decompressor(data, *size):  # MCAP's take the size the chunk declares as well: not used
        reading = _reading.get()
        if reading is None:
            return original(data, *size)
        if kind not in STREAMS:
            raise InputError(f"{chunk_name(reading.path, data)}: compressed with {kind}, which is not read (no "
                             "bounded decompressor for it)")
        return decompress(kind, data, lambda: chunk_name(reading.path, data))

    chunk_decompressor.bounded = True
    return chunk_decompressor


def _install() -> None:
    """Put ours in the place of rosbags' decompressors (once)."""
    with _install_lock:
        if _installed:
            return
        from rosbags.rosbag1 import reader as ros1
        from rosbags.rosbag2 import reader as ros2, storage_mcap as mcap

        for table in (ros1.decompressors, mcap.DECOMPRESSORS):
            for kind, original in table.items():
                if kind not in ("", "none") and not getattr(original, "bounded", False):
                    table[kind] = _bounded(kind, original)
        ros2.zstd = _ReaderZstd(ros2.zstd)
        _installed.append(ros2)


@contextmanager
def bounded(path):
    """Within it, what rosbags decompresses of the bag at ``path`` is bounded (module docstring).

    Parameters
    ----------
    path : str or os.PathLike
        The bag being read, named in the messages.

    Yields
    ------
    None
        The block within which rosbags' decompression is bounded.
    """
    _install()
    token = _reading.set(_Reading(Path(path)))
    try:
        yield
    finally:
        _reading.reset(token)


def chunk_name(path: Path, data: bytes) -> str:
    """"{file}: chunk {k} (at byte {n})": the chunk (counted from 1) of the bag at ``path`` that holds ``data``."""
    files = sorted(p for p in path.iterdir() if p.suffix == ".mcap") if path.is_dir() else [path]
    for file in files:
        try:
            with open(file, "rb") as handle, mmap.mmap(handle.fileno(), 0, access=mmap.ACCESS_READ) as view:
                for number, start, payload, size in _chunks(view):
                    if size == len(data) and view[payload:payload + size] == data:
                        return f"{file}: chunk {number} (at byte {start})"
        except (OSError, ValueError):  # unreadable, or empty (mmap's ValueError): not the file
            continue
    return f"{path}: a chunk of {len(data)} bytes"


def _chunks(view):
    """(number from 1, record's byte, data's byte, data's size) of each chunk of a ROS1 bag's or an MCAP file's."""
    end = len(view)
    if view[:len(ROS1_MAGIC)] == ROS1_MAGIC:
        position, number = len(ROS1_MAGIC), 0
        while position + 4 <= end:  # records: header size, header (fields: size, name=value), data size, data
            (header_size,) = struct.unpack_from("<I", view, position)
            header_end = position + 4 + header_size
            if header_end + 4 > end:
                return
            (size,) = struct.unpack_from("<I", view, header_end)
            if _ros1_op(view, position + 4, header_end) == ROS1_CHUNK:
                number += 1
                yield number, position, header_end + 4, size
            position = header_end + 4 + size
    elif view[:len(MCAP_MAGIC)] == MCAP_MAGIC:
        position, number = len(MCAP_MAGIC), 0
        while position + 9 <= end:  # records: op, length, body; a chunk's: times, size, crc, compression, data
            op, length = struct.unpack_from("<BQ", view, position)
            if op == MCAP_FOOTER:
                return
            if op == MCAP_CHUNK and position + 9 + 32 <= end:
                (name_size,) = struct.unpack_from("<I", view, position + 9 + 28)
                at = position + 9 + 32 + name_size
                if at + 8 <= end:
                    number += 1
                    yield number, position, at + 8, struct.unpack_from("<Q", view, at)[0]
            position += 9 + length


def _ros1_op(view, position: int, end: int) -> int | None:
    """The ``op`` field of the ROS1 record header between ``position`` and ``end``."""
    while position + 4 <= end:
        (size,) = struct.unpack_from("<I", view, position)
        field = view[position + 4:min(position + 4 + size, end)]
        if field[:3] == b"op=" and len(field) == 4:
            return field[3]
        position += 4 + size
    return None


__all__ = ["RATIO", "STREAMS", "DecompressionBombError", "bound", "bounded", "decompress"]
