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

Bags: a ROS1 ``.bag`` file, a ROS2 bag folder (``metadata.yaml`` beside sqlite3 or MCAP
storage files) and a bare ``.mcap`` file (:func:`is_bag`). The message types are read from the
bag itself (ROS1 bags always carry their definitions, ROS2 bags recorded since Iron do); a bag
without them is read with the definitions of ROS1 Noetic or ROS2 Humble plus our ``franka_msgs``.

Messages (one topic, :func:`read_bag`):

* ``sensor_msgs/JointState``: joints matched by name in every message, whatever the order
  (which may change between messages); joints of the message that are not ours (a gripper's) are
  ignored. ``velocity`` and ``effort`` are read only when every message has them (ROS allows empty
  arrays); a joint of ours that no message names is left out, one that some messages lack is an error.
* ``franka_msgs/FrankaState`` (franka_ros' ``/franka_state_controller/franka_states``): the arrays
  hold the 7 arm joints in order, given to the first 7 of ``joints`` (panda_joint1…7).

Messages are counted from 1 in the order of the bag (its receive times); the header stamps must
increase strictly along them.
"""
from __future__ import annotations

import os
import stat
from array import array
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from ..base.files import kind_of_file
from ..base.resources import check_memory, format_bytes, memory_budget

JOINT_STATE = "sensor_msgs/msg/JointState"
FRANKA_STATE = "franka_msgs/msg/FrankaState"
FRANKA_ERRORS = "franka_msgs/msg/Errors"
MESSAGE_TYPES = (JOINT_STATE, FRANKA_STATE)
DEFAULT_TOPIC = "/joint_states"
FRANKA_JOINTS = 7
KINDS = ("q", "qd", "tau_meas")
JOINT_STATE_FIELDS = {"q": "position", "qd": "velocity", "tau_meas": "effort"}
FRANKA_STATE_READ = {"q": "q", "qd": "dq", "tau_meas": "tau_J"}
BAG_SUFFIXES = (".bag", ".mcap")  # as rosbags spells them (it tells a ROS1 bag by its suffix alone)
# Peak memory of read_bag per value of the columns it returns (1 + 3n a message), measured with tracemalloc
# on bags of 200 001 UR5 JointState messages (3.8 million values, about 80 MB in each format): 11 bytes per
# value from ROS2 sqlite3 and MCAP bags (8 for the columns, the rest the buffers' growth and the stamps),
# 19 from a ROS1 bag (rosbags holds its index, about 150 bytes a message). Using them as `torques` uses a
# table took 44 bytes per value beyond reading it (tables.BYTES_PER_VALUE); budgeted with a like margin.
# Reading took 26 (sqlite3) to 35 (ROS1) µs a message, most of it rosbags decoding the message.
BYTES_PER_VALUE = 100

# franka_msgs/msg/FrankaState and Errors as franka_ros 0.10 defines them (frankaemika/franka_ros,
# franka_msgs/msg), field for field in their order, one (type, names) group per run of fields of
# one type. Only header, q, dq and tau_J are read, but the whole message is needed: a message is
# decoded field after field, its length is checked, and the ROS1 MD5 sum covers every field and
# constant (the test checks ours against the sum rosserial generated from franka_ros 0.10).
FRANKA_STATE_FIELDS = (
    ("std_msgs/Header", "header"),
    ("float64[6]", "cartesian_collision cartesian_contact"),
    ("float64[7]", "q q_d dq dq_d ddq_d theta dtheta tau_J dtau_J tau_J_d"),
    ("float64[6]", "K_F_ext_hat_K"),
    ("float64[2]", "elbow elbow_d elbow_c delbow_c ddelbow_c"),
    ("float64[7]", "joint_collision joint_contact"),
    ("float64[6]", "O_F_ext_hat_K O_dP_EE_d"),
    ("float64[3]", "O_ddP_O"),
    ("float64[6]", "O_dP_EE_c O_ddP_EE_c"),
    ("float64[7]", "tau_ext_hat_filtered"),
    ("float64", "m_ee"), ("float64[3]", "F_x_Cee"), ("float64[9]", "I_ee"),
    ("float64", "m_load"), ("float64[3]", "F_x_Cload"), ("float64[9]", "I_load"),
    ("float64", "m_total"), ("float64[3]", "F_x_Ctotal"), ("float64[9]", "I_total"),
    ("float64[16]", "O_T_EE O_T_EE_d O_T_EE_c F_T_EE F_T_NE NE_T_EE EE_T_K"),
    ("float64", "time control_command_success_rate"),
    ("uint8", "ROBOT_MODE_OTHER=0 ROBOT_MODE_IDLE=1 ROBOT_MODE_MOVE=2 ROBOT_MODE_GUIDING=3 ROBOT_MODE_REFLEX=4 "
              "ROBOT_MODE_USER_STOPPED=5 ROBOT_MODE_AUTOMATIC_ERROR_RECOVERY=6 robot_mode"),
    ("franka_msgs/Errors", "current_errors last_motion_errors"),
)
FRANKA_ERRORS_FIELDS = (("bool", """
    joint_position_limits_violation cartesian_position_limits_violation self_collision_avoidance_violation
    joint_velocity_violation cartesian_velocity_violation force_control_safety_violation joint_reflex
    cartesian_reflex max_goal_pose_deviation_violation max_path_pose_deviation_violation
    cartesian_velocity_profile_safety_violation joint_position_motion_generator_start_pose_invalid
    joint_motion_generator_position_limits_violation joint_motion_generator_velocity_limits_violation
    joint_motion_generator_velocity_discontinuity joint_motion_generator_acceleration_discontinuity
    cartesian_position_motion_generator_start_pose_invalid cartesian_motion_generator_elbow_limit_violation
    cartesian_motion_generator_velocity_limits_violation cartesian_motion_generator_velocity_discontinuity
    cartesian_motion_generator_acceleration_discontinuity cartesian_motion_generator_elbow_sign_inconsistent
    cartesian_motion_generator_start_elbow_invalid cartesian_motion_generator_joint_position_limits_violation
    cartesian_motion_generator_joint_velocity_limits_violation cartesian_motion_generator_joint_velocity_discontinuity
    cartesian_motion_generator_joint_acceleration_discontinuity cartesian_position_motion_generator_invalid_frame
    force_controller_desired_force_tolerance_violation controller_torque_discontinuity
    start_elbow_sign_inconsistent communication_constraints_violation power_limit_violation
    joint_p2p_insufficient_torque_for_planning tau_j_range_violation instability_detected
    joint_move_in_wrong_direction cartesian_spline_motion_generator_violation
    joint_via_motion_generator_planning_joint_limit_violation base_acceleration_initialization_timeout
    base_acceleration_invalid_reading"""),)


def _msg_text(fields) -> str:
    """The ``.msg`` text of (type, space-separated names) groups: one ``type name`` line per name."""
    return "".join(f"{kind} {name}\n" for kind, names in fields for name in names.split())


@dataclass(frozen=True)
class BagLog:
    """Our columns (module docstring; read-only arrays (rows,)) from one topic of a bag.

    ``where`` names the bag and topic for messages ("run.bag, topic /joint_states"); ``notes``
    says what was left out and why (joints no message names, rates or efforts some messages lack).
    """

    columns: dict[str, np.ndarray]
    where: str
    rows: int
    notes: tuple[str, ...] = ()


def is_bag(path) -> bool:
    """Whether ``path`` is read as a bag: a ``.bag`` or ``.mcap`` file, or a folder holding ``metadata.yaml``."""
    path = Path(path)
    if path.is_dir():
        return (path / "metadata.yaml").is_file()
    return path.suffix in BAG_SUFFIXES


@lru_cache(maxsize=2)
def typestore(ros1: bool):
    """The message types of ROS1 Noetic (``ros1``) or ROS2 Humble, with franka_msgs' FrankaState and Errors."""
    # rosbags is imported where it is used: it takes 0.1 s, which every other command would pay at start-up.
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    store.register({**get_types_from_msg(_msg_text(FRANKA_ERRORS_FIELDS), FRANKA_ERRORS),
                    **get_types_from_msg(_msg_text(FRANKA_STATE_FIELDS), FRANKA_STATE)})
    return store


def _reason(exc: Exception) -> str:
    lines = str(exc).strip().splitlines()
    return lines[0][:200] if lines else type(exc).__name__


def _check_path(path: Path) -> None:
    """A regular file or a folder holding metadata.yaml, or an InputError saying what it is instead."""
    try:
        mode = os.stat(path).st_mode
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    if stat.S_ISDIR(mode):
        if not (path / "metadata.yaml").is_file():
            raise InputError(f"{path}: a directory without metadata.yaml, not a ROS2 bag")
    elif not stat.S_ISREG(mode):
        raise InputError(f"{path}: not a regular file ({kind_of_file(mode)}), not a bag")
    elif path.suffix not in BAG_SUFFIXES:
        raise InputError(f"{path}: not a bag: bags are .bag files (ROS1), .mcap files and ROS2 bag folders "
                         "(holding metadata.yaml)")


def _stamp_text(ns: int) -> str:
    return f"t = {ns // 10**9}.{ns % 10**9:09d} s"


def _topic_list(topics) -> str:
    return ", ".join(f"{name} ({info.msgtype or 'several types'})" for name, info in sorted(topics.items())) or "none"


def _choose_topic(path, topics, topic: str | None) -> str:
    """The topic to read: ``topic``, else /joint_states, else the bag's only JointState or FrankaState topic.

    ``topics`` maps each topic of the bag to an object with a ``msgtype`` (rosbags' TopicInfo).
    """
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

    ``joints``: the model's joint names (Θ's order). ``topic``: when None, ``/joint_states`` if
    the bag has it, else the bag's only JointState or FrankaState topic. The messages are read
    as a stream into growing buffers, never held whole; the memory the columns need in use
    (:data:`BYTES_PER_VALUE` per value) is checked against the budget from the bag's message
    count before reading, and again while reading.

    Usage (not run here: it needs a bag)::

        log = read_bag("run.bag", load_robot("ur5").joint_names)
        log.columns["q_elbow_joint"]        # (log.rows,), rad

    Raises
    ------
    InputError
        Naming the bag, and the topic, message (counted from 1), time and joint where it can: a path
        that is no bag or a damaged bag; a missing topic (listing the bag's topics and types) or
        several candidates; a message lacking a joint others have, with names and values of
        different lengths, or with a non-finite value; stamps that repeat or go back.
    """
    path, joints = Path(path), tuple(joints)
    _check_path(path)
    # Lazily, as in typestore().
    from rosbags.highlevel import AnyReader

    # Every exception from rosbags' own calls means this file cannot be read as a bag: damaged files surface
    # from its parsers (and from apsw, lz4, zstd) as errors of many kinds, a length read as 2**62 as a
    # MemoryError. Only those calls are inside the try blocks, so a bug of ours keeps its traceback.
    fallback = typestore(path.suffix == ".bag")  # AnyReader's own rule for a ROS1 bag
    try:
        reader = AnyReader([path], default_typestore=fallback)
        reader.open()
        topics = reader.topics
    except Exception as exc:
        raise InputError(f"{path}: not a bag, or a damaged one ({_reason(exc)})") from None
    try:
        topic = _choose_topic(path, topics, topic)
        where, msgtype, count = f"{path}, topic {topic}", topics[topic].msgtype, topics[topic].msgcount
        _check_definition(reader.typestore, msgtype, where)
        width = 1 + len(KINDS) * (len(joints) if msgtype == JOINT_STATE else _franka_joints(where, joints))
        check_memory(count * width * BYTES_PER_VALUE, f"{where}: {count} messages of {width} values: reading and "
                                                      "using them")
        connections = [c for c in reader.connections if c.topic == topic]
        messages = _messages(reader, connections, where, memory_budget() // (width * BYTES_PER_VALUE))
        read = _read_joint_states if msgtype == JOINT_STATE else _read_franka_states
        return read(messages, joints, where)
    finally:
        try:
            reader.close()
        except Exception:  # rosbags' (see above); what was read stands
            pass


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
    if msgtype == JOINT_STATE:
        wanted = {"name": ("SEQUENCE", "string", 0)}
        wanted.update((field, ("SEQUENCE", "float64", 0)) for field in JOINT_STATE_FIELDS.values())
    else:
        wanted = {f: ("ARRAY", "float64", FRANKA_JOINTS) for f in FRANKA_STATE_READ.values()}
    wrong = [f"{name} ({element}[{length or ''}])" for name, (kind, element, length) in wanted.items()
             if name not in ours or array_of(ours[name]) != (kind, element, length)]
    if "stamp" not in header or not {"sec", "nanosec"} <= set(fields(header["stamp"][1])):
        wrong.append("header.stamp (sec, nanosec)")
    if wrong:
        raise InputError(f"{where}: the bag defines {msgtype} without {', '.join(wrong)}")


def _messages(reader, connections, where: str, limit: int):
    """The topic's messages, decoded, in the bag's order; rosbags' errors become ours, naming the message."""
    raw_messages = reader.messages(connections=connections)
    index = 0
    while True:
        try:
            item = next(raw_messages, None)
            if item is None:
                return
            connection, _, raw = item
            message = reader.deserialize(raw, connection.msgtype)
        except Exception as exc:  # rosbags' own (read_bag)
            raise InputError(f"{where}: message {index + 1} cannot be read ({_reason(exc)})") from None
        index += 1
        if index > limit:  # the bag's own count was wrong: still bounded
            raise InputError(f"{where}: more than {limit} messages: using them would need more than "
                             f"{format_bytes(memory_budget())} of memory, half of this machine's")
        yield message


def _stamp_ns(message) -> int:
    return message.header.stamp.sec * 10**9 + message.header.stamp.nanosec


@dataclass(frozen=True)
class _Match:
    """Where our joints sit in one list of names: ``take[j]`` indexes the message's arrays, ``len(names)`` if absent."""

    take: np.ndarray
    absent: tuple[int, ...]
    ignored: tuple[str, ...]


def _match(names: tuple[str, ...], joints: tuple[str, ...], where: str, index: int) -> _Match:
    position = {}
    for k, name in enumerate(names):
        if name in position:
            raise InputError(f"{where}: message {index}: joint '{name}' is named twice")
        position[name] = k
    take = np.array([position.get(j, len(names)) for j in joints], dtype=np.intp)
    absent = tuple(j for j, joint in enumerate(joints) if joint not in position)
    return _Match(take, absent, tuple(name for name in names if name not in set(joints)))


def _read_joint_states(messages, joints: tuple[str, ...], where: str) -> BagLog:
    """sensor_msgs/JointState messages to our columns, joints matched by name in each."""
    n = len(joints)
    values, stamps = array("d"), array("q")
    matches: dict[tuple[str, ...], _Match] = {}
    ignored: dict[str, None] = {}
    first_absent: dict[int, tuple[int, int]] = {}   # joint → (message, stamp) of the first message lacking it
    present = np.zeros(n, dtype=bool)                # joints some message names
    lacking = {"qd": [0, 0], "tau_meas": [0, 0]}     # how many messages have no velocity (effort), the first
    blank = np.full(n, np.nan).tobytes()
    for index, message in enumerate(messages, start=1):
        names = tuple(message.name)
        match = matches.get(names)
        stamp = message.header.stamp
        ns = stamp.sec * 10**9 + stamp.nanosec
        if match is None:  # a new set or order of names: the only place a joint can appear or go
            match = matches[names] = _match(names, joints, where, index)
            ignored.update(dict.fromkeys(match.ignored))
            present[match.take < len(names)] = True
            for j in match.absent:
                first_absent.setdefault(j, (index, ns))
            partly = [j for j in first_absent if present[j]]
            if partly:
                j = min(partly, key=lambda j: first_absent[j][0])
                raise InputError(f"{where}: message {first_absent[j][0]} ({_stamp_text(first_absent[j][1])}) has no "
                                 f"joint '{joints[j]}', which other messages have")
        values.append(stamp.sec + stamp.nanosec * 1e-9)
        for kind, field in JOINT_STATE_FIELDS.items():
            data = getattr(message, field)
            if len(data) == len(names):
                values.frombytes((np.append(data, np.nan) if match.absent else data)[match.take].tobytes())
            elif len(data) == 0 and kind != "q":
                lacking[kind][0] += 1
                lacking[kind][1] = lacking[kind][1] or index
                values.frombytes(blank)
            else:
                raise InputError(f"{where}: message {index} ({_stamp_text(ns)}) has {len(names)} joint names and "
                                 f"{len(data)} values in {field}")
        stamps.append(ns)
    rows = len(stamps)
    data = np.frombuffer(values, dtype=float).reshape(rows, 1 + len(KINDS) * n) if rows else np.empty((0, 1 + 3 * n))
    notes = []
    keep = [j for j in range(n) if present[j]]
    if len(keep) < n:
        notes.append(f"joints in no message, left out: {', '.join(joints[j] for j in range(n) if not present[j])}")
    kinds = ["q"]
    for kind, field in list(JOINT_STATE_FIELDS.items())[1:]:  # q: every message has positions
        count, first = lacking[kind]
        if count:
            notes.append(f"{kind}: {count} of {rows} messages have no {field} (first: message {first}), so {kind} "
                         "is not read")
        else:
            kinds.append(kind)
    if ignored:
        notes.append(f"joints of the messages that the robot does not have, ignored: {', '.join(ignored)}")
    return _bag_log(where, data, stamps, joints, keep, kinds, JOINT_STATE_FIELDS, notes)


def _franka_joints(where: str, joints: tuple[str, ...]) -> int:
    if len(joints) < FRANKA_JOINTS:
        raise InputError(f"{where}: {FRANKA_STATE} holds {FRANKA_JOINTS} arm joints in order, but the robot "
                         f"has {len(joints)} joints ({', '.join(joints)})")
    return FRANKA_JOINTS


def _read_franka_states(messages, joints: tuple[str, ...], where: str) -> BagLog:
    """franka_msgs/FrankaState messages to our columns: q, dq and tau_J are the first 7 joints', in order."""
    n = _franka_joints(where, joints)
    values, stamps = array("d"), array("q")
    for message in messages:
        stamp = message.header.stamp
        values.append(stamp.sec + stamp.nanosec * 1e-9)
        values.frombytes(np.concatenate((message.q, message.dq, message.tau_J)).astype(float).tobytes())
        stamps.append(_stamp_ns(message))
    data = np.frombuffer(values, dtype=float).reshape(len(stamps), 1 + len(KINDS) * n)
    notes = [f"{FRANKA_STATE} holds the arm's joints only; left out: {', '.join(joints[n:])}"] * (len(joints) > n)
    return _bag_log(where, data, stamps, joints, list(range(n)), list(KINDS), FRANKA_STATE_READ, notes)


def _bag_log(where: str, data: np.ndarray, stamps: array, joints, keep: list[int], kinds: list[str], fields: dict,
             notes: list[str]) -> BagLog:
    """The BagLog of ``data`` (rows, 1 + 3n: t, then each of KINDS for all n joints) for the joints ``keep``
    and ``kinds`` read, after checking the stamps and that every value kept is finite."""
    rows, n = len(stamps), (data.shape[1] - 1) // len(KINDS)
    if rows == 0:
        raise InputError(f"{where}: no messages")
    ns = np.frombuffer(stamps, dtype=np.int64)
    steps = np.diff(ns)
    if (steps <= 0).any():
        k = int(np.flatnonzero(steps <= 0)[0]) + 1
        what = "the same stamp as" if steps[k - 1] == 0 else "an earlier stamp than"
        unset = "; a stamp of 0: does the publisher fill in header.stamp?" if ns[k] == 0 else ""
        raise InputError(f"{where}: message {k + 1} ({_stamp_text(int(ns[k]))}) has {what} message {k} "
                         f"({_stamp_text(int(ns[k - 1]))}): stamps must increase{unset}")
    columns = {"t": data[:, 0]}
    for kind in kinds:
        for j in keep:
            column = data[:, 1 + KINDS.index(kind) * n + j]
            bad = np.flatnonzero(~np.isfinite(column))
            if len(bad):
                raise InputError(f"{where}: message {bad[0] + 1} ({_stamp_text(int(ns[bad[0]]))}): {fields[kind]} of "
                                 f"joint '{joints[j]}' is {column[bad[0]]} (must be finite)")
            columns[f"{kind}_{joints[j]}"] = column
    for column in columns.values():
        column.flags.writeable = False
    return BagLog(columns=columns, where=where, rows=rows, notes=tuple(notes))
