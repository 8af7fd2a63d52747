"""The linter's checks of a link's inertia against its shapes, and of a rotated inertial frame.

A link's shapes are its ``<collision>`` elements, else its ``<visual>`` ones, when every one of them is a box, a
cylinder or a sphere (meshes are not read: a link with one is not measured). Overlaps are not subtracted, so
the volume is at most an overestimate and the density at least an underestimate of the real one.

=========  ==========================================================================================
symbol     meaning
=========  ==========================================================================================
``m``      the link's mass, kg
``V``      the shapes' volume, m³
``rho``    m / V, kg/m³: solids lie within :data:`DENSITY` (foams to osmium)
``k``      the radius of gyration sqrt(I₃ / m) about the centre of mass, m
``reach``  the distance from the centre of mass to the farthest corner of the box around the shapes, m;
           no body has k > reach, since I₃ = ∫ r⊥² dm ≤ m reach²
``R``      the rotation of an ``<origin rpy>``: R = R_z(yaw) R_y(pitch) R_x(roll), URDF's fixed axes
=========  ==========================================================================================

>>> (rotation_rpy([0.0, 0.0, math.pi / 2]).round(12) + 0.0).tolist()   # 90° of yaw
[[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ..core.inertia import rotate
from .lint_classes import Finding

#: The densities of solids in kg/m³, from foams (~10) to osmium (22 590), with some room.
DENSITY = (10.0, 25_000.0)
#: The densities of the materials robot links are made of, kg/m³ (plastics to steel), to name a units slip.
MATERIALS = (300.0, 10_000.0)
#: Powers of ten a units slip multiplies a density by, each with the likely slip.
SLIPS = {3: "the mass in grams", 6: "the mass in milligrams", -3: "the mass in tonnes, or the shapes 10 times too "
         "large", -9: "the shapes in millimetres", 9: "the shapes in kilometres, or the mass in grams and the shapes "
         "10 times too small", -6: "the mass in grams and the shapes in millimetres"}
COM_MARGIN = 0.1         # of the box's largest side: how far outside the box a centre of mass may lie
COM_SLIP = 100.0         # boxes' largest sides: a centre of mass this far out, inside in millimetres, is a slip
GYRATION_MARGIN = 1.5    # k may exceed reach by this factor (the box is only around the shapes)
GYRATION_SLIP = 20.0     # k / reach at which the inertia is taken to be in the wrong units (31.6 for 10³)
#: A mass under this share of the robot's is negligible, and a placeholder when it does not fit its shapes.
PLACEHOLDER = 1e-3


def rotation_rpy(rpy) -> np.ndarray:
    """The rotation of a URDF ``<origin rpy>``: R_z(yaw) R_y(pitch) R_x(roll).

    Parameters
    ----------
    rpy : array_like, shape (3,)
        Roll, pitch and yaw about the fixed x, y and z axes, rad.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        The rotation of the frame in its parent.

    Examples
    --------
    >>> (rotation_rpy([math.pi / 2, 0.0, 0.0]).round(12)[1:] + 0.0).tolist()   # 90° of roll: y → z
    [[0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]
    """
    roll, pitch, yaw = (float(x) for x in rpy)
    cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw), \
        math.sin(yaw)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


@dataclass(frozen=True)
class Shape:
    """One shape of a link, as :func:`shape` measures it.

    Parameters
    ----------
    kind : str
        Its geometry's tag: ``"box"``, ``"cylinder"``, ``"sphere"``, ``"mesh"``, ...
    volume : float or None
        Its volume, m³; None when it is not measured (a mesh, or values not readable).
    corners : numpy.ndarray or None
        The 8 corners of its box in the link's frame, shape (8, 3), m; None when it is not measured.
    """

    kind: str
    volume: float | None
    corners: np.ndarray | None


def shape(kind: str, values: dict, xyz, rpy) -> Shape:
    """A ``<geometry>`` element's shape in the link's frame.

    Parameters
    ----------
    kind : str
        The geometry's tag: ``"box"``, ``"cylinder"``, ``"sphere"`` (measured) or any other (not measured).
    values : dict
        ``size`` (shape (3,)), ``radius`` and ``length`` (shape (1,)) as read, m (NaN where absent).
    xyz : array_like, shape (3,)
        The shape's origin in the link's frame, m.
    rpy : array_like, shape (3,)
        Its orientation there, rad.

    Returns
    -------
    Shape
        Its volume and box corners (8 × 3, m), or None for both when it is not measured.

    Examples
    --------
    >>> shape("box", dict(size=np.array([1.0, 2.0, 3.0])), [0, 0, 0], [0, 0, 0]).volume
    6.0
    """
    if kind == "box":
        half, volume = np.asarray(values["size"], dtype=float) / 2, float(np.prod(values["size"]))
    elif kind == "cylinder":
        r, h = float(values["radius"][0]), float(values["length"][0])
        half, volume = np.array([r, r, h / 2]), math.pi * r * r * h
    elif kind == "sphere":
        r = float(values["radius"][0])
        half, volume = np.array([r, r, r]), 4 / 3 * math.pi * r**3
    else:
        return Shape(kind, None, None)
    if not (np.all(np.isfinite(half)) and np.all(half >= 0) and np.all(np.isfinite(np.r_[xyz, rpy]))):
        return Shape(kind, None, None)
    local = np.array(list(itertools.product(*[(-h, h) for h in half])))
    return Shape(kind, volume, np.asarray(xyz, dtype=float) + local @ rotation_rpy(rpy).T)


def _measured(link):
    shapes = link.collision or link.visual
    if not shapes or any(s.volume is None for s in shapes):
        return None
    return shapes


def _slip(ratio: float) -> int | None:
    """The power of ten (a multiple of 3) that brings ``ratio`` (a value over what a material gives) to 1."""
    for power in sorted(SLIPS, key=abs):
        if MATERIALS[0] <= ratio / 10.0**power <= MATERIALS[1]:
            return power
    return None


def geometry_findings(link, total: float | None = None) -> list:
    """The density, centre-of-mass or radius-of-gyration finding of one link against its shapes: one diagnosis.

    Parameters
    ----------
    link : course_dynamics.tools.lint.Link
        The link as the linter reads it.
    total : float, optional
        The robot's mass, kg: a link under :data:`PLACEHOLDER` of it whose mass or inertia does not fit its
        shapes gets a ``placeholder-inertia`` note instead (a sensor's or a frame's 1 g in a 1 mm cube).

    Returns
    -------
    list of Finding
        At most one: ``units-slip``, ``implausible-density``, ``com-outside-geometry``, ``gyration-exceeds-link``
        or ``placeholder-inertia``; empty when the link has no mass, no measured shapes, or nothing wrong.
    """
    found = _diagnoses(link)[:1]
    m = link.inertial.mass if found else 0.0
    if found and total and m < PLACEHOLDER * total:
        measured = found[0].message.split(": ", 1)[1]
        measured = measured.rsplit(": ", 1)[0] if measured.endswith("?") else measured   # no unit to blame
        return [Finding("placeholder-inertia", "link", link.name, f"link '{link.name}': mass {m:g} kg, {m / total:.2g} "
                        f"of the robot's {total:.4g} kg, a placeholder that does not fit its shapes: {measured}",
                        link.line)]
    return found


def _diagnoses(link) -> list:
    inertial, shapes = link.inertial, _measured(link)
    if inertial is None or shapes is None or not (inertial.mass > 0) or not np.all(np.isfinite(inertial.inertia)) \
            or not np.all(np.isfinite(inertial.xyz)):
        return []
    m, owner, line, found = inertial.mass, f"link '{link.name}'", link.line, []
    volume = sum(s.volume for s in shapes)
    corners = np.vstack([s.corners for s in shapes])
    low, high = corners.min(axis=0), corners.max(axis=0)
    if volume > 0:
        rho = m / volume
        if not DENSITY[0] <= rho <= DENSITY[1]:
            power = _slip(rho)
            if power is None:
                found.append(Finding("implausible-density", "link", link.name, f"{owner}: mass {m:g} kg over the "
                                     f"shapes' {volume:.4g} m^3 is {rho:.4g} kg/m^3", line))
            else:
                found.append(Finding("units-slip", "link", link.name, f"{owner}: mass {m:g} kg over the shapes' "
                                     f"{volume:.4g} m^3 is {rho:.4g} kg/m^3, 1e{power} times a material's: "
                                     f"{SLIPS[power]}?", line))
    margin = COM_MARGIN * max(float((high - low).max()), 1e-9)
    com = inertial.xyz

    def inside(point):
        return bool(np.all(point >= low - margin) and np.all(point <= high + margin))

    if not inside(com):
        if inside(com / 1000) and float(np.abs(com).max()) > COM_SLIP * float((high - low).max()):
            found.append(Finding("units-slip", "link", link.name, f"{owner}: centre of mass {com.tolist()} lies far "
                                 "outside its shapes, and would lie within them in millimetres", line))
        else:
            found.append(Finding("com-outside-geometry", "link", link.name, f"{owner}: centre of mass "
                                 f"{com.tolist()} m lies outside the box {low.round(6).tolist()} to "
                                 f"{high.round(6).tolist()} m around its shapes", line))
        return found
    moments = np.linalg.eigvalsh(inertial.inertia)
    k = math.sqrt(max(float(moments[-1]), 0.0) / m)
    reach = float(np.linalg.norm(np.maximum(np.abs(low - com), np.abs(high - com))))
    if k > GYRATION_MARGIN * reach:
        if k >= GYRATION_SLIP * reach:
            found.append(Finding("units-slip", "link", link.name, f"{owner}: radius of gyration {k:.4g} m, "
                                 f"{k / reach:.3g} times the {reach:.4g} m its shapes reach: the inertia 1e3 or 1e6 "
                                 "times too large (g m^2 or kg mm^2)?", line))
        else:
            found.append(Finding("gyration-exceeds-link", "link", link.name, f"{owner}: radius of gyration "
                                 f"{k:.4g} m exceeds the {reach:.4g} m its shapes reach from the centre of mass",
                                 line))
    return found


def inertial_rpy_finding(link):
    """The ``inertial-rpy`` finding of a link whose ``<inertial><origin rpy>`` is not zero, with the tensor in the
    link's axes.

    Parameters
    ----------
    link : course_dynamics.tools.lint.Link
        The link as the linter reads it.

    Returns
    -------
    Finding or None
        The finding, or None when the rpy is zero (or not readable).
    """
    inertial = link.inertial
    if inertial is None or not np.all(np.isfinite(inertial.rpy)) or not np.any(inertial.rpy != 0):
        return None
    I = rotate(inertial.inertia, rotation_rpy(inertial.rpy))
    I = np.where(np.abs(I) > 1e-12 * np.abs(I).max(), I, 0.0) + 0.0  # round-off of the rotation, and -0, as 0
    entries = " ".join(f'{n}="{I[i, j]:.12g}"' for n, (i, j) in
                       (("ixx", (0, 0)), ("ixy", (0, 1)), ("ixz", (0, 2)), ("iyy", (1, 1)), ("iyz", (1, 2)),
                        ("izz", (2, 2))))
    rpy = " ".join(f"{x:g}" for x in inertial.rpy)
    return Finding("inertial-rpy", "link", link.name, f"link '{link.name}': <inertial><origin rpy=\"{rpy}\">; in "
                   f"the link's axes the tensor is {entries} (an importer that drops the rpy uses the tensor "
                   "unrotated)", link.line)


__all__ = ["DENSITY", "MATERIALS", "PLACEHOLDER", "Shape", "geometry_findings", "inertial_rpy_finding", "rotation_rpy",
           "shape"]
