"""ROS bags as robots' recorders write them, from a known motion (``logmakers.multisine``), written with rosbags.

Formats (:data:`FORMATS`): a ROS1 ``.bag``; ROS2 bag folders with sqlite3 or MCAP storage; a bare
``.mcap`` file (the one file of such a folder, moved out of it). Messages are dicts of their fields
(:func:`joint_states`, :func:`franka_states`); :func:`write_bag` makes them messages of the format's
ROS version, with every field a real message has (zeros for those not given).

Stamps: a time t (s) is stamped as sec = ⌊t⌋, nanosec = round((t − sec)·1e9) (:func:`stamp`); a reader
gives back sec + nanosec·1e-9 (:func:`stamped_seconds`), within 0.5 ns of t plus float rounding.

Compression (:func:`write_bag`'s ``compression``): a ROS1 bag's chunks in bz2 or lz4, an MCAP file's chunks in zstd
or lz4, a ROS2 bag's messages one by one (``message``); :func:`file_compressed` compresses a ROS2 bag's storage files
(``compression_mode: file``). Decompression bombs: ``zeros`` bytes of zeros after every chunk's own data (or a
storage file's), while the chunk's header still declares its own size; zeros compress 10⁶ times in bz2, 3·10⁴ in
zstd and 250 in lz4 (:func:`compressed`), so a few kilobytes stand for gigabytes.
"""
from __future__ import annotations

import bz2
import math
import shutil
import sqlite3
from contextlib import closing
from functools import lru_cache
from pathlib import Path

import lz4.frame
import numpy as np
from rosbags.rosbag1 import Writer as Writer1
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer as Writer2

try:  # the zstd module rosbags uses
    from compression import zstd
except ImportError:
    from backports import zstd

from course_dynamics.tools.bags import FRANKA_STATE, JOINT_STATE, typestore

FORMATS = ("ros1", "ros2-sqlite3", "ros2-mcap", "mcap")
SUFFIXES = {"ros1": ".bag", "ros2-sqlite3": "", "ros2-mcap": "", "mcap": ".mcap"}
FRANKA_TOPIC = "/franka_state_controller/franka_states"
FRANKA_JOINT_STATES = "/franka_state_controller/joint_states"
LATENCY_NS = 200_000  # a message reaches the recorder 0.2 ms after its stamp


def stamp(t: float) -> tuple[int, int]:
    sec = math.floor(t)
    nanosec = round((t - sec) * 1e9)
    return (sec + 1, nanosec - 10**9) if nanosec >= 10**9 else (sec, nanosec)


def stamped_seconds(t) -> np.ndarray:
    """What a reader gives back for the times ``t`` once stamped: sec + nanosec·1e-9."""
    return np.array([sec + nanosec * 1e-9 for sec, nanosec in map(stamp, t)])


def joint_states(joints, t, q, qd=None, tau=None, extra=("gripper_finger_joint",), shuffle_seed: int | None = 0,
                 drop=None):
    """sensor_msgs/JointState messages: ``q``, ``qd``, ``tau`` (K, n) for ``joints``; no velocity or effort when None.

    ``extra`` joints (a gripper's) are added with values of their own; ``shuffle_seed`` shuffles the order of
    the names in every message anew (None keeps the model's order); ``drop`` maps a message index (from 0)
    to a joint that message leaves out.
    """
    rng = np.random.default_rng(shuffle_seed)
    drop = drop or {}
    names = list(joints) + list(extra)
    messages = []
    for k, time in enumerate(t):
        rows = [np.append(block[k], 0.01 * np.arange(1, len(extra) + 1)) if block is not None else None
                for block in (q, qd, tau)]
        order = rng.permutation(len(names)) if shuffle_seed is not None else np.arange(len(names))
        order = [i for i in order if names[i] != drop.get(k)]
        messages.append({"stamp": stamp(time), "name": [names[i] for i in order],
                         **{field: np.array([row[i] for i in order]) if row is not None else np.zeros(0)
                            for field, row in zip(("position", "velocity", "effort"), rows)}})
    return messages


def franka_states(t, q, qd, tau):
    """franka_msgs/FrankaState messages (what franka_state_controller publishes): q, dq, tau_J (K, 7)."""
    q, qd, tau = (np.ascontiguousarray(block, dtype=float) for block in (q, qd, tau))
    return [{"stamp": stamp(time), "q": q[k], "dq": qd[k], "tau_J": tau[k],
             "q_d": q[k] + 1e-4, "time": float(time) - float(t[0])} for k, time in enumerate(t)]


def _message(store, msgtype: str, ros1: bool, values: dict, seq: int = 0):
    """A message of ``msgtype`` with ``values`` (``stamp`` for its header), every other field zero."""
    fields = {}
    for name, (node, detail) in store.fielddefs[msgtype][1]:
        kind = node.name
        if name in values:
            fields[name] = values[name]
        elif name == "header":
            sec, nanosec = values["stamp"]
            time = store.types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec)
            header = {"seq": seq, "stamp": time, "frame_id": "panda_link0"} if ros1 else {"stamp": time,
                                                                                          "frame_id": "panda_link0"}
            fields[name] = store.types["std_msgs/msg/Header"](**header)
        elif kind == "NAME":
            fields[name] = _message(store, detail, ros1, {})
        elif kind == "ARRAY":
            fields[name] = np.zeros(detail[1], dtype=float)
        elif kind == "SEQUENCE":
            fields[name] = np.zeros(0, dtype=float) if detail[0][1][0] == "float64" else []
        else:
            fields[name] = {"bool": False, "string": ""}.get(detail[0], 0)
    return store.types[msgtype](**fields)


ZERO_UNITS = {"bz2": 45_000_000, "zstd": 2**27, "lz4": 2**22}  # zeros in one bz2 stream (its most), zstd frame


@lru_cache(maxsize=None)
def _zeros(kind: str) -> bytes:  # ZERO_UNITS[kind] zeros compressed: bz2 streams and zstd frames follow each other
    return {"bz2": bz2.compress, "zstd": zstd.compress}[kind](bytes(ZERO_UNITS[kind]))


def sparse_noise(size: int, every: int = 100, seed: int = 0) -> bytes:
    """``size`` zero bytes but one random byte in about ``every``: it compresses some 20-50 times, as no real log
    does but well within the ratio refused as a bomb."""
    rng = np.random.default_rng(seed)
    data = np.zeros(size, dtype=np.uint8)
    data[rng.integers(0, size, size // every)] = rng.integers(1, 256, size // every)
    return data.tobytes()


def compressed(kind: str, data: bytes, zeros: int = 0) -> bytes:
    """``data`` followed by at least ``zeros`` zero bytes, compressed as ``kind`` (bz2, zstd, lz4), as fast as can be.

    bz2 and zstd: ``data``'s stream (frame) followed by copies of one of zeros; lz4 (whose decompress reads one
    frame): one frame, fed the zeros 4 MiB at a time.
    """
    if kind == "lz4":
        compressor = lz4.frame.LZ4FrameCompressor()
        pieces = [compressor.begin(), compressor.compress(data)]
        unit = bytes(ZERO_UNITS["lz4"])
        pieces += [compressor.compress(unit) for _ in range(-(-zeros // len(unit)))]
        return b"".join(pieces + [compressor.flush()])
    own = {"bz2": bz2.compress, "zstd": zstd.compress}[kind](data)
    return own + _zeros(kind) * -(-zeros // ZERO_UNITS[kind])


def write_bag(path, fmt: str, topics: dict, compression: str | None = None, zeros: int = 0, noise: int = 0) -> Path:
    """A bag at ``path`` (plus the format's suffix) holding ``topics`` {topic: (msgtype, [message dicts])}.

    Messages of all topics are written in the order they reach the recorder: LATENCY_NS after their stamp,
    and never before the one written last (so a message stamped earlier than the previous one stays after it).
    ``compression``: the chunks' (bz2 or lz4 for ROS1, zstd or lz4 for MCAP), or ``message`` (ROS2: each message
    compressed with zstd); ``zeros``: that many zero bytes compressed after each chunk's data (module docstring);
    ``noise``: that many bytes of :func:`sparse_noise` after each chunk's data (before the zeros).
    """
    path = Path(str(path) + SUFFIXES[fmt])
    ros1 = fmt == "ros1"
    store = typestore(ros1)
    if ros1:
        writer = Writer1(path)
        if compression:
            writer.set_compression(Writer1.CompressionFormat[compression.upper()])
    else:
        plugin = StoragePlugin.SQLITE3 if fmt == "ros2-sqlite3" else StoragePlugin.MCAP
        writer = Writer2(path.with_suffix("") if fmt == "mcap" else path, version=9, storage_plugin=plugin)
        if compression:
            writer.set_compression(CompressionMode.MESSAGE if compression == "message" else CompressionMode.STORAGE,
                                   CompressionFormat.ZSTD)
    pending = []
    for topic, (msgtype, messages) in topics.items():
        last = 0
        for seq, values in enumerate(messages):
            sec, nanosec = values["stamp"]
            last = max(sec * 10**9 + nanosec + LATENCY_NS, last + 1)
            pending.append((last, topic, msgtype, seq, values))
    with writer:
        if compression and compression != "message":  # rosbags' own compressor, made ours
            storage = writer if ros1 else writer.storage
            if not ros1:  # an MCAP chunk names its compression (a ROS1 chunk's is set_compression's)
                storage.compression = compression
            storage.compressor = lambda data: compressed(compression, data + sparse_noise(noise), zeros)
        connections = {topic: writer.add_connection(topic, msgtype, typestore=store)
                       for topic, (msgtype, _) in topics.items()}
        for received, topic, msgtype, seq, values in sorted(pending, key=lambda item: item[0]):
            message = _message(store, msgtype, ros1, values, seq)
            data = store.serialize_ros1(message, msgtype) if ros1 else store.serialize_cdr(message, msgtype)
            writer.write(connections[topic], received, data)
    if fmt == "mcap":  # the folder's one storage file, alone
        folder = path.with_suffix("")
        (storage,) = folder.glob("*.mcap")
        shutil.move(storage, path)
        shutil.rmtree(folder)
    return path


def without_definitions(folder) -> Path:
    """The ROS2 sqlite3 bag ``folder`` with its message definitions deleted, as rosbag2 before Iron recorded."""
    (database,) = Path(folder).glob("*.db3")
    with closing(sqlite3.connect(database)) as connection, connection:
        connection.execute("DELETE FROM message_definitions")
    return Path(folder)


def write_joint_states(path, fmt: str, joints, t, q, qd=None, tau=None, topic="/joint_states", compression=None,
                       zeros: int = 0, noise: int = 0, **options) -> Path:
    """A bag of one JointState topic (:func:`joint_states` with ``options``; :func:`write_bag`'s compression)."""
    return write_bag(path, fmt, {topic: (JOINT_STATE, joint_states(joints, t, q, qd, tau, **options))}, compression,
                     zeros, noise)


def write_franka(path, fmt: str, joints, t, q, qd, tau) -> Path:
    """A bag as franka_ros records one: FrankaState and the JointState of the arm's 7 joints, effort = τ_J."""
    return write_bag(path, fmt, {
        FRANKA_TOPIC: (FRANKA_STATE, franka_states(t, q, qd, tau)),
        FRANKA_JOINT_STATES: (JOINT_STATE, joint_states(joints[:7], t, q, qd, tau, extra=(), shuffle_seed=None)),
    })


def file_compressed(folder, zeros: int = 0) -> Path:
    """The ROS2 bag ``folder`` with its storage files compressed with zstd, as ``ros2 bag record --compression-mode
    file`` leaves them (``x.db3.zstd``, metadata.yaml saying so), ``zeros`` zero bytes compressed after each."""
    folder = Path(folder)
    metadata = folder / "metadata.yaml"
    text = metadata.read_text()
    for storage in sorted(p for p in folder.iterdir() if p.suffix in (".db3", ".mcap")):
        (folder / (storage.name + ".zstd")).write_bytes(compressed("zstd", storage.read_bytes(), zeros))
        storage.unlink()
        text = text.replace(f"- {storage.name}\n", f"- {storage.name}.zstd\n").replace(
            f"path: {storage.name}\n", f"path: {storage.name}.zstd\n")
    assert "compression_mode: ''" in text and "compression_format: ''" in text, text
    metadata.write_text(text.replace("compression_mode: ''", "compression_mode: FILE").replace(
        "compression_format: ''", "compression_format: zstd"))
    return folder


def message_bombed(folder, zeros: int) -> Path:
    """The ROS2 sqlite3 bag ``folder`` (written with compression ``message``) whose first message is followed by
    ``zeros`` zero bytes inside its compressed data."""
    (database,) = Path(folder).glob("*.db3")
    with closing(sqlite3.connect(database)) as connection, connection:
        data = connection.execute("SELECT data FROM messages ORDER BY id LIMIT 1").fetchone()[0]
        connection.execute("UPDATE messages SET data = ? WHERE id = (SELECT MIN(id) FROM messages)",
                           (compressed("zstd", zstd.decompress(data), zeros),))
    return Path(folder)
