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

Mimic joints: a URDF with ``<mimic>`` is built with ``mimic=True``, so that
Pinocchio's own mimic support (``JointModelMimic``: q_mimic = scaling · q + offset)
gives τ, M, G and V with one coordinate per independent joint. Where Pinocchio 4.1
does not honour mimic joints — ``aba``, the regressor, the energies refuse a mimic
model, and ``computeCoriolisMatrix`` returns a C with C Θ̇ ≠ V — the oracle uses the
model built without ``mimic`` (one coordinate per joint) through the coupling it
reads from Pinocchio's mimic joints (θ_bodies = S Θ + b): C = Sᵀ C S, the
regressor Sᵀ Y, Jacobians J S, energies and placements at S Θ + b, and Θ̈ by
solving M Θ̈ = τ − V − G with Pinocchio's mimic M and bias. A mimic joint's damping
and friction act at its own rate and add a² d and |a| c to its leader's (the
convention of ``Friction.from_urdf``; Pinocchio's mimic model keeps the leader's only).
"""
from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin


def _build_model(urdf, mimic: bool = False):
    """``pin.buildModelFromUrdf``; what urdfdom prints on failure becomes one InputError, not stray lines."""
    import os
    import tempfile

    from course_dynamics.base.errors import InputError

    with tempfile.TemporaryFile() as captured:
        saved = os.dup(2)
        os.dup2(captured.fileno(), 2)  # urdfdom writes its complaints to file descriptor 2 directly
        try:
            return pin.buildModelFromUrdf(str(urdf), mimic=mimic)
        except (ValueError, RuntimeError) as exc:
            captured.seek(0)
            said = [line.strip() for line in captured.read().decode("utf-8", "replace").splitlines() if line.strip()]
            reason = said[0] if said else str(exc).splitlines()[0]
            forms = _mimic_forms(urdf) if mimic else ()
            if forms:
                raise InputError(f"{urdf}: Pinocchio {pin.__version__} cannot build mimic joint " + "; ".join(
                    f"'{joint}' ({why})" for joint, why in forms) + ", a form course_dynamics honours, so there "
                    "is nothing to compare with") from None
            raise InputError(f"{urdf}: Pinocchio cannot read this URDF ({reason}); our loader is more lenient "
                             "(for example about joints without <limit>), "
                             "so there is nothing to compare with") from None
        finally:
            os.dup2(saved, 2)
            os.close(saved)


def _mimic_forms(urdf) -> tuple:
    """The mimic forms of ``urdf`` Pinocchio cannot build (``Model.mimic_forms``), () when it does not load."""
    from course_dynamics.base.errors import ModelError
    from course_dynamics.core.urdf import load_urdf

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the caller loaded the model already, and warned as it did
            return load_urdf(urdf, allow_nonphysical_inertia=True).mimic_forms
    except ModelError:
        return ()


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
        self.plain = _build_model(urdf)
        self.model = _build_model(urdf, mimic=True)
        self.has_mimic = self.model.nv != self.plain.nv
        if not self.has_mimic:
            self.model = self.plain
        for model in {id(self.model): self.model, id(self.plain): self.plain}.values():
            model.gravity.linear = np.asarray(gravity, dtype=float)
        self.data = self.model.createData()
        self.plain_data = self.plain.createData() if self.has_mimic else self.data  # one Data without mimic joints
        self.joint_names = tuple(joint_names)
        if self.model.nv != len(self.joint_names):
            raise ValueError(f"Pinocchio has {self.model.nv} velocity coordinates, "
                             f"we have {len(self.joint_names)} joints")
        ids = [self.model.getJointId(name) for name in self.joint_names]
        self.idx_q = [self.model.joints[i].idx_q for i in ids]
        self.nq = [self.model.joints[i].nq for i in ids]
        self.idx_v = np.array([self.model.joints[i].idx_v for i in ids])
        self._coupling()

    def _coupling(self) -> None:
        """S (plain nv × n) and b (plain joints) from Pinocchio's mimic joints: θ_plain = S Θ + b."""
        ours = {int(v): j for j, v in enumerate(self.idx_v)}
        self.S = np.zeros((self.plain.nv, len(self.joint_names)))
        self.b = np.zeros(self.plain.njoints)
        for jid in range(1, self.plain.njoints):
            row = self.plain.joints[jid].idx_v
            joint = self.model.joints[self.model.getJointId(self.plain.names[jid])]
            if joint.shortname() == "JointModelMimic":
                mimic = joint.extract()
                self.S[row, ours[joint.idx_v]] = mimic.scaling
                self.b[jid] = mimic.offset
            else:
                self.S[row, ours[joint.idx_v]] = 1.0

    def plain_configuration(self, q) -> np.ndarray:
        """The configuration of the model without mimic: every joint's θ = S Θ + b (continuous → cos, sin)."""
        theta = self.S @ np.asarray(q, dtype=float)
        q_pin = np.zeros(self.plain.nq)
        for jid in range(1, self.plain.njoints):
            joint = self.plain.joints[jid]
            value = theta[joint.idx_v] + self.b[jid]
            q_pin[joint.idx_q:joint.idx_q + joint.nq] = (np.cos(value), np.sin(value)) if joint.nq == 2 else value
        return q_pin

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
        S = self.S
        Y = pin.computeJointTorqueRegressor(self.plain, self.plain_data, self.plain_configuration(q), S @ qd, S @ qdd)
        return (S.T @ np.reshape(Y, (self.plain.nv, -1))).copy()  # Y = Sᵀ Y_plain: rows in our order already

    def add_payload(self, link: str, mass: float, com, inertia) -> None:
        """Fix a rigid body to URDF link ``link`` (Pinocchio's ``appendBodyToJoint``): mass (kg),
        centre of mass (3,) and inertia about it (3, 3), both in the link's frame."""
        frame = self.model.frames[self.model.getFrameId(link)]
        body = pin.Inertia(float(mass), np.asarray(com, dtype=float), np.asarray(inertia, dtype=float))
        self.model.appendBodyToJoint(frame.parentJoint, body, frame.placement)
        self.data = self.model.createData()
        self.plain_data = self.data
        if self.has_mimic:
            frame = self.plain.frames[self.plain.getFrameId(link)]
            self.plain.appendBodyToJoint(frame.parentJoint, body, frame.placement)
            self.plain_data = self.plain.createData()

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
        # Pinocchio 4.1's crba on a mimic model whose mimic is in another branch than its leader leaves Data
        # stale: a second call on one Data gives a wrong M. A fresh Data per call on mimic models; the shared
        # one without mimic joints.
        data = self.model.createData() if self.has_mimic else self.data
        A = pin.crba(self.model, data, self.configuration(q)).copy()
        A = np.triu(A) + np.triu(A, 1).T  # crba fills the upper triangle only
        return self._ours_matrix(A)

    def C(self, q, qd) -> np.ndarray:
        S = self.S
        return S.T @ pin.computeCoriolisMatrix(self.plain, self.plain_data, self.plain_configuration(q), S @ qd) @ S

    def G(self, q) -> np.ndarray:
        return self._ours(pin.computeGeneralizedGravity(self.model, self.data, self.configuration(q)).copy())

    def V(self, q, qd) -> np.ndarray:
        nle = pin.nonLinearEffects(self.model, self.data, self.configuration(q), self.velocity(qd)).copy()
        return self._ours(nle) - self.G(q)

    def terms(self, q, qd, qdd) -> dict[str, np.ndarray]:
        """τ, M, C, V, G at one state, our joint order."""
        return dict(tau=self.tau(q, qd, qdd), M=self.M(q), C=self.C(q, qd), V=self.V(q, qd), G=self.G(q))

    def kinetic_energy(self, q, qd) -> float:
        return float(pin.computeKineticEnergy(self.plain, self.plain_data, self.plain_configuration(q),
                                              self.S @ np.asarray(qd, dtype=float)))

    def potential_energy(self, q) -> float:
        return float(pin.computePotentialEnergy(self.plain, self.plain_data, self.plain_configuration(q)))

    def frame_placement(self, q, frame: str) -> tuple[np.ndarray, np.ndarray]:
        """⁰R_F (3, 3) and ⁰P_F (3,) of a URDF link's frame."""
        pin.framesForwardKinematics(self.plain, self.plain_data, self.plain_configuration(q))
        placement = self.plain_data.oMf[self.plain.getFrameId(frame, pin.BODY)]
        return placement.rotation.copy(), placement.translation.copy()

    @property
    def damping(self) -> np.ndarray:
        """Viscous coefficients (URDF ``<dynamics damping>``), our joint order."""
        return self.S.T ** 2 @ np.asarray(self.plain.damping)  # a² d of each joint on its coordinate

    @property
    def friction(self) -> np.ndarray:
        """Coulomb coefficients (URDF ``<dynamics friction>``), our joint order."""
        return np.abs(self.S.T) @ np.asarray(self.plain.friction)  # |a| c of each joint on its coordinate

    def set_armature(self, armature) -> None:
        """Rotor inertias (kg·m², kg) on our coordinates, as Pinocchio's ``model.armature``: added to the diagonal
        of crba's M and to rnea's τ (Iₐ Θ̈), and seen by aba."""
        self.model.armature[self.idx_v] = np.asarray(armature, dtype=float)

    def aba(self, q, qd, tau) -> np.ndarray:
        """Θ̈ by the articulated-body algorithm (no friction); with mimic joints, M⁻¹ (τ − V − G)."""
        if self.has_mimic:
            return np.linalg.solve(self.M(q), np.asarray(tau, dtype=float) - self.V(q, qd) - self.G(q))
        return self._ours(pin.aba(self.model, self.data, self.configuration(q), self.velocity(qd),
                                  self.velocity(tau)).copy())

    def _reference_frame(self, expressed_in: str):
        return {"base": pin.LOCAL_WORLD_ALIGNED, "frame": pin.LOCAL}[expressed_in]

    def frame_jacobian(self, q, frame: str, expressed_in: str = "base") -> np.ndarray:
        """(6, n) Jacobian of a URDF link's frame, rows (v; ω), our joint order."""
        frame_id = self.plain.getFrameId(frame)
        J = pin.computeFrameJacobian(self.plain, self.plain_data, self.plain_configuration(q), frame_id,
                                     self._reference_frame(expressed_in))
        return np.reshape(J, (6, self.plain.nv)) @ self.S  # eigenpy returns (6,) when nv = 1

    def frame_jacobian_dot(self, q, qd, frame: str, expressed_in: str = "base") -> np.ndarray:
        """(6, n) time variation of :meth:`frame_jacobian` along Θ̇."""
        frame_id = self.plain.getFrameId(frame)
        pin.computeJointJacobiansTimeVariation(self.plain, self.plain_data, self.plain_configuration(q),
                                               self.S @ np.asarray(qd, dtype=float))
        pin.updateFramePlacements(self.plain, self.plain_data)
        dJ = pin.getFrameJacobianTimeVariation(self.plain, self.plain_data, frame_id,
                                               self._reference_frame(expressed_in))
        return np.reshape(dJ, (6, self.plain.nv)) @ self.S

    def link_quantities(self, q, qd, qdd) -> dict[str, np.ndarray]:
        """Craig's per-link quantities from Pinocchio's RNEA data, each (n_bodies, 3) in our body order.

        Run on the model without mimic at θ_bodies = S Θ + b, so that a mimic joint's body has its row too.

        Pinocchio keeps spatial quantities in each joint frame (= our frame i):
        ``v[i]`` (linear velocity of the origin, ω), ``a_gf[i]`` (spatial
        acceleration with the −g base lift), ``f[i]`` (force and moment on body i
        from its parent, about the origin). Craig's v̇ is the classical
        acceleration of the origin, a.linear + ω × v.linear; at the COM c it is
        a.linear + ω̇ × c + ω × (v.linear + ω × c). The body's inertial load
        I a + v ×* I v gives ⁱFᵢ (linear) and ⁱNᵢ + c × ⁱFᵢ (angular).
        """
        model, data, S = self.plain, self.plain_data, self.S
        pin.rnea(model, data, self.plain_configuration(q), S @ np.asarray(qd, dtype=float),
                 S @ np.asarray(qdd, dtype=float))
        out = {key: [] for key in ("omega", "omega_dot", "v_dot", "v_dot_c", "F", "N", "f", "n")}
        names = self.joint_names if not self.has_mimic else model.names[1:]  # with mimic: Pinocchio's depth-first order
        for joint in map(model.getJointId, names):
            v, a, inertia = data.v[joint], data.a_gf[joint], model.inertias[joint]
            c, w = inertia.lever, v.angular
            load = inertia * a + v.cross(inertia * v)
            out["omega"].append(w)
            out["omega_dot"].append(a.angular)
            out["v_dot"].append(a.linear + np.cross(w, v.linear))
            out["v_dot_c"].append(a.linear + np.cross(a.angular, c) + np.cross(w, v.linear + np.cross(w, c)))
            out["F"].append(load.linear)
            out["N"].append(load.angular - np.cross(c, load.linear))
            out["f"].append(data.f[joint].linear)
            out["n"].append(data.f[joint].angular)
        return {key: np.array(values) for key, values in out.items()}
