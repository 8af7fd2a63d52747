"""Robot logs from ROS bags (course_dynamics.tools.bags), written by tests/bagmakers.py from a known motion."""
from __future__ import annotations

import os
import re
import signal
import threading
from contextlib import contextmanager, suppress

import numpy as np
import pytest

import bagmakers
from bagmakers import FORMATS, FRANKA_JOINT_STATES, FRANKA_TOPIC, stamp, stamped_seconds, write_bag
from course_dynamics import load_robot
from course_dynamics.base import resources
from course_dynamics.base.errors import InputError
from course_dynamics.core.newton_euler import inverse_dynamics
from course_dynamics.tools.bags import FRANKA_STATE, JOINT_STATE, is_bag, read_bag, typestore
from logmakers import multisine

START = 1_700_000_000.0  # stamps as a robot's clock gives them: seconds since 1970
EXACT = 1e-12


@pytest.fixture(scope="module")
def ur5():
    model = load_robot("ur5")
    motion = multisine(model, duration=0.2, rate=500.0, start=START)
    return model, motion, inverse_dynamics(model, motion.q, motion.qd, motion.qdd)


@pytest.fixture(scope="module")
def panda():
    model = load_robot("panda")
    motion = multisine(model, duration=0.2, rate=500.0, start=START)
    tau = inverse_dynamics(model, motion.q, motion.qd, motion.qdd)
    return model, motion.t, motion.q[:, :7], motion.qd[:, :7], tau[:, :7]


def expected_columns(joints, t, q, qd=None, tau=None):
    columns = {"t": stamped_seconds(t)}
    for kind, block in (("q", q), ("qd", qd), ("tau_meas", tau)):
        if block is not None:
            columns.update({f"{kind}_{joint}": block[:, j] for j, joint in enumerate(joints)})
    return columns


def assert_columns(log, expected):
    assert list(log.columns) == list(expected)
    for name, values in expected.items():
        assert np.allclose(log.columns[name], values, rtol=0, atol=EXACT), name
    assert log.rows == len(expected["t"])


def time_text(t: float) -> str:
    sec, nanosec = stamp(t)
    return f"t = {sec}.{nanosec:09d} s"


@pytest.mark.parametrize("fmt", FORMATS)
def test_each_format_reads_back_what_was_written(tmp_path, ur5, fmt):
    model, motion, tau = ur5
    path = bagmakers.write_joint_states(tmp_path / "run", fmt, model.joint_names, motion.t, motion.q, motion.qd, tau)
    log = read_bag(path, model.joint_names)
    assert_columns(log, expected_columns(model.joint_names, motion.t, motion.q, motion.qd, tau))
    assert np.abs(log.columns["t"] - motion.t).max() < 1e-6  # absolute times, as stamped (to the nanosecond)
    assert log.where == f"{path}, topic /joint_states"
    assert log.notes == ("joints of the messages that the robot does not have, ignored: gripper_finger_joint",)
    assert not log.columns["q_elbow_joint"].flags.writeable


def test_the_formats_give_identical_columns(tmp_path, ur5):
    model, motion, tau = ur5
    logs = [read_bag(bagmakers.write_joint_states(tmp_path / fmt, fmt, model.joint_names, motion.t, motion.q,
                                                  motion.qd, tau), model.joint_names) for fmt in FORMATS]
    for log in logs[1:]:
        assert list(log.columns) == list(logs[0].columns)
        for name, values in logs[0].columns.items():
            assert np.array_equal(log.columns[name], values), name


# Each way a bag is compressed: (format, compression); "file" compresses a ROS2 bag's storage files.
COMPRESSIONS = [("ros1", "bz2"), ("ros1", "lz4"), ("mcap", "zstd"), ("mcap", "lz4"), ("ros2-mcap", "zstd"),
                ("ros2-sqlite3", "message"), ("ros2-sqlite3", "file"), ("ros2-mcap", "file")]


@pytest.mark.parametrize("fmt, compression", COMPRESSIONS, ids=lambda x: x)
def test_compressed_bags_read_back_what_was_written(tmp_path, ur5, fmt, compression):
    """Through the bounded decompression (tools.decompression), as the uncompressed bag of the format reads."""
    model, motion, tau = ur5
    write = lambda name, compression=None: bagmakers.write_joint_states(  # noqa: E731
        tmp_path / name, fmt, model.joint_names, motion.t, motion.q, motion.qd, tau, compression=compression)
    path = bagmakers.file_compressed(write("file")) if compression == "file" else write("packed", compression)
    log, plain = read_bag(path, model.joint_names), read_bag(write("plain"), model.joint_names)
    assert list(log.columns) == list(plain.columns) and log.notes == plain.notes
    for name, values in plain.columns.items():
        assert np.array_equal(log.columns[name], values), name


def test_joints_are_matched_by_name_whatever_their_order_in_each_message(tmp_path, ur5):
    model, motion, tau = ur5
    messages = bagmakers.joint_states(model.joint_names, motion.t, motion.q, motion.qd, tau, shuffle_seed=1)
    orders = {tuple(m["name"]) for m in messages}
    assert len(orders) > 10 and tuple(model.joint_names) + ("gripper_finger_joint",) not in orders
    log = read_bag(write_bag(tmp_path / "run", "ros1", {"/joint_states": (JOINT_STATE, messages)}), model.joint_names)
    assert_columns(log, expected_columns(model.joint_names, motion.t, motion.q, motion.qd, tau))


def test_without_velocity_and_effort_only_positions_are_read(tmp_path, ur5):
    model, motion, _ = ur5
    path = bagmakers.write_joint_states(tmp_path / "run", "ros2-mcap", model.joint_names, motion.t, motion.q)
    log = read_bag(path, model.joint_names)
    assert_columns(log, expected_columns(model.joint_names, motion.t, motion.q))
    rows = len(motion.t)
    assert any(note.startswith(f"qd: {rows} of {rows} messages have no velocity") for note in log.notes)


def test_velocity_missing_from_some_messages_is_not_read(tmp_path, ur5):
    model, motion, tau = ur5
    messages = bagmakers.joint_states(model.joint_names, motion.t, motion.q, motion.qd, tau)
    for k in (4, 9):
        messages[k]["velocity"] = np.zeros(0)
    log = read_bag(write_bag(tmp_path / "run", "ros1", {"/joint_states": (JOINT_STATE, messages)}), model.joint_names)
    assert_columns(log, expected_columns(model.joint_names, motion.t, motion.q, tau=tau))
    assert f"qd: 2 of {len(motion.t)} messages have no velocity (first: message 5), so qd is not read" in log.notes


def test_a_joint_that_no_message_names_is_left_out(tmp_path, ur5):
    model, motion, tau = ur5
    path = bagmakers.write_joint_states(tmp_path / "run", "ros1", model.joint_names[:5], motion.t, motion.q[:, :5],
                                        motion.qd[:, :5], tau[:, :5], extra=())
    log = read_bag(path, model.joint_names)
    assert_columns(log, expected_columns(model.joint_names[:5], motion.t, motion.q[:, :5], motion.qd[:, :5],
                                         tau[:, :5]))
    assert log.notes == ("joints in no message, left out: wrist_3_joint",)


@pytest.mark.parametrize("k", [0, 7])
def test_a_message_lacking_a_joint_the_others_have_is_an_error(tmp_path, ur5, k):
    model, motion, tau = ur5
    path = bagmakers.write_joint_states(tmp_path / "run", "ros2-sqlite3", model.joint_names, motion.t, motion.q,
                                        motion.qd, tau, drop={k: "elbow_joint"})
    message = (f"{path}, topic /joint_states: message {k + 1} ({time_text(motion.t[k])}) has no joint 'elbow_joint', "
               "which other messages have")
    with pytest.raises(InputError, match=re.escape(message)):
        read_bag(path, model.joint_names)


def test_a_value_that_is_not_finite_is_an_error(tmp_path, ur5):
    model, motion, tau = ur5
    q = motion.q.copy()
    q[3, 2] = np.nan
    path = bagmakers.write_joint_states(tmp_path / "run", "ros1", model.joint_names, motion.t, q, motion.qd, tau)
    message = f"message 4 ({time_text(motion.t[3])}): position of joint 'elbow_joint' is nan (must be finite)"
    with pytest.raises(InputError, match=re.escape(message)):
        read_bag(path, model.joint_names)


@pytest.mark.parametrize("fmt", ["ros1", "mcap"])
def test_stamps_that_go_back_or_repeat_are_an_error(tmp_path, ur5, fmt):
    model, motion, tau = ur5
    t = motion.t.copy()
    t[5] = t[3]                      # message 6 is stamped as message 4, before message 5
    path = bagmakers.write_joint_states(tmp_path / "back", fmt, model.joint_names, t, motion.q, motion.qd, tau)
    with pytest.raises(InputError, match=re.escape(f"message 6 ({time_text(t[3])}) has an earlier stamp than "
                                                   f"message 5 ({time_text(t[4])}): stamps must increase")):
        read_bag(path, model.joint_names)
    t = motion.t.copy()
    t[5] = t[4]
    path = bagmakers.write_joint_states(tmp_path / "same", fmt, model.joint_names, t, motion.q, motion.qd, tau)
    with pytest.raises(InputError, match=re.escape("message 6 (") + ".* has the same stamp as message 5"):
        read_bag(path, model.joint_names)


@pytest.mark.parametrize("fmt", FORMATS)
def test_franka_states_give_the_arm_joints_in_order(tmp_path, panda, fmt):
    model, t, q, qd, tau = panda
    path = bagmakers.write_franka(tmp_path / "panda", fmt, model.joint_names, t, q, qd, tau)
    log = read_bag(path, model.joint_names, topic=FRANKA_TOPIC)
    assert_columns(log, expected_columns(model.joint_names[:7], t, q, qd, tau))
    assert log.notes == (f"{FRANKA_STATE} holds the arm's joints only; left out: panda_finger_joint1",)
    # franka_state_controller's JointState of the same samples: effort is the same measured τ_J
    joint_states = read_bag(path, model.joint_names, topic=FRANKA_JOINT_STATES)
    assert_columns(joint_states, expected_columns(model.joint_names[:7], t, q, qd, tau))


def test_franka_states_need_seven_joints(tmp_path, panda):
    model, t, q, qd, tau = panda
    path = bagmakers.write_franka(tmp_path / "panda", "ros1", model.joint_names, t, q, qd, tau)
    with pytest.raises(InputError, match="holds 7 arm joints in order, but the robot has 6 joints"):
        read_bag(path, load_robot("ur5").joint_names, topic=FRANKA_TOPIC)


def test_our_franka_state_definition_is_franka_ros_0_10s():
    # The MD5 sum that rosserial's generated franka_msgs/FrankaState.h carries for franka_ros 0.10's
    # definition (getMD5()); ROS1 sums cover every field and constant, in order.
    assert typestore(True).generate_msgdef(FRANKA_STATE)[1] == "431567d5df6caf4e4dd7385f25cb71ee"


@pytest.mark.parametrize("msgtype", [JOINT_STATE, FRANKA_STATE])
def test_a_ros2_bag_without_definitions_is_read_with_ours(tmp_path, panda, msgtype):
    model, t, q, qd, tau = panda
    topic = "/joint_states" if msgtype == JOINT_STATE else FRANKA_TOPIC
    messages = (bagmakers.joint_states(model.joint_names[:7], t, q, qd, tau) if msgtype == JOINT_STATE
                else bagmakers.franka_states(t, q, qd, tau))
    path = bagmakers.without_definitions(write_bag(tmp_path / "humble", "ros2-sqlite3", {topic: (msgtype, messages)}))
    assert_columns(read_bag(path, model.joint_names[:7]), expected_columns(model.joint_names[:7], t, q, qd, tau))


def topic_bag(tmp_path, ur5, topics: dict[str, str], name: str = "topics"):
    """A bag with the topics {name: message type} (the motion's JointState or FrankaState, or a String)."""
    model, motion, tau = ur5
    made = {JOINT_STATE: lambda: bagmakers.joint_states(model.joint_names, motion.t, motion.q, motion.qd, tau),
            FRANKA_STATE: lambda: bagmakers.franka_states(motion.t, motion.q[:, [0, 1, 2, 3, 4, 5, 5]],
                                                          motion.qd[:, [0, 1, 2, 3, 4, 5, 5]],
                                                          tau[:, [0, 1, 2, 3, 4, 5, 5]]),
            "std_msgs/msg/String": lambda: [{"stamp": stamp(t), "data": "ok"} for t in motion.t[:3]]}
    return write_bag(tmp_path / name, "ros1", {name: (msgtype, made[msgtype]()) for name, msgtype in topics.items()})


def test_joint_states_is_the_default_topic(tmp_path, ur5):
    path = topic_bag(tmp_path, ur5, {"/joint_states": JOINT_STATE, "/arm/joint_states": JOINT_STATE,
                                     "/rosout": "std_msgs/msg/String"})
    assert read_bag(path, ur5[0].joint_names).where == f"{path}, topic /joint_states"


def test_the_only_joint_state_topic_is_read_without_being_named(tmp_path, ur5):
    path = topic_bag(tmp_path, ur5, {"/arm/joint_states": JOINT_STATE, "/rosout": "std_msgs/msg/String"})
    assert read_bag(path, ur5[0].joint_names).where == f"{path}, topic /arm/joint_states"
    path = topic_bag(tmp_path, ur5, {FRANKA_TOPIC: FRANKA_STATE}, name="franka")
    assert read_bag(path, load_robot("panda").joint_names).where == f"{path}, topic {FRANKA_TOPIC}"


def test_several_candidate_topics_ask_for_one(tmp_path, ur5):
    path = topic_bag(tmp_path, ur5, {"/left/joint_states": JOINT_STATE, "/right/joint_states": JOINT_STATE})
    with pytest.raises(InputError, match=re.escape(
            f"{path}: several topics hold joint states: /left/joint_states ({JOINT_STATE}), /right/joint_states "
            f"({JOINT_STATE}); say which with --topic")):
        read_bag(path, ur5[0].joint_names)
    assert read_bag(path, ur5[0].joint_names, topic="/right/joint_states").rows == len(ur5[1].t)


def test_a_missing_topic_lists_the_bags_topics_with_their_types(tmp_path, ur5):
    path = topic_bag(tmp_path, ur5, {"/joint_states": JOINT_STATE, "/rosout": "std_msgs/msg/String"})
    with pytest.raises(InputError, match=re.escape(f"{path}: no topic /robot/joint_states; the bag's topics: "
                                                   f"/joint_states ({JOINT_STATE}), /rosout (std_msgs/msg/String)")):
        read_bag(path, ur5[0].joint_names, topic="/robot/joint_states")
    with pytest.raises(InputError, match="topic /rosout holds std_msgs/msg/String; joint logs are read from"):
        read_bag(path, ur5[0].joint_names, topic="/rosout")


def test_a_bag_without_joint_states_lists_its_topics(tmp_path, ur5):
    path = topic_bag(tmp_path, ur5, {"/rosout": "std_msgs/msg/String"})
    with pytest.raises(InputError, match=re.escape("; the bag's topics: /rosout (std_msgs/msg/String)")):
        read_bag(path, ur5[0].joint_names)


@pytest.mark.parametrize("name, content, reason", [
    ("notes.bag", b"time,q1\n0,1\n", "not a bag, or a damaged one (File magic is invalid.)"),
    ("notes.mcap", b"", "not a bag, or a damaged one"),
    ("log.csv", b"t,q\n", "not a bag: bags are .bag files (ROS1), .mcap files and ROS2 bag folders"),
])
def test_a_file_that_is_not_a_bag_is_one_clear_error(tmp_path, ur5, name, content, reason):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(InputError, match=re.escape(f"{path}: {reason}")):
        read_bag(path, ur5[0].joint_names)


def test_a_damaged_bag_is_one_clear_error(tmp_path, ur5):
    model, motion, tau = ur5
    path = bagmakers.write_joint_states(tmp_path / "run", "ros1", model.joint_names, motion.t, motion.q, motion.qd, tau)
    cut = tmp_path / "cut.bag"
    cut.write_bytes(path.read_bytes()[:5000])  # a recording stopped before rosbag wrote its index
    with pytest.raises(InputError, match=re.escape(f"{cut}: not a bag, or a damaged one")):
        read_bag(cut, model.joint_names)
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="a directory without metadata.yaml, not a ROS2 bag"):
        read_bag(tmp_path / "empty", model.joint_names)
    with pytest.raises(InputError, match="cannot read: No such file"):
        read_bag(tmp_path / "missing", model.joint_names)


def test_a_bag_too_large_for_memory_is_refused_before_reading(tmp_path, ur5, monkeypatch):
    model, motion, tau = ur5
    path = bagmakers.write_joint_states(tmp_path / "run", "ros1", model.joint_names, motion.t, motion.q, motion.qd, tau)
    monkeypatch.setattr(resources, "memory_budget", lambda: 10_000)
    with pytest.raises(InputError, match=re.escape(f"{path}, topic /joint_states: {len(motion.t)} messages of 19 "
                                                   "values: reading and using them would need about")):
        read_bag(path, model.joint_names)


def test_which_paths_are_bags(tmp_path, ur5):
    model, motion, tau = ur5
    folder = bagmakers.write_joint_states(tmp_path / "ros2", "ros2-mcap", model.joint_names, motion.t, motion.q)
    (tmp_path / "plain").mkdir()
    assert is_bag(folder) and is_bag(tmp_path / "run.bag") and is_bag(tmp_path / "run.mcap")
    assert not is_bag(tmp_path / "plain") and not is_bag(tmp_path / "run.csv") and not is_bag(folder / "metadata.yaml")


# ---------------------------------------------------------------------------- hostile bags


@contextmanager
def fails_instead_of_hanging(fifos, seconds: float = 5.0):
    """A regression that opens one of the named pipes ``fifos`` fails instead of hanging the suite.

    After ``seconds`` a thread opens each pipe for writing and closes it, again and again, so a reader blocked in
    open() gets end of file (and the test fails on its message): sqlite retries an open interrupted by a signal, so
    SIGALRM alone would not free it; SIGALRM (twice as late) stops any other wait."""
    done = threading.Event()

    def release():
        while not done.wait(0.05):
            for fifo in fifos:
                with suppress(OSError):  # ENXIO: nobody has it open for reading
                    os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))

    def timeout(*_):
        raise TimeoutError(f"still waiting after {2 * seconds:.0f} s: a named pipe was opened")

    previous = signal.signal(signal.SIGALRM, timeout)
    signal.alarm(int(2 * seconds))
    timer = threading.Timer(seconds, release)
    timer.start()
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
        done.set()
        timer.cancel()
        timer.join()


def short_bag(tmp_path, ur5, fmt: str, name: str = "run"):
    model, motion, tau = ur5
    return bagmakers.write_joint_states(tmp_path / name, fmt, model.joint_names, motion.t[:20], motion.q[:20],
                                        motion.qd[:20], tau[:20])


@pytest.mark.parametrize("fmt", ["ros2-sqlite3", "ros2-mcap"])
@pytest.mark.parametrize("where", ["storage file", "link to a pipe elsewhere", "unnamed file", "metadata.yaml"])
def test_a_named_pipe_in_a_ros2_bag_folder_is_refused_without_waiting(tmp_path, ur5, fmt, where):
    folder = short_bag(tmp_path, ur5, fmt)
    (storage,) = (f for f in folder.iterdir() if f.name != "metadata.yaml")
    fifo, kind = {"storage file": (storage, "a named pipe"),
                  "link to a pipe elsewhere": (storage, "a link to a named pipe"),
                  "unnamed file": (folder / "notes.txt", "a named pipe"),
                  "metadata.yaml": (folder / "metadata.yaml", "a named pipe")}[where]
    fifo.unlink(missing_ok=True)
    if where.startswith("link"):
        os.mkfifo(tmp_path / "elsewhere")
        fifo.symlink_to(tmp_path / "elsewhere")
    else:
        os.mkfifo(fifo)
    assert is_bag(folder)
    pipe = tmp_path / "elsewhere" if where.startswith("link") else fifo
    with fails_instead_of_hanging([pipe]), pytest.raises(InputError) as error:
        read_bag(folder, ur5[0].joint_names)
    assert str(error.value) == f"{fifo}: not a regular file ({kind}), in a ROS2 bag folder"


@pytest.mark.parametrize("name", ["run.bag", "run.mcap"])
def test_a_bag_file_that_is_a_named_pipe_is_refused_without_opening_it(tmp_path, ur5, name):
    fifo = tmp_path / name
    os.mkfifo(fifo)
    with fails_instead_of_hanging([fifo]), pytest.raises(InputError) as error:
        read_bag(fifo, ur5[0].joint_names)
    assert str(error.value) == f"{fifo}: not a regular file (a named pipe), not a bag"


def gripper_states(t, names=("gripper_finger_joint",)):
    """A gripper's own sensor_msgs/JointState messages, stamped ``t``: its joints only."""
    return [{"stamp": stamp(time), "name": list(names), **{field: np.full(len(names), 0.01 * k) for field in
                                                            ("position", "velocity", "effort")}}
            for k, time in enumerate(t)]


def interleaved(arm, gripper):
    """The arm's and the gripper's messages on one topic, each arm message followed by a gripper message."""
    return [message for pair in zip(arm, gripper) for message in pair]


def test_a_grippers_own_joint_states_on_the_topic_are_skipped_with_a_note(tmp_path, ur5):
    model, motion, tau = ur5
    arm = bagmakers.joint_states(model.joint_names, motion.t, motion.q, motion.qd, tau, extra=())
    messages = interleaved(arm, gripper_states(motion.t + 0.001))  # between the arm's (500 Hz)
    log = read_bag(write_bag(tmp_path / "run", "ros2-mcap", {"/joint_states": (JOINT_STATE, messages)}),
                   model.joint_names)
    assert_columns(log, expected_columns(model.joint_names, motion.t, motion.q, motion.qd, tau))
    rows = len(motion.t)
    assert log.notes == ((f"messages holding none of the robot's joints, skipped: {rows} of {2 * rows} (first: "
                          "message 2; they hold gripper_finger_joint)"),)


def test_errors_after_skipped_messages_name_the_bags_own_message_numbers(tmp_path, ur5):
    model, motion, tau = ur5
    q, t = motion.q.copy(), motion.t.copy()
    q[3, 2] = np.nan                                  # arm message 4: the bag's message 7
    gripper = gripper_states(motion.t + 0.001)
    path = write_bag(tmp_path / "nan", "ros1", {"/joint_states": (JOINT_STATE, interleaved(
        bagmakers.joint_states(model.joint_names, t, q, motion.qd, tau, extra=()), gripper))})
    with pytest.raises(InputError, match=re.escape(f"message 7 ({time_text(t[3])}): position of joint 'elbow_joint'")):
        read_bag(path, model.joint_names)
    t[5] = t[3]                                       # arm message 6 (the bag's 11) stamped as arm message 4
    path = write_bag(tmp_path / "back", "ros1", {"/joint_states": (JOINT_STATE, interleaved(
        bagmakers.joint_states(model.joint_names, t, motion.q, motion.qd, tau, extra=()), gripper))})
    with pytest.raises(InputError, match=re.escape(f"message 11 ({time_text(t[3])}) has an earlier stamp than "
                                                   f"message 9 ({time_text(t[4])}): stamps must increase")):
        read_bag(path, model.joint_names)


def test_a_message_with_some_of_the_robots_joints_is_still_an_error_among_skipped_ones(tmp_path, ur5):
    model, motion, tau = ur5
    arm = bagmakers.joint_states(model.joint_names, motion.t, motion.q, motion.qd, tau, extra=(),
                                 drop={4: "elbow_joint"})
    path = write_bag(tmp_path / "run", "ros1", {"/joint_states": (JOINT_STATE, interleaved(
        arm, gripper_states(motion.t + 0.001)))})
    with pytest.raises(InputError, match=re.escape(f"message 9 ({time_text(motion.t[4])}) has no joint 'elbow_joint', "
                                                   "which other messages have")):
        read_bag(path, model.joint_names)


def test_messages_holding_none_of_the_robots_joints_at_all_are_one_error_naming_a_few_of_theirs(tmp_path, ur5):
    model, motion, _ = ur5
    names = [f"finger_{k}" for k in range(1, 8)]
    path = write_bag(tmp_path / "run", "ros1", {"/joint_states": (JOINT_STATE, gripper_states(motion.t[:4], names))})
    with pytest.raises(InputError) as error:
        read_bag(path, model.joint_names)
    assert str(error.value) == (f"{path}, topic /joint_states: none of the 4 messages holds a joint of the robot "
                                f"({', '.join(model.joint_names)}); they hold finger_1, finger_2, finger_3, finger_4, "
                                "finger_5, …")


@pytest.mark.parametrize("text, reason", [
    ("", "rosbag2_bagfile_information missing or not as rosbags reads them"),
    ("[1, 2, 3]\n", "rosbag2_bagfile_information missing or not as rosbags reads them"),
    ("rosbag2_bagfile_information: {version: 9}\n", ("storage_identifier, relative_file_paths, message_count, "
                                                      "duration, starting_time, topics_with_message_count missing")),
    ("version: 9 -> version: 10", "(version 10, mcap storage: rosbags reads versions 1 to 9, sqlite3 or mcap storage)"),
    ("version: 9 -> version: '9'", "(version missing or not as rosbags reads them)"),
    ("storage_identifier: mcap -> storage_identifier: rosbag_v2", "rosbag_v2 storage: rosbags reads versions 1 to 9"),
    ("serialization_format: cdr -> serialization_format: json", "(Serialization format {'json'} is not supported.)"),
    ("rosbag2_bagfile_information: [\n", "(not YAML: "),
    ("[" * 5000 + "]" * 5000, "(not YAML: "),
])
def test_metadata_rosbags_cannot_read_is_one_error_of_ours(tmp_path, ur5, text, reason):
    folder = short_bag(tmp_path, ur5, "ros2-mcap")
    metadata = folder / "metadata.yaml"
    if " -> " in text:
        old, new = text.split(" -> ")
        metadata.write_text(metadata.read_text().replace(old, new, 1))
    else:
        metadata.write_text(text)
    with pytest.raises(InputError) as error:
        read_bag(folder, ur5[0].joint_names)
    message = str(error.value)
    assert message.startswith(f"{folder}: metadata.yaml is not a ROS2 bag's metadata (") and reason in message
    assert "\n" not in message and "please report" not in message and "NoneType" not in message


def test_a_yaml_tag_in_metadata_runs_nothing(tmp_path, ur5):
    folder = short_bag(tmp_path, ur5, "ros2-sqlite3")
    made = tmp_path / "made_by_yaml"
    (folder / "metadata.yaml").write_text(f"!!python/object/apply:os.mkdir ['{made}']\n")
    with pytest.raises(InputError, match=re.escape("metadata.yaml is not a ROS2 bag's metadata (not YAML: could not "
                                                   "determine a constructor for the tag")):
        read_bag(folder, ur5[0].joint_names)
    assert not made.exists()


def test_control_characters_of_names_from_the_bag_are_escaped(tmp_path, ur5):
    model, motion, tau = ur5
    gripper = "grip\x1b]0;owned\x07\nper"
    path = bagmakers.write_joint_states(tmp_path / "run", "ros1", model.joint_names, motion.t, motion.q, motion.qd,
                                        tau, extra=(gripper,), topic="/arm\n\x1b[2J/joint_states")
    log = read_bag(path, model.joint_names)
    assert log.notes == (r"joints of the messages that the robot does not have, ignored: grip\x1b]0;owned\x07\nper",)
    assert log.where == f"{path}, topic /arm\\n\\x1b[2J/joint_states"
    with pytest.raises(InputError) as error:
        read_bag(path, model.joint_names, topic="/other")
    assert str(error.value).endswith(f"the bag's topics: /arm\\n\\x1b[2J/joint_states ({JOINT_STATE})")
    joints = (*model.joint_names[:5], "wrist\u202e_3\tjoint")  # a direction mark, a tab: a joint of the robot's own
    with pytest.raises(InputError) as error:
        read_bag(bagmakers.write_joint_states(tmp_path / "twice", "ros1", joints, motion.t, motion.q,
                                              extra=(joints[5],)), joints)
    assert str(error.value).endswith("message 1: joint 'wrist\\u202e_3\\tjoint' is named twice")
