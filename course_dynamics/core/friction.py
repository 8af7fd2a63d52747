"""Joint friction F(Θ̇), the term added to the dynamics in (6.114): τ = M Θ̈ + V + G + F.

==================  ======================================  ==================
model               F for one joint                         Craig
==================  ======================================  ==================
viscous             v θ̇                                     (6.110)
Coulomb             c sgn(θ̇)                                (6.111)
combined            c sgn(θ̇) + v θ̇                          (6.112)
==================  ======================================  ==================

``v`` is in N·m·s/rad (N·s/m for prismatic joints), ``c`` in N·m (N). By
default both come from the URDF's ``<dynamics damping="v" friction="c">``.

At zero velocity sgn(0) = 0: Coulomb friction vanishes exactly at rest and
does not model stiction (the static friction of (6.113)). A joint released
at rest under a torque smaller than c therefore starts to move, and a Coulomb
joint crossing θ̇ = 0 chatters at the step size. ``smoothing`` > 0 replaces
sgn(θ̇) by tanh(θ̇ / smoothing), a common regularisation that removes the chatter.

A mimic joint (θₖ = a θⱼ + b) has no coordinate: its damping vₖ and friction cₖ act at
its own rate a θ̇ⱼ and map onto the leader's coordinate through Sᵀ, so they add to the
leader's coefficients in :meth:`Friction.from_urdf`, exactly for sgn:

    Fⱼ = (vⱼ + a² vₖ) θ̇ⱼ + (cⱼ + abs(a) cₖ) sgn(θ̇ⱼ)

(with smoothing, the tanh is taken of the leader's rate).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError
from .model import Model


@dataclass(frozen=True)
class Friction:
    """Per-joint friction coefficients (arrays of shape (n,)).

    Parameters
    ----------
    viscous : array_like, shape (n,)
        v of (6.110) for each joint, N·m·s/rad (N·s/m for a prismatic joint); kept as a read-only float array.
    coulomb : array_like, shape (n,)
        c of (6.111) for each joint, N·m (N for a prismatic joint); kept as a read-only float array.
    smoothing : float, optional
        0 (the default) for sgn(θ̇); a velocity > 0 (rad/s, m/s) for tanh(θ̇ / smoothing).

    Raises
    ------
    InputError
        If a coefficient or ``smoothing`` is negative or not finite.

    Examples
    --------

    >>> friction = Friction(viscous=[0.5], coulomb=[0.2])   # N·m·s/rad, N·m
    >>> friction.torques([2.0]), friction.torques([0.0])     # (6.112); 0 at rest
    (array([1.2]), array([0.]))
    """

    viscous: np.ndarray
    coulomb: np.ndarray
    smoothing: float = 0.0

    def __post_init__(self):
        for name in ("viscous", "coulomb"):
            values = np.array(getattr(self, name), dtype=float)
            if not np.all(np.isfinite(values)) or np.any(values < 0):
                raise InputError(f"{name} friction coefficients must be finite and non-negative, got {values.tolist()}")
            values.setflags(write=False)
            object.__setattr__(self, name, values)
        if not 0 <= self.smoothing < float("inf"):  # inf would be no Coulomb friction, said another way
            raise InputError(f"friction smoothing must be finite and non-negative, got {self.smoothing}")

    @classmethod
    def from_urdf(cls, model: Model, smoothing: float = 0.0) -> "Friction":
        """Viscous = URDF damping, Coulomb = URDF friction, joint by joint; a mimic joint's onto its leader's
        coordinate (module docstring).

        Parameters
        ----------
        model : Model
            The robot, read from a URDF (each body's ``damping`` and ``friction``).
        smoothing : float, optional
            As for :class:`Friction`.

        Returns
        -------
        Friction
            The URDF's coefficients.

        Examples
        --------
        >>> from course_dynamics import load_robot
        >>> Friction.from_urdf(load_robot("two_link")).viscous.shape
        (2,)
        """
        viscous, coulomb = np.zeros(model.n), np.zeros(model.n)
        for body, (j, a, _) in zip(model.bodies, model.coupling):
            viscous[j] += a * a * float(body.damping)  # Sᵀ (v (S θ̇)): a² v
            coulomb[j] += abs(a) * float(body.friction)  # Sᵀ (c sgn(a θ̇)) = |a| c sgn(θ̇)
        return cls(viscous=viscous, coulomb=coulomb, smoothing=smoothing)

    @classmethod
    def none(cls, model: Model) -> "Friction":
        """No friction on any joint of ``model``: F(Θ̇) = 0.

        Parameters
        ----------
        model : Model
            The robot (its number of joints n).

        Returns
        -------
        Friction
            Zero coefficients, shape (n,).

        Examples
        --------
        >>> from course_dynamics import load_robot
        >>> Friction.none(load_robot("two_link")).torques([1.0, 2.0])
        array([0., 0.])
        """
        return cls(viscous=np.zeros(model.n), coulomb=np.zeros(model.n))

    def slope(self) -> np.ndarray:
        """The steepest ∂F/∂θ̇ of each joint away from a jump, shape (n,): v + c / smoothing with smoothing (at
        θ̇ = 0, where tanh is steepest), v for sgn (whose jump at θ̇ = 0 has no slope). An explicit step of dt
        follows the friction only while dt times the largest eigenvalue of M⁻¹ diag(slope) stays below the
        integrator's stability bound (2 for Euler, about 2.785 for RK4).

        Returns
        -------
        numpy.ndarray, shape (n,)
            N·m·s/rad (N·s/m for a prismatic joint).

        Examples
        --------
        >>> Friction(viscous=[0.1, 0.1], coulomb=[0.5, 0.0], smoothing=0.01).slope()
        array([50.1,  0.1])
        """
        return self.viscous + (self.coulomb / self.smoothing if self.smoothing > 0 else 0.0)

    def torques(self, qd) -> np.ndarray:
        """F(Θ̇), shape like ``qd``: (n,) or (N, n); opposes the motion.

        Parameters
        ----------
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s for a prismatic joint).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            Friction torques F(Θ̇) of (6.112), N·m (N for a prismatic joint).
        """
        qd = np.asarray(qd, dtype=float)
        sign = np.tanh(qd / self.smoothing) if self.smoothing > 0 else np.sign(qd)
        return self.coulomb * sign + self.viscous * qd  # (6.112)


__all__ = ["Friction"]
