"""Is an identified body plausible: its mass against the URDF's, its centre of mass within its link.

===========  ===========  ===========================================================================
code         symbol       meaning (unit)
===========  ===========  ===========================================================================
``extent``   ℓᵢ           how far link i reaches from its frame's origin, m: the farthest of its
                          child joints' origins, the links fixed to it, the URDF's centre of mass and
                          its <collision>/<visual> boxes, cylinders and spheres (meshes are not
                          read: their links reach as far as their joints); at least :data:`MIN_EXTENT`
===========  ===========  ===========================================================================

A body moved far when its mass more than doubled or halved (:data:`MASS_RATIO`), or its centre of
mass lies farther from its frame's origin than ℓᵢ.

>>> from course_dynamics import load_robot
>>> [round(float(x), 3) for x in link_extents(load_robot("two_link"))]     # to joint 2, to the tool
[0.5, 0.4]
"""
from __future__ import annotations

import numpy as np

from ..base.errors import CourseDynamicsError
from ..core.model import Model
from ..core.urdf import read_description

#: The least extent of a link, m (a link whose joints all sit at its origin still has a size).
MIN_EXTENT = 0.05
#: A mass this many times the URDF's (or this share of it) counts as moved far.
MASS_RATIO = 2.0


def _shape_reach(element, T) -> float:
    """How far a primitive shape at placement T (4, 4) in the body's frame reaches from the origin, m (0 for
    a mesh)."""
    geometry = element.geometry
    centre = float(np.linalg.norm(T[:3, 3]))
    if geometry.box is not None:
        return centre + 0.5 * float(np.linalg.norm(geometry.box.size))
    if geometry.cylinder is not None:
        return centre + float(np.hypot(geometry.cylinder.radius, geometry.cylinder.length / 2))
    if geometry.sphere is not None:
        return centre + float(geometry.sphere.radius)
    return 0.0


def _geometry_reach(model: Model) -> np.ndarray:
    """Per body, the reach of its links' primitive shapes (0 without any, or without a readable URDF)."""
    reach = np.zeros(model.n_bodies)
    if not model.source:
        return reach
    try:
        robot = read_description(model.source)
    except (CourseDynamicsError, OSError):
        return reach
    frames = {f.name: f for f in model.frames}
    for link in robot.links:
        frame = frames.get(link.name)
        if frame is None or frame.body < 0:
            continue
        T_body_link = np.eye(4)
        T_body_link[:3, :3], T_body_link[:3, 3] = frame.R, frame.P
        for element in list(link.visuals) + list(link.collisions):
            T = T_body_link @ (element.origin if element.origin is not None else np.eye(4))
            reach[frame.body] = max(reach[frame.body], _shape_reach(element, T))
    return reach


def link_extents(model: Model) -> np.ndarray:
    """ℓᵢ of every body (module table), m.

    Parameters
    ----------
    model : Model
        The robot (its URDF, ``model.source``, is read for shapes if it has one).

    Returns
    -------
    numpy.ndarray, shape (n_bodies,)
        Each link's extent, m.
    """
    extent = np.maximum(_geometry_reach(model), MIN_EXTENT)
    for i, body in enumerate(model.bodies):
        reaches = [np.linalg.norm(np.asarray(body.p_com, dtype=float))]
        reaches += [np.linalg.norm(np.asarray(model.bodies[c].P, dtype=float)) for c in model.children[i]]
        reaches += [np.linalg.norm(frame.P) for frame in model.frames if frame.body == i]
        extent[i] = max(extent[i], *reaches)
    return extent


def far_moves(original: Model, identified: Model, extents) -> list[str]:
    """What moved far, one sentence per body and kind (module docstring).

    Parameters
    ----------
    original : Model
        The URDF's robot.
    identified : Model
        The identified robot (same bodies).
    extents : numpy.ndarray, shape (n_bodies,)
        ℓᵢ (:func:`link_extents`), m.

    Returns
    -------
    list of str
        ``body 'name': …`` for a mass more than doubled or halved, and for a centre of mass outside its link.
    """
    lines = []
    for old, new, extent in zip(original.bodies, identified.bodies, extents):
        m0, m1 = float(old.mass), float(new.mass)
        if m0 > 0 and not 1 / MASS_RATIO <= m1 / m0 <= MASS_RATIO:
            lines.append(f"body '{old.name}': its mass went from {m0:.4g} kg to {m1:.4g} kg")
        distance = float(np.linalg.norm(np.asarray(new.p_com, dtype=float)))
        if distance > extent * (1 + 1e-9):
            lines.append(f"body '{old.name}': its centre of mass is {distance:.3g} m from its frame's origin, outside "
                         f"the link ({extent:.3g} m)")
    return lines


__all__ = ["MASS_RATIO", "MIN_EXTENT", "far_moves", "link_extents"]
