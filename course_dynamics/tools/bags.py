"""Robot logs from ROS bags, read without ROS (the pure-Python ``rosbags`` package).

==================  ================================  ===========================================
our column          read from                         meaning (shape, unit)
==================  ================================  ===========================================
``t``               ``header.stamp``                  sec + nanosec·1e-9 as stamped, absolute
                                                      (not shifted to start at 0) (N,), s
``q_<joint>``       JointState ``position``,          Θⱼ (N,), rad or m
                    FrankaState ``q``
``qd_<joint>``      JointState ``velocity``,          Θ̇ⱼ (N,), rad/s or m/s
                    FrankaState ``dq``
``tau_meas_<j>``    JointState ``effort``,            measured τⱼ (N,), N·m or N (on a Franka
                    FrankaState ``tau_J``             τ_J, the link-side joint torque sensors)
==================  ================================  ===========================================

Bags: a ROS1 ``.bag`` file, a ROS2 bag folder (``metadata.yaml`` beside sqlite3 or MCAP storage files) and a
bare ``.mcap`` file (:func:`is_bag`). The message types are read from the bag itself (ROS1 bags always carry their
definitions, ROS2 bags recorded since Iron do); a bag without them is read with the definitions of ROS1 Noetic or
ROS2 Humble plus our ``franka_msgs``; a ROS2 bag folder's metadata.yaml and files are checked first (:func:`read_bag`).

Messages (one topic, :func:`read_bag`):

* ``sensor_msgs/JointState``: joints matched by name in every message, whatever the order (which may change between
  messages); joints of a message that are not ours (a gripper's) are ignored, messages holding none of ours (a
  gripper's own) skipped, with a note. ``velocity`` and ``effort`` are read only when every message has them (ROS
  allows empty arrays); a joint of ours that no message names is left out, one that some messages lack is an error.
* ``franka_msgs/FrankaState`` (franka_ros' ``/franka_state_controller/franka_states``): the arrays hold the 7 arm
  joints in order, given to the first 7 of ``joints`` (panda_joint1…7).

Messages are counted from 1 in the order of the bag (its receive times); the header stamps must increase strictly
along them. Names from the bag reach notes and errors with their control characters escaped. What rosbags decompresses
(chunks, ROS2 storage files and messages) is bounded before it grows (:mod:`~course_dynamics.tools.decompression`).
"""
from __future__ import annotations

import itertools
import os
import stat
from array import array
from contextlib import suppress
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from ..base.files import kind_of_file, read_small
from ..base.resources import budget_text, check_memory, memory_budget
from ..base.text import one_line
from .bagtypes import FRANKA_STATE, JOINT_STATE, typestore
from .decompression import bounded

MESSAGE_TYPES = (JOINT_STATE, FRANKA_STATE)
DEFAULT_TOPIC, FRANKA_JOINTS = "/joint_states", 7
KINDS = ("q", "qd", "tau_meas")
JOINT_STATE_FIELDS = {"q": "position", "qd": "velocity", "tau_meas": "effort"}
FRANKA_STATE_READ = {"q": "q", "qd": "dq", "tau_meas": "tau_J"}
#: The suffixes of the files read as bags (a ROS2 bag's folder is told by its metadata.yaml).
BAG_SUFFIXES = (".bag", ".mcap")  # as rosbags spells them (it tells a ROS1 bag by its suffix alone)
METADATA, METADATA_LIMIT = "metadata.yaml", 16 * 2**20
# What rosbags 0.11 reads of a ROS2 bag's metadata.yaml (its rosbag2_bagfile_information): a type, a mapping of
# keys (others are allowed) or a list of one shape. METADATA_ERRORS: rosbags' texts we report as ours.
METADATA_SHAPE = {"version": int, "storage_identifier": str, "relative_file_paths": [str], "message_count": int,
                  "duration": {"nanoseconds": int}, "starting_time": {"nanoseconds_since_epoch": int},
                  "topics_with_message_count": [{"message_count": int, "topic_metadata": {
                      "name": str, "type": str, "serialization_format": str}}]}
METADATA_ERRORS = ("Invalid bag metadata", "A metadata key", "Serialization format", "Compression format")
STORAGE_IDS, BAG_VERSIONS = ("sqlite3", "mcap"), range(1, 10)
SKIPPED_NAMES = 5  # at most this many joint names of skipped messages in the note
# Peak memory of read_bag per value of the columns it returns (1 + 3n a message), measured with tracemalloc on bags
# of 200 001 UR5 JointState messages (3.8 million values, about 80 MB in each format): 11 bytes per value from ROS2
# sqlite3 and MCAP bags (8 for the columns, the rest the buffers' growth and the stamps), 19 from a ROS1 bag (rosbags
# holds its index, about 150 bytes a message). Using them as `torques` uses a table took 44 bytes per value beyond
# reading it (tables.BYTES_PER_VALUE); budgeted with a like margin. Reading took 26 (sqlite3) to 35 (ROS1) µs a
# message, most of it rosbags decoding it.
#: Bytes of memory a bag's value (1 + 3 n a message) is budgeted at, read and in use.
BYTES_PER_VALUE = 100

@dataclass(frozen=True)
class BagLog:
    """Our columns (module docstring; read-only arrays (rows,)) from one topic of a bag. ``where`` names the bag and
    topic for messages ("run.bag, topic /joint_states"); ``notes`` says what was left out or skipped, and why.

    Parameters
    ----------
    columns : dict of str to numpy.ndarray
        Our columns (``t`` s, ``q_<joint>`` rad or m, ``qd_<joint>`` rad/s or m/s, ``tau_meas_<joint>`` N·m or N),
        each of shape (rows,), read-only.
    where : str
        The bag and topic, for messages.
    rows : int
        The messages read.
    notes : tuple of str
        What was left out or skipped, and why.
    """

    columns: dict[str, np.ndarray]
    where: str
    rows: int
    notes: tuple[str, ...] = ()


def is_bag(path) -> bool:
    """Whether ``path`` is read as a bag: a ``.bag`` or ``.mcap`` file, or a folder holding ``metadata.yaml``.

    Parameters
    ----------
    path : str or os.PathLike
        A file or folder.

    Returns
    -------
    bool
        Whether it is read as a bag (by its name and folder only; its content is checked by :func:`read_bag`).
    """
    path = Path(path)
    return os.path.lexists(path / METADATA) if path.is_dir() else path.suffix in BAG_SUFFIXES


def _reason(exc: Exception) -> str:
    lines = str(exc).replace("; please report issue", "").strip().splitlines()
    return lines[0][:200] if lines else type(exc).__name__


def _fits(value, shape) -> bool:  # whether value has METADATA_SHAPE's shape: a type, a mapping's keys, a list
    if isinstance(shape, dict):
        return isinstance(value, dict) and all(_fits(value.get(key), inner) for key, inner in shape.items())
    if isinstance(shape, list):
        return isinstance(value, list) and all(_fits(item, shape[0]) for item in value)
    return type(value) is shape  # a bool is no int here


def _check_path(path: Path) -> None:
    """A regular file, or a folder whose metadata.yaml holds what rosbags reads and whose files are regular or folders
    (rosbags would wait forever on a named pipe); else an InputError saying what it is instead."""
    try:
        mode = os.stat(path).st_mode
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    if not stat.S_ISDIR(mode):
        if not stat.S_ISREG(mode):
            raise InputError(f"{path}: not a regular file ({kind_of_file(mode)}), not a bag")
        if path.suffix not in BAG_SUFFIXES:
            raise InputError(f"{path}: not a bag: bags are .bag files (ROS1), .mcap files and ROS2 bag folders "
                             "(holding metadata.yaml)")
        return
    if not os.path.lexists(path / METADATA):
        raise InputError(f"{path}: a directory without metadata.yaml, not a ROS2 bag")
    try:  # a link's target's mode, wherever it is; a dangling link skipped (rosbags reports it if it is named)
        inside = [(entry, os.stat(entry.path).st_mode) for entry in os.scandir(path) if os.path.exists(entry.path)]
    except OSError as exc:
        raise InputError(f"{exc.filename}: cannot read: {exc.strerror}") from None
    for entry, mode in inside:
        if not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
            raise InputError(f"{entry.path}: not a regular file ({'a link to ' * entry.is_symlink()}"
                             f"{kind_of_file(mode)}), in a ROS2 bag folder")
    text = read_small(path / METADATA, METADATA_LIMIT, "ROS2 bag's metadata")  # refuses a pipe without waiting
    from ruamel.yaml import YAML

    wrong = f"{path}: {METADATA} is not a ROS2 bag's metadata"
    try:
        document = YAML(typ="safe").load(text)  # rosbags' own loader; "safe": no tag makes an object or runs code
    except Exception as exc:  # the parser's: a YAMLError, a RecursionError from deep nesting
        raise InputError(f"{wrong} (not YAML: {_reason(exc)})") from None
    info = document.get("rosbag2_bagfile_information") if isinstance(document, dict) else None
    if bad := ["rosbag2_bagfile_information"] if not isinstance(info, dict) else [
            key for key, shape in METADATA_SHAPE.items() if not _fits(info.get(key), shape)]:
        raise InputError(f"{wrong} ({', '.join(bad)} missing or not as rosbags reads them)")
    if info["version"] not in BAG_VERSIONS or info["storage_identifier"] not in STORAGE_IDS:
        raise InputError(f"{wrong} (version {info['version']}, {info['storage_identifier']} storage: rosbags reads "
                         f"versions {BAG_VERSIONS[0]} to {BAG_VERSIONS[-1]}, {' or '.join(STORAGE_IDS)} storage)")


def _stamp_text(ns: int) -> str:
    return f"t = {ns // 10**9}.{ns % 10**9:09d} s"


def _topic_list(topics) -> str:
    return ", ".join(f"{name} ({info.msgtype or 'several types'})" for name, info in sorted(topics.items())) or "none"


def _choose_topic(path, topics, topic: str | None) -> str:
    """The topic to read: ``topic``, else /joint_states, else the only JointState or FrankaState one of ``topics``
    (each topic of the bag to an object with a ``msgtype``, rosbags' TopicInfo)."""
    if topic is not None:
        if topic not in topics:
            raise InputError(f"{path}: no topic {topic}; the bag's topics: {_topic_list(topics)}")
        if topics[topic].msgtype not in MESSAGE_TYPES:
            raise InputError(f"{path}: topic {topic} holds {topics[topic].msgtype or 'messages of several types'}; "
                             f"joint logs are read from {' or '.join(MESSAGE_TYPES)}")
        return topic
    if DEFAULT_TOPIC in topics and topics[DEFAULT_TOPIC].msgtype == JOINT_STATE:
        return DEFAULT_TOPIC
    candidates = sorted(name for name, info in topics.items() if info.msgtype in MESSAGE_TYPES)
    if len(candidates) == 1:
        return candidates[0]
    if candidates:
        raise InputError(f"{path}: several topics hold joint states: {_topic_list({c: topics[c] for c in candidates})}"
                         "; say which with --topic")
    raise InputError(f"{path}: no topic holds {' or '.join(MESSAGE_TYPES)}; the bag's topics: {_topic_list(topics)}")


def read_bag(path, joints: tuple[str, ...], topic: str | None = None) -> BagLog:
    """Our columns ``t``, ``q_<joint>``, ``qd_<joint>``, ``tau_meas_<joint>`` from one topic of a ROS bag.

    ``joints``: the model's joint names (Θ's order). ``topic``: when None, ``/joint_states`` if the bag has it, else
    the bag's only JointState or FrankaState topic. The messages are read as a stream into growing buffers, never
    held whole; the memory the columns need in use (:data:`BYTES_PER_VALUE` per value) is checked against the budget
    from the bag's message count before reading, and against the messages counted while reading. What rosbags
    decompresses is bounded by what it measures (:func:`~course_dynamics.tools.decompression.bounded`).

    Usage (not run here: it needs a bag)::

        log = read_bag("run.bag", load_robot("ur5").joint_names)
        log.columns["q_elbow_joint"]        # (log.rows,), rad

    Parameters
    ----------
    path : str or os.PathLike
        A ``.bag`` or ``.mcap`` file, or a ROS2 bag's folder.
    joints : tuple of str
        The model's joint names, in Θ's order.
    topic : str, optional
        The topic to read.

    Returns
    -------
    BagLog
        Our columns, the bag's name and the notes.

    Raises
    ------
    InputError
        Naming the bag, and the topic, message (counted from 1), time and joint where it can: a path that is no bag
        or a damaged bag, a ROS2 bag folder holding a named pipe (or device, socket) or metadata rosbags cannot read;
        a missing topic (listing the bag's topics and types) or several candidates; a message lacking a joint others
        have (one holding none is skipped), with names and values of different lengths, or with a non-finite value;
        stamps that repeat or go back; a chunk (storage file, message) decompressing past its bound.
    """
    try:
        with bounded(path):
            log = _read_bag(Path(path), tuple(joints), topic)
    except InputError as exc:  # names from the bag (topics, types, joints) and rosbags' texts made safe to print
        raise InputError(one_line(str(exc))) from None
    return BagLog(log.columns, one_line(log.where), log.rows, tuple(map(one_line, log.notes)))


def _read_bag(path: Path, joints: tuple[str, ...], topic: str | None) -> BagLog:
    _check_path(path)
    from rosbags.highlevel import AnyReader  # lazily, as in typestore()

    # Every exception from rosbags' own calls means this file cannot be read as a bag: damaged files surface from its
    # parsers (and apsw, lz4, zstd) as errors of many kinds, a length read as 2**62 as a MemoryError. Only those
    # calls are inside the try blocks, so a bug of ours keeps its traceback.
    try:  # typestore: AnyReader's own rule for a ROS1 bag
        reader = AnyReader([path], default_typestore=typestore(path.suffix == ".bag"))
        reader.open()
        topics = reader.topics
    except Exception as exc:
        if isinstance(exc, InputError):  # ours: a decompression refused
            raise
        if path.is_dir() and _reason(exc).startswith(METADATA_ERRORS):  # what _check_folder does not check
            raise InputError(f"{path}: {METADATA} is not a ROS2 bag's metadata ({_reason(exc)})") from None
        raise InputError(f"{path}: not a bag, or a damaged one ({_reason(exc)})") from None
    try:
        topic = _choose_topic(path, topics, topic)
        where, msgtype, count = f"{path}, topic {topic}", topics[topic].msgtype, topics[topic].msgcount
        _check_definition(reader.typestore, msgtype, where)
        if msgtype == FRANKA_STATE and len(joints) < FRANKA_JOINTS:
            raise InputError(f"{where}: {FRANKA_STATE} holds {FRANKA_JOINTS} arm joints in order, but the robot has "
                             f"{len(joints)} joints ({', '.join(joints)})")
        width = 1 + len(KINDS) * (len(joints) if msgtype == JOINT_STATE else FRANKA_JOINTS)
        check_memory(count * width * BYTES_PER_VALUE, f"{where}: {count} messages of {width} values: reading and "
                                                      "using them")
        connections = [c for c in reader.connections if c.topic == topic]
        messages = _messages(reader, connections, where, memory_budget() // (width * BYTES_PER_VALUE))
        return (_read_joint_states if msgtype == JOINT_STATE else _read_franka_states)(messages, joints, where)
    finally:
        with suppress(Exception):  # rosbags' (see above); what was read stands
            reader.close()


def _check_definition(store, msgtype: str, where: str) -> None:
    """The bag's own definition of ``msgtype`` has the fields we read, of our types (a bag may define it its way)."""
    def fields(name):
        return dict(store.fielddefs[name][1]) if name in store.fielddefs else {}

    def array_of(field):  # ("SEQUENCE" or "ARRAY", element type, length) of an array of a base type
        node, detail = field
        is_array = node.name in ("ARRAY", "SEQUENCE") and detail[0][0].name == "BASE"
        return (node.name, detail[0][1][0], detail[1]) if is_array else None

    ours = fields(msgtype)
    header = fields(ours["header"][1]) if "header" in ours else {}
    joint_state = msgtype == JOINT_STATE
    wanted = {"name": ("SEQUENCE", "string", 0)} if joint_state else {}
    wanted |= dict.fromkeys((JOINT_STATE_FIELDS if joint_state else FRANKA_STATE_READ).values(),
                            ("SEQUENCE", "float64", 0) if joint_state else ("ARRAY", "float64", FRANKA_JOINTS))
    wrong = [f"{name} ({element}[{length or ''}])" for name, (kind, element, length) in wanted.items()
             if name not in ours or array_of(ours[name]) != (kind, element, length)]
    if "stamp" not in header or not {"sec", "nanosec"} <= set(fields(header["stamp"][1])):
        wrong.append("header.stamp (sec, nanosec)")
    if wrong:
        raise InputError(f"{where}: the bag defines {msgtype} without {', '.join(wrong)}")


def _messages(reader, connections, where: str, limit: int):
    """The topic's messages, decoded, in the bag's order; rosbags' errors become ours, naming the message."""
    raw_messages = reader.messages(connections=connections)
    for index in itertools.count(1):
        try:
            item = next(raw_messages, None)
            message = None if item is None else reader.deserialize(item[2], item[0].msgtype)
        except InputError:  # ours: a decompression refused
            raise
        except Exception as exc:  # rosbags' own (read_bag)
            raise InputError(f"{where}: message {index} cannot be read ({_reason(exc)})") from None
        if item is None:
            return
        if index > limit:  # the bag's own count was wrong: still bounded
            raise InputError(f"{where}: more than {limit} messages: using them would need more memory than "
                             f"{budget_text(memory_budget())}")
        yield message


def _match(names: tuple[str, ...], joints: tuple[str, ...], where: str, index: int):
    """Where our joints sit in one list of names: ``take[j]`` indexes the message's arrays (``len(names)`` if absent),
    ``absent`` (our joints it lacks) and ``ignored`` (its names that are not ours)."""
    position = {name: k for k, name in reversed(list(enumerate(names)))}  # each name's first place
    if len(position) < len(names):
        name = next(name for k, name in enumerate(names) if position[name] != k)
        raise InputError(f"{where}: message {index}: joint '{name}' is named twice")
    take = np.array([position.get(j, len(names)) for j in joints], dtype=np.intp)
    absent = tuple(j for j, joint in enumerate(joints) if joint not in position)
    return take, absent, tuple(name for name in names if name not in set(joints))


def _read_joint_states(messages, joints: tuple[str, ...], where: str) -> BagLog:
    """sensor_msgs/JointState messages to our columns, joints matched by name in each."""
    n, values, stamps = len(joints), array("d"), array("q")
    matches, ignored = {}, {}  # _match's of each list of names (None: it holds none of our joints); names not ours
    first_absent: dict[int, tuple[int, int]] = {}   # joint → (message, stamp) of the first message lacking it
    present = np.zeros(n, dtype=bool)                # joints some message names
    lacking = {"qd": [0, 0], "tau_meas": [0, 0]}     # how many messages have no velocity (effort), the first
    blank = np.full(n, np.nan).tobytes()
    skipped, others = array("q"), {}                 # messages holding none of our joints; the names they hold
    for index, message in enumerate(messages, start=1):
        names = tuple(message.name)
        match = matches.get(names, False)
        if match is False and not set(names) & set(joints):
            match = matches[names] = None
            others.update((name, None) for name in names[:SKIPPED_NAMES + 1 - len(others)])
        if match is None:  # another publisher's on the topic (a gripper's)
            skipped.append(index)
            continue
        stamp = message.header.stamp
        ns = stamp.sec * 10**9 + stamp.nanosec
        if match is False:  # a new set or order of names: the only place a joint can appear or go
            match = matches[names] = _match(names, joints, where, index)
            ignored.update(dict.fromkeys(match[2]))
            present[match[0] < len(names)] = True
            first_absent = {j: (index, ns) for j in match[1]} | first_absent
            if partly := [j for j in first_absent if present[j]]:
                j = min(partly, key=lambda j: first_absent[j][0])
                raise InputError(f"{where}: message {first_absent[j][0]} ({_stamp_text(first_absent[j][1])}) has no "
                                 f"joint '{joints[j]}', which other messages have")
        values.append(stamp.sec + stamp.nanosec * 1e-9)
        take, absent, _ = match
        for kind, field in JOINT_STATE_FIELDS.items():
            data = getattr(message, field)
            if len(data) == len(names):
                values.frombytes((np.append(data, np.nan) if absent else data)[take].tobytes())
            elif len(data) == 0 and kind != "q":
                lacking[kind] = [lacking[kind][0] + 1, lacking[kind][1] or index]
                values.frombytes(blank)
            else:
                raise InputError(f"{where}: message {index} ({_stamp_text(ns)}) has {len(names)} joint names and "
                                 f"{len(data)} values in {field}")
        stamps.append(ns)
    rows, held = len(stamps), ", ".join(list(others)[:SKIPPED_NAMES]) + ", …" * (len(others) > SKIPPED_NAMES)
    if skipped and not rows:
        raise InputError(f"{where}: none of the {len(skipped)} messages holds a joint of the robot "
                         f"({', '.join(joints)}); they hold {held or 'no joint'}")
    data = np.frombuffer(values, dtype=float).reshape(rows, 1 + len(KINDS) * n) if rows else np.empty((0, 1 + 3 * n))
    keep = [j for j in range(n) if present[j]]
    notes = [f"joints in no message, left out: {', '.join(joints[j] for j in range(n) if not present[j])}"] * (
        len(keep) < n)
    kinds = ["q"] + [kind for kind in lacking if not lacking[kind][0]]  # q: every message has positions
    notes += [f"{kind}: {count} of {rows} messages have no {JOINT_STATE_FIELDS[kind]} (first: message {first}), so "
              f"{kind} is not read" for kind, (count, first) in lacking.items() if count]
    if ignored:
        notes.append(f"joints of the messages that the robot does not have, ignored: {', '.join(ignored)}")
    if skipped:
        notes.append(f"messages holding none of the robot's joints, skipped: {len(skipped)} of {len(skipped) + rows} "
                     f"(first: message {skipped[0]}; they hold {held or 'no joint'})")
    before = np.frombuffer(skipped, dtype=np.int64) - np.arange(1, len(skipped) + 1)  # kept messages before each
    return _bag_log(where, data, stamps, joints, keep, kinds, JOINT_STATE_FIELDS, notes,
                    lambda row: row + 1 + int(np.searchsorted(before, row, side="right")))


def _read_franka_states(messages, joints: tuple[str, ...], where: str) -> BagLog:
    """franka_msgs/FrankaState messages to our columns: q, dq and tau_J are the first 7 joints', in order."""
    n, values, stamps = FRANKA_JOINTS, array("d"), array("q")  # read_bag checked the robot has as many joints
    for message in messages:
        stamp = message.header.stamp
        values.append(stamp.sec + stamp.nanosec * 1e-9)
        values.frombytes(np.concatenate((message.q, message.dq, message.tau_J)).astype(float).tobytes())
        stamps.append(stamp.sec * 10**9 + stamp.nanosec)
    data = np.frombuffer(values, dtype=float).reshape(len(stamps), 1 + len(KINDS) * n)
    notes = [f"{FRANKA_STATE} holds the arm's joints only; left out: {', '.join(joints[n:])}"] * (len(joints) > n)
    return _bag_log(where, data, stamps, joints, list(range(n)), list(KINDS), FRANKA_STATE_READ, notes)


def _bag_log(where: str, data: np.ndarray, stamps: array, joints, keep: list[int], kinds: list[str], fields: dict,
             notes: list[str], number=lambda row: row + 1) -> BagLog:
    """The BagLog of ``data`` (rows, 1 + 3n: t, then each of KINDS for all n joints) for the joints ``keep`` and
    ``kinds`` read, after checking the stamps and that every value kept is finite. ``number``: a row's message's."""
    rows, n = len(stamps), (data.shape[1] - 1) // len(KINDS)
    if rows == 0:
        raise InputError(f"{where}: no messages")
    steps = np.diff(ns := np.frombuffer(stamps, dtype=np.int64))
    if (steps <= 0).any():
        k = int(np.flatnonzero(steps <= 0)[0]) + 1
        what = "the same stamp as" if steps[k - 1] == 0 else "an earlier stamp than"
        unset = "; a stamp of 0: does the publisher fill in header.stamp?" if ns[k] == 0 else ""
        raise InputError(f"{where}: message {number(k)} ({_stamp_text(int(ns[k]))}) has {what} message {number(k - 1)} "
                         f"({_stamp_text(int(ns[k - 1]))}): stamps must increase{unset}")
    data.flags.writeable = False  # and so every column, a view of it
    columns = {"t": data[:, 0]}
    for kind in kinds:
        for j in keep:
            column = data[:, 1 + KINDS.index(kind) * n + j]
            bad = np.flatnonzero(~np.isfinite(column))
            if len(bad):
                raise InputError(f"{where}: message {number(bad[0])} ({_stamp_text(int(ns[bad[0]]))}): "
                                 f"{fields[kind]} of joint '{joints[j]}' is {column[bad[0]]} (must be finite)")
            columns[f"{kind}_{joints[j]}"] = column
    return BagLog(columns=columns, where=where, rows=rows, notes=tuple(notes))


__all__ = ["BAG_SUFFIXES", "BYTES_PER_VALUE", "BagLog", "is_bag", "read_bag"]
