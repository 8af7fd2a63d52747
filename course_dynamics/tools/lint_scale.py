"""The linter's checks that need no shapes: a robot's masses and inertias against its joints and effort limits.

A link drawn by meshes has no shape the linter measures, but its joints still give it a size: the link length
``L`` is the farthest of its child joints' origins and its centre of mass from its frame. A units slip moves
every link alike, so these checks are made on the robot as a whole, at q = 0:

- the masses add to effectively nothing (:data:`NO_MASS`);
- the joints span more than any robot does (:data:`EXTENT`): lengths in millimetres;
- the links' median k / L lies outside :data:`GYRATION_RATIO` (bodies have about 0.3): masses in grams, lengths
  in millimetres, inertias in kg·mm²;
- one link's k exceeds :data:`GYRATION_ROBOT` times the robot's extent (a mass of 1e-300 kg under an inertia);
- a joint's effort limit could not hold what it carries against gravity by a factor of :data:`EFFORT_FACTOR`.

============  ==========================================================================================
symbol        meaning
============  ==========================================================================================
``m``         a link's mass, kg; ``M`` the robot's, the sum of its links'
``I₃``        a link's largest principal moment about its centre of mass, kg·m²
``k``         its radius of gyration sqrt(I₃ / m), m
``L``         its length: the farthest of its child joints' origins and its centre of mass from its frame, m
``extent``    the farthest link frame from the root's at q = 0, m
``τ_g``       M_sub g r: the weight of what a joint carries (M_sub, kg) times the farthest of its centres of
              mass from the joint's origin (r, m; 1 for a prismatic joint), an upper bound of its gravity load
``g``         9.81 m/s²
============  ==========================================================================================

>>> GYRATION_RATIO
(0.03, 50.0)
"""
from __future__ import annotations

import math

import numpy as np

from .lint_classes import Finding
from .lint_geometry import rotation_rpy

G = 9.81                       # m/s²
#: The mass in kg under which a robot's links, added, have effectively none.
NO_MASS = 1e-6
#: The span in m between joints that no robot described by a URDF exceeds.
EXTENT = 50.0
#: The range of the median k / L of a robot's links (example-robot-data's lie within 0.29 to 4.6).
GYRATION_RATIO = (0.03, 50.0)
#: A link's k beyond this many times the robot's extent (and 1 m) is a mass too small for its inertia.
GYRATION_ROBOT = 10.0
#: τ_g over the effort limit beyond which a joint could not hold what it carries (example-robot-data's stay under 14).
EFFORT_FACTOR = 100.0
MIN_LENGTH = 0.01              # m: links shorter than this are not used for the median k / L
MOVING = ("revolute", "continuous", "prismatic")


def _finite(inertial) -> bool:
    return inertial is not None and bool(np.all(np.isfinite(np.r_[inertial.mass, inertial.xyz,
                                                                   inertial.inertia.ravel()])))


def _frames(links, parents, above):
    """The position (m) and rotation of each link's frame in the root's at q = 0."""
    P, R = [], []
    for link, parent, joint in zip(links, parents, above):
        if parent < 0:
            P.append(np.zeros(3))
            R.append(np.eye(3))
            continue
        origin = joint.origin if np.all(np.isfinite(joint.origin)) else np.zeros(6)
        P.append(P[parent] + R[parent] @ origin[:3])
        R.append(R[parent] @ rotation_rpy(origin[3:]))
    return P, R


def _gyration(inertial) -> float:
    moment = float(np.linalg.eigvalsh(inertial.inertia)[-1])
    return math.sqrt(moment / inertial.mass) if moment > 0 and inertial.mass > 0 else math.nan


def scale_findings(robot, tree) -> list:
    """The robot-wide units and scale findings, which need no shapes.

    Parameters
    ----------
    robot : course_dynamics.tools.lint.Robot
        The URDF as the linter reads it.
    tree : tuple or None
        ``(links, parents, above)``: its links parents first, each one's parent index (−1 for the root) and the
        joint above it; None when the links form no tree (then nothing is checked).

    Returns
    -------
    list of Finding
        ``no-mass``, ``units-slip``, ``gyration-exceeds-link`` and ``mass-beyond-effort`` findings; empty for a
        robot whose masses and inertias fit its joints.
    """
    if tree is None:
        return []
    links, parents, above = tree
    masses = np.array([link.inertial.mass if _finite(link.inertial) and link.inertial.mass > 0 else 0.0
                       for link in links])
    total = float(masses.sum())
    if total == 0:
        return []    # no mass at all: the no-mass and joint-carries-nothing checks say so
    if total < NO_MASS:
        return [Finding("no-mass", "robot", robot.name, f"robot '{robot.name}': its links' masses add to {total:.3g} "
                        f"kg, effectively none: every torque is about 0 and M(q) about 0", robot.line)]
    P, R = _frames(links, parents, above)
    extent = max(float(np.linalg.norm(p)) for p in P)
    found = []
    if extent > EXTENT:
        found.append(Finding("units-slip", "robot", robot.name, f"robot '{robot.name}': its joints span {extent:.4g} m "
                             f"at q = 0, more than any robot's {EXTENT:g} m: lengths in millimetres?", robot.line))
    children = {}
    for joint in robot.joints:
        children.setdefault(joint.parent, []).append(joint)
    ratios, per_link = [], []
    for link in links:
        if not _finite(link.inertial) or not link.inertial.mass > 0:
            continue
        k = _gyration(link.inertial)
        if k > GYRATION_ROBOT * max(extent, 1.0):
            size = f"{k:.3g} m" if math.isfinite(k) else "beyond 1e308 m"
            per_link.append(Finding("gyration-exceeds-link", "link", link.name, f"link '{link.name}': radius of "
                                    f"gyration {size} (mass {link.inertial.mass:.3g} kg), more than "
                                    f"{GYRATION_ROBOT:g} times the {extent:.3g} m the robot spans: the mass too "
                                    "small for its inertia", link.line))
        length = max([float(np.linalg.norm(j.origin[:3])) for j in children.get(link.name, [])
                      if np.all(np.isfinite(j.origin))] + [float(np.linalg.norm(link.inertial.xyz))])
        if link.inertial.mass > 1e-3 * total and length >= MIN_LENGTH and not math.isnan(k):
            ratios.append(k / length)
    if len(ratios) >= 3 and not found:   # one robot-wide diagnosis: a span in millimetres explains the ratio
        median = float(np.median(ratios))
        if not GYRATION_RATIO[0] <= median <= GYRATION_RATIO[1]:
            likely = ("the inertias in kg mm^2 or g m^2" if median > GYRATION_RATIO[1] else
                      "the masses in grams (k 31.6 times too small) or the lengths in millimetres (1000 times)")
            found.append(Finding("units-slip", "robot", robot.name, f"robot '{robot.name}': its links' radii of "
                                 f"gyration are a median {median:.3g} of their lengths between joints (bodies have "
                                 f"about 0.3, {GYRATION_RATIO[0]:g} to {GYRATION_RATIO[1]:g} here): {likely}?",
                                 robot.line))
    if found:   # a robot-wide slip explains each link's and each joint's numbers
        return found
    return per_link + _effort(links, parents, above, masses, P, R)


def _effort(links, parents, above, masses, P, R):
    """The joint whose effort limit is farthest below the weight it carries, when that is over EFFORT_FACTOR."""
    coms = [P[i] + R[i] @ (link.inertial.xyz if _finite(link.inertial) else np.zeros(3))
            for i, link in enumerate(links)]
    subtree = [[i] for i in range(len(links))]
    for i in range(len(links) - 1, 0, -1):
        subtree[parents[i]].extend(subtree[i])
    worst = None
    for i, joint in enumerate(above):
        effort = (joint.limit or {}).get("effort") if joint is not None and joint.type in MOVING else None
        if not effort or not math.isfinite(effort) or effort <= 0:
            continue
        carried = float(masses[subtree[i]].sum())
        lever = 1.0 if joint.type == "prismatic" else max(float(np.linalg.norm(coms[j] - P[i])) for j in subtree[i])
        ratio = carried * G * lever / effort
        if ratio > EFFORT_FACTOR and (worst is None or ratio > worst[0]):
            worst = (ratio, joint, carried, lever, effort)
    if worst is None:
        return []
    ratio, joint, carried, lever, effort = worst
    unit = "N" if joint.type == "prismatic" else "N m"
    reach = "" if joint.type == "prismatic" else f", up to {lever:.3g} m from its origin"
    return [Finding("mass-beyond-effort", "joint", joint.name, f"joint '{joint.name}' carries {carried:.4g} kg"
                    f"{reach}: up to {carried * G * lever:.3g} {unit} of weight, {ratio:.3g} times its effort limit "
                    f"{effort:g} {unit}: masses in grams, or a wrong limit?", joint.line)]


__all__ = ["EFFORT_FACTOR", "EXTENT", "GYRATION_RATIO", "GYRATION_ROBOT", "NO_MASS", "scale_findings"]
