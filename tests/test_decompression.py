"""Bounded decompression (course_dynamics.tools.decompression): ours gives what rosbags' own decompressors give, up to
its bound; bags that are decompression bombs (written by tests/bagmakers.py) are one error line through the command
line, in bounded memory and disk, with nothing written."""
from __future__ import annotations

import bz2
import os
import resource
import subprocess
import sys

import lz4.frame
import numpy as np
import pytest
from helpers import assert_one_line_error, run

import bagmakers
from bagmakers import compressed, sparse_noise, zstd
from course_dynamics import load_robot
from course_dynamics.base.errors import InputError
from course_dynamics.base.resources import BUDGET_VARIABLE
from course_dynamics.tools import decompression
from course_dynamics.tools.bags import read_bag
from course_dynamics.tools.decompression import RATIO, STEP, DecompressionBombError, bounded, chunk_name, decompress

ORIGINALS = {"bz2": bz2.decompress, "zstd": zstd.decompress, "lz4": lz4.frame.decompress}  # what rosbags calls
COMPRESS = {"bz2": bz2.compress, "zstd": zstd.compress, "lz4": lz4.frame.compress}
UR5 = load_robot("ur5").joint_names
GiB, MiB = 2**30, 2**20


def samples(rows: int = 20):
    t = 1_700_000_000.0 + 0.002 * np.arange(rows)
    q = 0.1 * np.sin(np.outer(t - t[0], np.arange(1, 7)))
    return t, q


def text_like(size: int) -> bytes:  # compresses a few times, as a log does
    rng = np.random.default_rng(1)
    return rng.choice(np.frombuffer(b"0123456789.,-e\n ", dtype=np.uint8), size).tobytes()


# ---------------------------------------------------------------- the decompressor itself

@pytest.mark.parametrize("kind", ORIGINALS)
def test_ours_gives_what_rosbags_own_decompressor_gives(kind):
    """One stream, one larger than a step (3 steps), two streams (lz4's reads the first only), and for bz2 a stream
    followed by bytes that are none (ignored by bz2.decompress)."""
    one, large = COMPRESS[kind](text_like(5000)), COMPRESS[kind](sparse_noise(3 * STEP))
    cases = [one, large, one + COMPRESS[kind](b"second")] + [one + b"not bz2 data"] * (kind == "bz2")
    for data in cases:
        assert decompress(kind, data, "probe") == ORIGINALS[kind](data)


@pytest.mark.parametrize("kind", ORIGINALS)
def test_damaged_data_fails_as_the_original_does_not_as_a_bomb(kind):
    data = COMPRESS[kind](text_like(5000))
    for damaged in (data[:len(data) // 2], data[:8] + bytes(len(data) - 8)):
        with pytest.raises(Exception) as original:
            ORIGINALS[kind](damaged)
        with pytest.raises(Exception) as ours:
            decompress(kind, damaged, "probe")
        assert not isinstance(ours.value, DecompressionBombError), (original.value, ours.value)


@pytest.mark.parametrize("kind", ORIGINALS)
def test_past_the_ratio_is_refused_naming_the_data_and_its_size(kind):
    bomb = compressed(kind, b"", 300 * MiB if kind == "lz4" else GiB)
    with pytest.raises(DecompressionBombError) as refused:
        decompress(kind, bomb, "run.bag: chunk 3 (at byte 8201)")
    assert str(refused.value) == (f"run.bag: chunk 3 (at byte 8201) decompresses past {RATIO}x its "
                                  f"{decompression.format_bytes(len(bomb))}: refused as a decompression bomb")
    assert isinstance(refused.value, InputError)


def test_the_ratio_refused_is_far_beyond_what_logs_reach():
    data = sparse_noise(4 * MiB)  # 20-50x in each: more than a log reaches, less than refused
    for kind in ORIGINALS:
        assert decompress(kind, COMPRESS[kind](data), "probe") == data


def test_the_memory_budget_bounds_what_the_ratio_allows(monkeypatch):
    data = COMPRESS["bz2"](sparse_noise(4 * MiB))
    monkeypatch.setenv(BUDGET_VARIABLE, "1M")
    with pytest.raises(DecompressionBombError, match=f"probe decompresses past the memory budget, the 1 MiB that "
                                                     f"{BUDGET_VARIABLE} allows: refused$"):
        decompress("bz2", data, "probe")
    monkeypatch.setenv(BUDGET_VARIABLE, "5M")
    assert len(decompress("bz2", data, "probe")) == 4 * MiB


# ---------------------------------------------------------------- rosbags' decompressors, replaced

def test_every_decompressor_rosbags_has_is_ours_once_a_bag_is_read(tmp_path):
    from rosbags.rosbag1 import reader as ros1
    from rosbags.rosbag2 import reader as ros2, storage_mcap as mcap

    with bounded(tmp_path):
        pass
    for table in (ros1.decompressors, mcap.DECOMPRESSORS):
        assert all(getattr(function, "bounded", False) for kind, function in table.items() if kind not in ("", "none"))
    assert isinstance(ros2.zstd, decompression._ReaderZstd)
    assert set(ros1.decompressors) - {"none"} <= set(decompression.STREAMS)
    assert set(mcap.DECOMPRESSORS) - {""} <= set(decompression.STREAMS)


def test_outside_a_read_rosbags_decompresses_as_it_always_has(tmp_path):
    from rosbags.rosbag1 import reader as ros1
    from rosbags.rosbag2 import reader as ros2, storage_mcap as mcap

    with bounded(tmp_path):
        pass
    zeros = bytes(10**7)  # 10⁵ times smaller compressed in bz2: refused within a read, not outside
    assert ros1.decompressors["bz2"](bz2.compress(zeros)) == zeros
    assert mcap.DECOMPRESSORS["zstd"](zstd.compress(zeros), len(zeros)) == zeros
    assert ros2.zstd.decompress(zstd.compress(zeros)) == zeros
    with bounded(tmp_path), pytest.raises(DecompressionBombError):
        ros1.decompressors["bz2"](bz2.compress(zeros))


def test_a_compression_rosbags_reads_and_we_cannot_bound_is_refused_within_a_read(tmp_path):
    decompressor = decompression._bounded("brotli", lambda data: data * 10**6)
    assert len(decompressor(b"ab")) == 2 * 10**6  # outside a read: rosbags' own
    with bounded(tmp_path / "run.bag"), pytest.raises(InputError, match="compressed with brotli, which is not read"):
        decompressor(b"ab")


@pytest.mark.parametrize("fmt", ["ros1", "mcap"])
def test_chunks_are_named_by_number_and_byte_as_rosbags_finds_them(tmp_path, fmt):
    """Every chunk of a bag of several (rosbags' chunks are 1 MiB), found in the file by the bytes rosbags hands over."""
    t, q = samples(12_000)
    path = bagmakers.write_joint_states(tmp_path / "long", fmt, UR5, t, q, q, q,
                                        compression="bz2" if fmt == "ros1" else "zstd")
    from rosbags.rosbag1 import Reader as Reader1
    from rosbags.rosbag2.storage_mcap import McapReader

    blob = path.read_bytes()
    if fmt == "ros1":
        with Reader1(path) as reader:  # its chunks by the byte where their record begins
            records, chunks = zip(*sorted(reader.chunks.items()))
        datas = [blob[chunk.datapos:chunk.datapos + chunk.datasize] for chunk in chunks]
    else:
        reader = McapReader(path)
        reader.open()
        chunks = sorted(reader.chunks, key=lambda chunk: chunk.chunk_start_offset)
        reader.close()
        records = [chunk.chunk_start_offset for chunk in chunks]
        starts = [chunk.chunk_start_offset + 9 + 40 + len(chunk.compression) for chunk in chunks]
        datas = [blob[start:start + chunk.compressed_size] for start, chunk in zip(starts, chunks)]
    assert len(datas) >= 3
    for number, (record, data) in enumerate(zip(records, datas), start=1):
        assert chunk_name(path, data) == f"{path}: chunk {number} (at byte {record})"
    assert chunk_name(path, b"no chunk's") == f"{path}: a chunk of 10 bytes"


# ---------------------------------------------------------------- bombs through the command line

# name: (format, compression, zero bytes after the chunk's data). lz4 compresses zeros only 250 times: its bombs are
# smaller for a file of the same size. "file": the ROS2 bag's storage file compressed (compression_mode file).
BOMBS = {"ros1-bz2": ("ros1", "bz2", 4 * GiB), "ros1-lz4": ("ros1", "lz4", GiB),
         "mcap-zstd": ("mcap", "zstd", 4 * GiB), "mcap-lz4": ("mcap", "lz4", GiB),
         "ros2-mcap-zstd": ("ros2-mcap", "zstd", 4 * GiB), "ros2-file": ("ros2-sqlite3", "file", 2 * GiB),
         "ros2-message": ("ros2-sqlite3", "message", 2 * GiB)}
AS_LIMIT, FILE_LIMIT = 3 * GiB // 2, 256 * MiB
# The command line in-process, writing its peak resident memory (bytes) to argv[1] however it ends.
PEAK = """import resource, sys
from course_dynamics.cli import main
try:
    code = main(sys.argv[2:])
finally:
    with open(sys.argv[1], "w") as out:
        out.write(str(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024))
sys.exit(code)
"""


@pytest.fixture(scope="module")
def bombs(tmp_path_factory):
    """{name: (the bomb, the file its error names)} for each of BOMBS."""
    folder, made = tmp_path_factory.mktemp("bombs"), {}
    t, q = samples()
    for name, (fmt, compression, zeros) in BOMBS.items():
        if compression == "file":
            bomb = bagmakers.file_compressed(bagmakers.write_joint_states(folder / name, fmt, UR5, t, q, q, q), zeros)
        elif compression == "message":
            bomb = bagmakers.message_bombed(bagmakers.write_joint_states(folder / name, fmt, UR5, t, q, q, q,
                                                                         compression="message"), zeros)
        else:
            bomb = bagmakers.write_joint_states(folder / name, fmt, UR5, t, q, q, q, compression=compression,
                                                zeros=zeros)
        inside = {"file": "*.zstd", "zstd": "*.mcap"}.get(compression) if bomb.is_dir() else None
        made[name] = bomb, next(bomb.glob(inside)) if inside else bomb
    return made


def run_limited(tmp_path, *argv, env=None):
    """The command line in a process of its own with at most 1.5 GiB of address space and 256 MiB a file (where
    a bomb let through ends, instead of filling the machine), its temporary folder in ``tmp_path``:
    (the finished process, its peak resident bytes or None if it was killed, the temporary folder)."""
    def limits():
        resource.setrlimit(resource.RLIMIT_AS, (AS_LIMIT, AS_LIMIT))
        resource.setrlimit(resource.RLIMIT_FSIZE, (FILE_LIMIT, FILE_LIMIT))

    peak, temp = tmp_path / "peak", tmp_path / "tmp"
    temp.mkdir()
    result = subprocess.run([sys.executable, "-c", PEAK, str(peak), *argv], capture_output=True, text=True,
                            preexec_fn=limits, env={**os.environ, "TMPDIR": str(temp), **(env or {})}, timeout=300)
    return result, int(peak.read_text()) if peak.exists() else None, temp


@pytest.fixture(scope="module")
def plain_peak(tmp_path_factory):
    """The peak resident bytes of the same command on a plain bag of the same samples, in this environment."""
    folder = tmp_path_factory.mktemp("plain")
    t, q = samples()
    qd = 0.1 * np.arange(1, 7) * np.cos(np.outer(t - t[0], np.arange(1, 7)))   # Θ̇ of samples()' Θ, so it reads
    plain = bagmakers.write_joint_states(folder / "plain", "ros1", UR5, t, q, qd, q)
    result, peak, _ = run_limited(folder, "torques", "ur5", "--log", str(plain), "--out", str(folder / "tau.csv"))
    assert result.returncode == 0, result.stderr[-2000:]
    return peak


@pytest.mark.parametrize("name", BOMBS)
def test_a_bomb_is_one_error_line_in_bounded_memory_and_disk_with_nothing_written(tmp_path, bombs, plain_peak, name):
    bomb, named = bombs[name]
    out = tmp_path / "tau.csv"
    result, peak, temp = run_limited(tmp_path, "torques", "ur5", "--log", str(bomb), "--out", str(out))
    assert result.returncode == 2, (result.returncode, result.stderr[-2000:])
    assert_one_line_error(result.returncode, result.stderr, f"error: {named}: ", f"decompresses past {RATIO}x its ",
                          "refused as a decompression bomb")
    assert not out.exists() and not list(temp.iterdir())
    size = sum(file.stat().st_size for file in ([bomb] if bomb.is_file() else bomb.iterdir()))
    # What a plain bag takes here (about 160 MiB; more in some environments), and the ratio's bound on top.
    assert peak < plain_peak + 64 * MiB + 1.5 * RATIO * size, (peak, plain_peak, size)


def test_under_a_small_memory_budget_a_chunk_within_the_ratio_is_refused(capsys, tmp_path, monkeypatch):
    """16 MiB in one chunk, compressed some 45 times: read under the usual budget, refused under one of 8 MiB."""
    t, q = samples()
    bag = bagmakers.write_joint_states(tmp_path / "noisy", "ros1", UR5, t, q, q, q, compression="bz2", noise=16 * MiB)
    assert read_bag(bag, UR5).rows == 20
    out = tmp_path / "tau.csv"
    monkeypatch.setenv(BUDGET_VARIABLE, "8M")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(bag), "--out", str(out))
    assert_one_line_error(code, err, f"error: {bag}: chunk 1 (at byte ", "decompresses past the memory budget, the "
                          f"8 MiB that {BUDGET_VARIABLE} allows: refused")
    assert not out.exists()
