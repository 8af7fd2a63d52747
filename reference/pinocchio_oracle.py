"""The same URDF through Pinocchio, in course_dynamics' joint order and units.

Pinocchio orders joints its own way and gives a continuous joint two
configuration entries (cos θ, sin θ); :class:`PinocchioOracle` matches joints
by name and converts, so its results line up entry by entry with ours.

Terms: ``tau`` ← ``rnea``; ``M`` ← ``crba`` (upper triangle, symmetrised);
``C`` ← ``computeCoriolisMatrix``; ``G`` ← ``computeGeneralizedGravity``;
``V`` ← ``nonLinearEffects`` − G; ``aba`` ← ``aba``; frame Jacobians ←
``getFrameJacobian`` and ``getFrameJacobianTimeVariation`` (``base`` is
LOCAL_WORLD_ALIGNED, ``frame`` is LOCAL); frame placements ← ``oMf`` after
``framesForwardKinematics``; energies ← ``computeKineticEnergy``,
``computePotentialEnergy``; joint damping and friction ← the model's
``damping`` and ``friction`` (read from the URDF by Pinocchio's own parser).
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin


def _build_model(urdf):
    """``pin.buildModelFromUrdf``; what urdfdom prints on failure becomes one InputError, not stray lines."""
    import os
    import tempfile

    from course_dynamics.base.errors import InputError

    with tempfile.TemporaryFile() as captured:
        saved = os.dup(2)
        os.dup2(captured.fileno(), 2)  # urdfdom writes its complaints to file descriptor 2 directly
        try:
            return pin.buildModelFromUrdf(str(urdf))
        except (ValueError, RuntimeError) as exc:
            captured.seek(0)
            said = [line.strip() for line in captured.read().decode("utf-8", "replace").splitlines() if line.strip()]
            reason = said[0] if said else str(exc).splitlines()[0]
            raise InputError(f"{urdf}: Pinocchio cannot read this URDF ({reason}); our loader is more lenient "
                             "(for example about joints without <limit>), "
                             "so there is nothing to compare with") from None
        finally:
            os.dup2(saved, 2)
            os.close(saved)


class PinocchioOracle:
    """Pinocchio model of a URDF, evaluated on states in our joint order.

    Parameters
    ----------
    urdf : str or Path
    joint_names : sequence of str
        Our joint order (``Model.joint_names``); every name must be a Pinocchio joint.
    gravity : array_like, shape (3,)
    """

    def __init__(self, urdf, joint_names, gravity=(0.0, 0.0, -9.81)):
        self.model = _build_model(urdf)
        self.model.gravity.linear = np.asarray(gravity, dtype=float)
        self.data = self.model.createData()
        self.joint_names = tuple(joint_names)
        if self.model.nv != len(self.joint_names):
            raise ValueError(f"Pinocchio has {self.model.nv} velocity coordinates, "
                             f"we have {len(self.joint_names)} joints")
        ids = [self.model.getJointId(name) for name in self.joint_names]
        self.idx_q = [self.model.joints[i].idx_q for i in ids]
        self.nq = [self.model.joints[i].nq for i in ids]
        self.idx_v = np.array([self.model.joints[i].idx_v for i in ids])

    def configuration(self, q) -> np.ndarray:
        """Pinocchio's q from our Θ (continuous joints → cos θ, sin θ)."""
        q_pin = np.zeros(self.model.nq)
        for theta, start, nq in zip(np.asarray(q, dtype=float), self.idx_q, self.nq):
            q_pin[start:start + nq] = (np.cos(theta), np.sin(theta)) if nq == 2 else theta
        return q_pin

    def velocity(self, v) -> np.ndarray:
        """Pinocchio's v (or a) from ours."""
        v_pin = np.zeros(self.model.nv)
        v_pin[self.idx_v] = v
        return v_pin

    def _ours(self, x: np.ndarray) -> np.ndarray:
        return x[self.idx_v]

    def _ours_matrix(self, A: np.ndarray) -> np.ndarray:
        return A[np.ix_(self.idx_v, self.idx_v)]

    def tau(self, q, qd, qdd) -> np.ndarray:
        return self._ours(pin.rnea(self.model, self.data, self.configuration(q), self.velocity(qd),
                                   self.velocity(qdd)).copy())

    def regressor(self, q, qd, qdd) -> np.ndarray:
        """``computeJointTorqueRegressor``, (n, 10 n): rows in our joint order, columns in Pinocchio's.

        Columns come in blocks of ten per Pinocchio joint (joint id j ≥ 1 owns columns 10 (j − 1) …),
        each block m, m c, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz about the joint frame's origin
        (``Inertia.toDynamicParameters``).
        """
        Y = pin.computeJointTorqueRegressor(self.model, self.data, self.configuration(q), self.velocity(qd),
                                            self.velocity(qdd))
        return np.reshape(Y, (self.model.nv, -1))[self.idx_v].copy()

    def add_payload(self, link: str, mass: float, com, inertia) -> None:
        """Fix a rigid body to URDF link ``link`` (Pinocchio's ``appendBodyToJoint``): mass (kg),
        centre of mass (3,) and inertia about it (3, 3), both in the link's frame."""
        frame = self.model.frames[self.model.getFrameId(link)]
        body = pin.Inertia(float(mass), np.asarray(com, dtype=float), np.asarray(inertia, dtype=float))
        self.model.appendBodyToJoint(frame.parentJoint, body, frame.placement)
        self.data = self.model.createData()

    def tau_with_wrench(self, q, qd, qdd, link: str, force, moment) -> np.ndarray:
        """``rnea`` with external forces: the robot exerts (force, moment) at the origin of ``link``
        (base coordinates), so the surroundings push back with the opposite wrench on its joint."""
        q_pin = self.configuration(q)
        pin.framesForwardKinematics(self.model, self.data, q_pin)
        frame_id = self.model.getFrameId(link)
        joint = self.model.frames[frame_id].parentJoint
        origin = self.data.oMf[frame_id].translation
        f, n = -np.asarray(force, dtype=float), -np.asarray(moment, dtype=float)
        on_robot = pin.Force(f, n + np.cross(origin, f))               # about the world origin, world axes
        fext = [pin.Force.Zero() for _ in range(self.model.njoints)]
        fext[joint] = self.data.oMi[joint].actInv(on_robot)             # in the joint's frame
        tau = pin.rnea(self.model, self.data, q_pin, self.velocity(qd), self.velocity(qdd), fext)
        return self._ours(tau.copy())

    def M(self, q) -> np.ndarray:
        A = pin.crba(self.model, self.data, self.configuration(q)).copy()
        A = np.triu(A) + np.triu(A, 1).T  # crba fills the upper triangle only
        return self._ours_matrix(A)

    def C(self, q, qd) -> np.ndarray:
        return self._ours_matrix(pin.computeCoriolisMatrix(self.model, self.data, self.configuration(q),
                                                           self.velocity(qd)).copy())

    def G(self, q) -> np.ndarray:
        return self._ours(pin.computeGeneralizedGravity(self.model, self.data, self.configuration(q)).copy())

    def V(self, q, qd) -> np.ndarray:
        nle = pin.nonLinearEffects(self.model, self.data, self.configuration(q), self.velocity(qd)).copy()
        return self._ours(nle) - self.G(q)

    def terms(self, q, qd, qdd) -> dict[str, np.ndarray]:
        """τ, M, C, V, G at one state, our joint order."""
        return dict(tau=self.tau(q, qd, qdd), M=self.M(q), C=self.C(q, qd), V=self.V(q, qd), G=self.G(q))

    def kinetic_energy(self, q, qd) -> float:
        return float(pin.computeKineticEnergy(self.model, self.data, self.configuration(q), self.velocity(qd)))

    def potential_energy(self, q) -> float:
        return float(pin.computePotentialEnergy(self.model, self.data, self.configuration(q)))

    def frame_placement(self, q, frame: str) -> tuple[np.ndarray, np.ndarray]:
        """⁰R_F (3, 3) and ⁰P_F (3,) of a URDF link's frame."""
        pin.framesForwardKinematics(self.model, self.data, self.configuration(q))
        placement = self.data.oMf[self.model.getFrameId(frame, pin.BODY)]
        return placement.rotation.copy(), placement.translation.copy()

    @property
    def damping(self) -> np.ndarray:
        """Viscous coefficients (URDF ``<dynamics damping>``), our joint order."""
        return self._ours(np.asarray(self.model.damping))

    @property
    def friction(self) -> np.ndarray:
        """Coulomb coefficients (URDF ``<dynamics friction>``), our joint order."""
        return self._ours(np.asarray(self.model.friction))

    def aba(self, q, qd, tau) -> np.ndarray:
        """Θ̈ by the articulated-body algorithm (no friction)."""
        return self._ours(pin.aba(self.model, self.data, self.configuration(q), self.velocity(qd),
                                  self.velocity(tau)).copy())

    def _reference_frame(self, expressed_in: str):
        return {"base": pin.LOCAL_WORLD_ALIGNED, "frame": pin.LOCAL}[expressed_in]

    def frame_jacobian(self, q, frame: str, expressed_in: str = "base") -> np.ndarray:
        """(6, n) Jacobian of a URDF link's frame, rows (v; ω), our joint order."""
        frame_id = self.model.getFrameId(frame)
        J = pin.computeFrameJacobian(self.model, self.data, self.configuration(q), frame_id,
                                     self._reference_frame(expressed_in))
        return np.reshape(J, (6, self.model.nv))[:, self.idx_v].copy()  # eigenpy returns (6,) when nv = 1

    def frame_jacobian_dot(self, q, qd, frame: str, expressed_in: str = "base") -> np.ndarray:
        """(6, n) time variation of :meth:`frame_jacobian` along Θ̇."""
        frame_id = self.model.getFrameId(frame)
        pin.computeJointJacobiansTimeVariation(self.model, self.data, self.configuration(q), self.velocity(qd))
        pin.updateFramePlacements(self.model, self.data)
        dJ = pin.getFrameJacobianTimeVariation(self.model, self.data, frame_id, self._reference_frame(expressed_in))
        return np.reshape(dJ, (6, self.model.nv))[:, self.idx_v].copy()

    def link_quantities(self, q, qd, qdd) -> dict[str, np.ndarray]:
        """Craig's per-link quantities from Pinocchio's RNEA data, each (n, 3) in our body order.

        Pinocchio keeps spatial quantities in each joint frame (= our frame i):
        ``v[i]`` (linear velocity of the origin, ω), ``a_gf[i]`` (spatial
        acceleration with the −g base lift), ``f[i]`` (force and moment on body i
        from its parent, about the origin). Craig's v̇ is the classical
        acceleration of the origin, a.linear + ω × v.linear; at the COM c it is
        a.linear + ω̇ × c + ω × (v.linear + ω × c). The body's inertial load
        I a + v ×* I v gives ⁱFᵢ (linear) and ⁱNᵢ + c × ⁱFᵢ (angular).
        """
        pin.rnea(self.model, self.data, self.configuration(q), self.velocity(qd), self.velocity(qdd))
        out = {key: [] for key in ("omega", "omega_dot", "v_dot", "v_dot_c", "F", "N", "f", "n")}
        for name in self.joint_names:
            joint = self.model.getJointId(name)
            v, a, inertia = self.data.v[joint], self.data.a_gf[joint], self.model.inertias[joint]
            c, w = inertia.lever, v.angular
            load = inertia * a + v.cross(inertia * v)
            out["omega"].append(w)
            out["omega_dot"].append(a.angular)
            out["v_dot"].append(a.linear + np.cross(w, v.linear))
            out["v_dot_c"].append(a.linear + np.cross(a.angular, c) + np.cross(w, v.linear + np.cross(w, c)))
            out["F"].append(load.linear)
            out["N"].append(load.angular - np.cross(c, load.linear))
            out["f"].append(self.data.f[joint].linear)
            out["n"].append(self.data.f[joint].angular)
        return {key: np.array(values) for key, values in out.items()}
