"""The linter's checks of each link's mass and inertia tensor: signs, the loader's test of a tensor, the boundary.

The tensor of a link on a moving body is tested as the loader tests it
(:func:`course_dynamics.core.urdf.inertia_problem`, one finding per tensor); the loader reads no tensor of a link
fixed to the base (it moves nothing), so such a tensor no body has is a ``base-inertia-not-physical`` warning.

==========  ==========================================================================================
symbol      meaning
==========  ==========================================================================================
``m``       a link's mass, kg
``I``       its inertia tensor about its centre of mass, in the ``<inertial>`` frame's axes, kg·m²
``I₁..I₃``  its principal moments, smallest first, kg·m²
==========  ==========================================================================================

>>> BOUNDARY
1e-06
"""
from __future__ import annotations

import numpy as np

from ..core.urdf import MAX_MAGNITUDE, inertia_problem
from .lint_classes import Finding
from .lint_geometry import inertial_rpy_finding

#: Principal moments this close to I1 + I2 = I3 (or to 0), relative to I3, lie on the boundary of what bodies have.
BOUNDARY = 1e-6
MOVING = ("revolute", "continuous", "prismatic")


def _on_base(tree) -> set:
    """The links fixed to the base (reached from the root through fixed joints only): the loader reads no inertia
    of theirs, since they move nothing."""
    if tree is None:
        return set()
    links, parents, above = tree
    fixed = [False] * len(links)
    for i, (parent, joint) in enumerate(zip(parents, above)):
        fixed[i] = parent < 0 or (fixed[parent] and joint.type == "fixed")
    return {link.name for link, on_base in zip(links, fixed) if on_base}


def _moments_text(I) -> str:
    """The principal moments, with eigenvalue round-off (below 1e-12 of the largest) written as 0."""
    moments = np.linalg.eigvalsh(I)
    moments = np.where(np.abs(moments) > 1e-12 * np.abs(moments).max(), moments, 0.0) + 0.0
    return ", ".join(f"{x:.6g}" for x in moments)


def inertia_findings(robot, tree) -> list:
    """The mass and inertia-tensor findings of every link, by the loader's rule.

    Parameters
    ----------
    robot : course_dynamics.tools.lint.Robot
        The URDF as the linter reads it.
    tree : tuple or None
        ``(links, parents, above)``: its links parents first, each one's parent index (−1 for the root) and the
        joint above it; None when the links form no tree (then no link is taken to be fixed to the base).

    Returns
    -------
    list of Finding
        ``negative-mass``, ``zero-mass``, ``inertia-not-psd``, ``triangle-inequality``,
        ``base-inertia-not-physical``, ``point-mass``, ``inertia-on-boundary`` and ``inertial-rpy`` findings.
    """
    return list(_inertias(robot, tree))


def _inertias(robot, tree):
    moved, on_base = {joint.child for joint in robot.joints if joint.type in MOVING}, _on_base(tree)
    for link in robot.links:
        inertial = link.inertial
        values = np.concatenate([[inertial.mass], inertial.inertia.ravel()]) if inertial is not None else None
        if values is None or not np.all(np.isfinite(values)) or np.abs(values).max() > MAX_MAGNITUDE:
            continue
        m, I, owner, line = inertial.mass, inertial.inertia, f"link '{link.name}'", link.line
        if m < 0:
            yield Finding("negative-mass", "link", link.name, f"{owner}: mass {m:g} kg", line)
        elif m == 0 and (link.name in moved or np.any(I != 0)):   # mass 0 elsewhere: a frame (a tool point)
            yield Finding("zero-mass", "link", link.name, f"{owner}: mass 0" + (
                " with a non-zero inertia, which no body has" if np.any(I != 0) else ""), line)
        problem = inertia_problem(I)   # the loader's rule, once per tensor
        if problem is not None:
            what = ("is not positive semi-definite" if "positive semi-definite" in problem else
                    "breaks the triangle inequality I1 + I2 >= I3")
            rule = ("base-inertia-not-physical" if link.name in on_base else
                    "inertia-not-psd" if "positive semi-definite" in problem else "triangle-inequality")
            yield Finding(rule, "link", link.name, f"{owner}: inertia tensor {what} (principal moments "
                          f"{_moments_text(I)} kg m^2)" + (", on a link fixed to the base" if link.name in on_base
                                                           else ""), line)
            continue
        moments = np.linalg.eigvalsh(I)
        if not np.any(I != 0):
            if m > 0:
                yield Finding("point-mass", "link", link.name, f"{owner}: mass {m:g} kg with zero rotational "
                              "inertia (a point mass)", line)
        elif moments[0] + moments[1] - moments[2] <= BOUNDARY * moments[2] or moments[0] <= BOUNDARY * moments[2]:
            yield Finding("inertia-on-boundary", "link", link.name, f"{owner}: principal moments "
                          f"{_moments_text(I)} kg m^2 lie on the boundary of what bodies have "
                          f"(I1 + I2 = I3, or I1 = 0, within {BOUNDARY:g})", line)
        found = inertial_rpy_finding(link)
        if found is not None:
            yield found


__all__ = ["BOUNDARY", "inertia_findings"]
