"""What a robot carries and what it pushes: a payload lumped into a link, and a wrench at a frame.

==================  ===========  =====================================================
code                Craig        meaning (shape, unit)
==================  ===========  =====================================================
``mass``            m            payload mass, kg
``com``             ᴸP_C         payload centre of mass in the link's frame (3,), m
``size``            a, b, c      edges of a uniform box payload along the link's axes, m
                                 (None: a point mass)
``force``           f_{N+1}      force the robot exerts on its surroundings (3,), N,
                                 base coordinates
``moment``          n_{N+1}      moment it exerts, about the frame's origin (3,), N·m,
                                 base coordinates
``J``               J(Θ)         the frame's Jacobian (6, n), base coordinates (6.91)
==================  ===========  =====================================================

A payload becomes part of the body its link belongs to: masses add, the centre
of mass is the mass-weighted mean, and both inertias move to the new centre by
the parallel-axis theorem (6.25). Every algorithm then sees an ordinary model.

A wrench follows Craig's convention for the inward iteration's start (6.51):
f_{N+1} and n_{N+1} are what the robot applies *to* its surroundings — a tool
pressing down on a table with 10 N is ``force = (0, 0, −10)``. The joint
torques that hold it are τ = Jᵀ F with F = (f, n) (chapter 5's static forces): by virtual work the
power the joints put in, τᵀΘ̇, is the power delivered to the surroundings, Fᵀ J Θ̇.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..base.errors import InputError
from ..core.cartesian import jacobian
from ..core.inertia import box, parallel_axis, rotate
from ..core.model import Model


@dataclass(frozen=True)
class Payload:
    """A point or box mass fixed to link ``link`` (None: the tip, see :func:`payload_link`).

    Parameters
    ----------
    mass : float
        The payload's mass m, kg (0 < m ≤ 1e9).
    link : str, optional
        The URDF link it is fixed to; None for the tip.
    com : tuple of float, shape (3,)
        Its centre of mass ᴸP_C in the link's frame, m.
    size : tuple of float, shape (3,), optional
        The edges a, b, c of a uniform box along the link's axes, m; None for a point mass.

    Raises
    ------
    InputError
        If the mass, centre of mass or size is not a finite number in range.
    """

    mass: float
    link: str | None = None
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    size: tuple[float, float, float] | None = None

    def __post_init__(self):
        if not (np.isfinite(self.mass) and 0 < self.mass <= 1e9):
            raise InputError(f"payload mass must be a positive number of kg (at most 1e9), got {self.mass}")
        com = np.asarray(self.com, dtype=float)
        if com.shape != (3,) or not np.all(np.isfinite(com)) or np.abs(com).max() > 1e3:
            raise InputError(f"payload centre of mass must be three numbers cx,cy,cz within 1000 m, got {self.com}")
        object.__setattr__(self, "com", tuple(com.tolist()))
        if self.size is not None:
            size = np.asarray(self.size, dtype=float)
            if size.shape != (3,) or not np.all(np.isfinite(size)) or np.any(size < 0) or np.any(size > 1e3):
                raise InputError(f"payload box size must be three numbers a,b,c between 0 and 1000 m, got {self.size}")
            object.__setattr__(self, "size", tuple(size.tolist()))

    def inertia(self) -> np.ndarray:
        """ᶜI of the payload about its own centre, in the link's axes (3, 3), kg·m².

        Returns
        -------
        numpy.ndarray, shape (3, 3)
            The inertia tensor, kg·m² (zero for a point mass).
        """
        return np.zeros((3, 3)) if self.size is None else box(self.mass, *self.size)


def payload_link(model: Model, payload: Payload) -> str:
    """The link a payload is fixed to: the one it names, else the tip — the last URDF link carried
    by the last moving body (a tool frame such as UR5's ``tool0`` where the URDF has one).

    Parameters
    ----------
    model : Model
        The robot.
    payload : Payload
        The payload.

    Returns
    -------
    str
        The link's name.
    """
    if payload.link is not None:
        return payload.link
    return [f.name for f in model.frames if f.body == model.n_bodies - 1][-1]


def with_payload(model: Model, payload: Payload) -> Model:
    """The same robot with ``payload`` lumped into the body of its link.

    Parameters
    ----------
    model : Model
        The robot.
    payload : Payload
        The payload.

    Returns
    -------
    Model
        The robot with the payload's mass, centre of mass and inertia added to the link's body (6.25).

    Raises
    ------
    ModelError
        If the link is unknown (the message lists the frames).
    InputError
        If the link is fixed to the base, where a payload moves nothing.
    """
    link = payload_link(model, payload)
    frame = model.frame(link)
    if frame.body < 0:
        raise InputError(f"link '{link}' is fixed to the base of robot '{model.name}': a payload there needs no torque")
    body = model.bodies[frame.body]
    m_p = payload.mass
    c_p = frame.R @ np.asarray(payload.com) + frame.P            # payload COM in the body's frame
    I_p = rotate(payload.inertia(), frame.R)                      # its inertia in the body's axes
    m = body.mass + m_p
    c = (body.mass * body.p_com + m_p * c_p) / m                  # the combined centre of mass
    I_c = parallel_axis(body.I_com, body.mass, body.p_com - c) + parallel_axis(I_p, m_p, c_p - c)  # (6.25)
    bodies = list(model.bodies)
    bodies[frame.body] = replace(body, mass=m, p_com=c, I_com=np.asarray(I_c, dtype=float))
    return replace(model, bodies=tuple(bodies))


@dataclass(frozen=True)
class Wrench:
    """Force and moment the robot exerts on its surroundings at the origin of frame ``link`` (base coordinates).

    Parameters
    ----------
    link : str
        The frame at whose origin the wrench acts.
    force : tuple of float, shape (3,)
        The force f_{N+1} the robot exerts, base coordinates, N.
    moment : tuple of float, shape (3,)
        The moment n_{N+1} it exerts about the frame's origin, base coordinates, N·m.

    Raises
    ------
    InputError
        If the force or moment is not three finite numbers (at most 1e12 in size).
    """

    link: str
    force: tuple[float, float, float]
    moment: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self):
        for name in ("force", "moment"):
            values = np.asarray(getattr(self, name), dtype=float)
            if values.shape != (3,) or not np.all(np.isfinite(values)) or np.abs(values).max() > 1e12:
                raise InputError(f"wrench {name} must be three finite numbers (at most 1e12 in size), "
                                 f"got {getattr(self, name)}")
            object.__setattr__(self, name, tuple(values.tolist()))

    @property
    def F(self) -> np.ndarray:
        """f and n stacked (6,), as the rows of J are ordered, N and N·m."""
        return np.array(self.force + self.moment)


def wrench_torques(model: Model, q, wrench: Wrench) -> np.ndarray:
    """τ = Jᵀ F (chapter 5's static-force relation): the joint torques that apply ``wrench``; shape like ``q``,
    (n,) or (N, n).

    Parameters
    ----------
    model : Model
        The robot.
    q : numpy.ndarray, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint).
    wrench : Wrench
        The wrench the robot exerts.

    Returns
    -------
    numpy.ndarray, shape (n,) or (N, n)
        Joint torques τ, N·m (N for a prismatic joint).

    Raises
    ------
    ModelError
        If the wrench's frame is not one of the robot's.
    StateError
        If ``q`` is not a finite array of shape (n,) or (N, n).
    """

    model.frame(wrench.link)  # a clear error for an unknown frame
    J = jacobian(model, q, wrench.link, expressed_in="base")     # (6, n) or (N, 6, n)
    return np.einsum("...kj,k->...j", J, wrench.F)                # τ = Jᵀ F (chapter 5)


__all__ = ["Payload", "Wrench", "payload_link", "with_payload", "wrench_torques"]
