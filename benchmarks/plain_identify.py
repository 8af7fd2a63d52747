"""The identification a Pinocchio user writes by hand, for bench_tools.py to time against ``course-dynamics identify``.

Run:  python benchmarks/plain_identify.py URDF LOG.mcap [--holdout 0.2]

It reads the ``sensor_msgs/JointState`` messages with rosbags (each message's joints by name), differentiates
the velocities with a Savitzky–Golay filter (scipy), stacks ``pin.computeJointTorqueRegressor`` over the first
80 % of the samples with viscous and Coulomb friction columns, solves ``numpy.linalg.lstsq`` and prints one JSON
line: the held-out RMS residual of each joint on the last 20 %, N·m.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pinocchio as pin
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore
from scipy.signal import savgol_filter


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("urdf")
    parser.add_argument("log")
    parser.add_argument("--holdout", type=float, default=0.2)
    args = parser.parse_args()
    model = pin.buildModelFromUrdf(args.urdf)
    data = model.createData()
    names = [model.names[j] for j in range(1, model.njoints)]
    t, q, qd, tau = [], [], [], []
    with AnyReader([Path(args.log)], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        for connection, _, raw in reader.messages(connections=reader.connections):
            message = reader.deserialize(raw, connection.msgtype)
            order = [list(message.name).index(name) for name in names]
            t.append(message.header.stamp.sec + 1e-9 * message.header.stamp.nanosec)
            q.append(np.asarray(message.position)[order])
            qd.append(np.asarray(message.velocity)[order])
            tau.append(np.asarray(message.effort)[order])
    t, q, qd, tau = map(np.array, (t, q, qd, tau))
    dt = float(np.median(np.diff(t)))
    qdd = savgol_filter(qd, 31, 3, deriv=1, delta=dt, axis=0)
    n = model.nv

    def stacked(rows):
        blocks = [np.hstack([pin.computeJointTorqueRegressor(model, data, q[k], qd[k], qdd[k]),
                             np.diag(qd[k]), np.diag(np.sign(qd[k]))]) for k in rows]
        return np.vstack(blocks)

    split = int(len(t) * (1 - args.holdout))
    theta = np.linalg.lstsq(stacked(range(split)), tau[:split].ravel(), rcond=None)[0]
    predicted = (stacked(range(split, len(t))) @ theta).reshape(-1, n)
    rms = np.sqrt(np.mean((tau[split:] - predicted) ** 2, axis=0))
    print(json.dumps({"joints": names, "held_out_rms": rms.tolist()}))


if __name__ == "__main__":
    main()
