"""PyBullet's adapter for the cross-engine check (see :mod:`course_dynamics_reference.engines`).

DIRECT mode, a fixed base, the file's inertias (``URDF_USE_INERTIA_FROM_FILE``, else PyBullet recomputes them
from the collision shapes), the URDF without ``<visual>`` and ``<collision>`` (it refuses a file whose meshes it
cannot find, and dynamics need none); what PyBullet prints goes to a temporary file at the file-descriptor level.
A body of more than :data:`MAX_LINKS` links is refused with that reason: PyBullet's per-link state fails.
PyBullet has no forward-dynamics call: Θ̈ = M⁻¹(τ − bias) from its own mass matrix and inverse dynamics.
A link without ``<inertial>`` gets 1 kg and unit inertia from PyBullet; the adapter loads a second copy
with an explicit zero inertial there, and that difference is the "massless links" convention.

=========  ==============================================
symbol     meaning
=========  ==============================================
Θ, Θ̇, Θ̈    joint positions (rad, m), velocities, accelerations
τ, M       joint torques (N·m, N), mass matrix
=========  ==============================================
"""
from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path

import numpy as np

from .engines import (
    EngineRefused,
    LoadedVariants,
    _lump,
    _quiet_descriptors,
    _world_inertia,
    geometry_free,
    import_engine,
)

MAX_LINKS = 128  # PyBullet 3.2.7: getLinkState serves every link of a 127-link body, fails for all of a 129-link one


def _explicit_massless(text: str) -> str:
    """Every ``<link>`` without ``<inertial>`` given a zero one (PyBullet would give it 1 kg)."""
    zero = ('<inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>'
            '</inertial>')

    def fill(match):
        whole = match.group(0)
        if "<inertial" in whole:
            return whole
        if whole.rstrip().endswith("/>") and "</link>" not in whole:
            return whole.rstrip()[:-2].rstrip() + ">" + zero + "</link>"
        return whole.replace("</link>", zero + "</link>")

    return re.sub(r"<link\b[^>]*/>|<link\b.*?</link>", fill, text, flags=re.S)


class PybulletEngine(LoadedVariants):
    """PyBullet in DIRECT mode, a fixed base and the file's inertias (``URDF_USE_INERTIA_FROM_FILE``)."""

    name = "pybullet"
    call = {"tau": "calculateInverseDynamics", "M": "calculateMassMatrix", "G": "calculateInverseDynamics at rest",
            "bias": "calculateInverseDynamics at qdd = 0", "forward": "M^-1 (tau - bias)"}
    ADDITIONS = ("massless links",)

    def __init__(self, model, urdf):
        super().__init__(model)
        self.pb = pybullet = import_engine("pybullet")
        # without geometry (the file's inertias are used, so no mesh is needed, nor a package:// path resolved)
        text = geometry_free(Path(urdf).read_text(encoding="utf-8"))
        with _quiet_descriptors():
            self.client = pybullet.connect(pybullet.DIRECT)
        try:
            self.bodies_loaded = [self._load_text(text)]
            plain = _explicit_massless(text)
            if plain != text:
                self.bodies_loaded.append(self._load_text(plain))
        except EngineRefused:
            self.close()
            raise
        links = pybullet.getNumJoints(self.bodies_loaded[0], physicsClientId=self.client)
        if links > MAX_LINKS:
            self.close()
            raise EngineRefused(f"its getLinkState serves a body of at most {MAX_LINKS} links; this one has {links}")
        pybullet.setGravity(*model.gravity, physicsClientId=self.client)
        body = self.bodies_loaded[0]
        infos = [pybullet.getJointInfo(body, j, physicsClientId=self.client)
                 for j in range(pybullet.getNumJoints(body, physicsClientId=self.client))]
        self.infos = infos
        movable = [info[1].decode() for info in infos if info[2] != pybullet.JOINT_FIXED]
        missing = [name for name in self.body_joints if name not in movable]
        if missing or len(movable) != model.n_bodies:
            raise EngineRefused(f"its movable joints {movable} are not ours {self.body_joints}")
        self.joint_order = movable
        self.order = np.array([movable.index(name) for name in self.body_joints])
        self.index = {info[1].decode(): info[0] for info in infos}
        self.axis_length = {info[1].decode(): float(np.linalg.norm(info[13])) if info[2] == pybullet.JOINT_PRISMATIC
                            else 1.0 for info in infos}
        for name, length in self.axis_length.items():
            if abs(length - 1.0) > 1e-12:
                self.notes.append(f"joint {name}: its kinematics (getLinkState) take the prismatic axis as written, "
                                  f"of length {length:.6g}, its dynamics a unit axis; the per-body data are read "
                                  "with the displacement scaled to match")

    def _load_text(self, text: str):
        """Load URDF text, written to a temporary file (PyBullet loads only files)."""
        handle, name = tempfile.mkstemp(suffix=".urdf")
        try:
            with os.fdopen(handle, "w", encoding="utf-8") as out:
                out.write(text)
            with _quiet_descriptors():
                return self.pb.loadURDF(name, useFixedBase=True, flags=self.pb.URDF_USE_INERTIA_FROM_FILE,
                                        physicsClientId=self.client)
        except self.pb.error as exc:
            raise EngineRefused(str(exc)) from None
        finally:
            os.unlink(name)

    def close(self):
        with _quiet_descriptors():
            self.pb.disconnect(physicsClientId=self.client)

    def _theirs(self, x) -> list:
        out = np.zeros(self.model.n_bodies)
        out[self.order] = x
        return out.tolist()

    def _call(self, k, function, *vectors):
        with _quiet_descriptors():
            try:
                return np.asarray(function(self.bodies_loaded[k], *map(self._theirs, vectors),
                                           physicsClientId=self.client))
            except self.pb.error as exc:  # its own limits: a refusal with its reason
                raise EngineRefused(str(exc)) from None  # its messages name the call ("… failed.")

    def _tau(self, k, q, qd, qdd):
        return self._call(k, self.pb.calculateInverseDynamics, q, qd, qdd)[self.order]

    def _M(self, k, q):
        return self._call(k, self.pb.calculateMassMatrix, q)[np.ix_(self.order, self.order)]

    def _bias(self, k, q, qd):
        return self._tau(k, q, qd, np.zeros(self.model.n_bodies))

    def _G(self, k, q):
        return self._bias(k, q, np.zeros(self.model.n_bodies))

    def _forward(self, k, q, qd, tau):
        return np.linalg.solve(self._M(k, q), np.asarray(tau) - self._bias(k, q, qd))

    def parts(self, term, *state):
        if len(self.bodies_loaded) == 1:
            return {}
        values = [self._at(term, k, *state) for k in range(2)]
        return {"massless links": values[0] - values[1]}

    def bodies(self, q):
        pb, body, client = self.pb, self.bodies_loaded[-1], self.client  # massless links as the URDF says
        for name, value in zip(self.body_joints, self.model.S @ np.asarray(q, dtype=float) + self.model.b):
            # resetJointState slides a prismatic joint along its axis as written, of whatever length
            pb.resetJointState(body, self.index[name], float(value) / self.axis_length[name], physicsClientId=client)
        owner = {-1: -1}
        lumps: dict[int, list] = {}
        for info in self.infos:
            link = info[0]
            owner[link] = link if info[2] != pb.JOINT_FIXED else owner[info[16]]
            if owner[link] < 0:
                continue
            try:
                dynamics = pb.getDynamicsInfo(body, link, physicsClientId=client)
                state = pb.getLinkState(body, link, computeForwardKinematics=True, physicsClientId=client)
            except pb.error as exc:
                raise EngineRefused(f"getLinkState or getDynamicsInfo of link {info[12].decode()}: {exc}") from None
            R = np.reshape(pb.getMatrixFromQuaternion(state[1]), (3, 3))
            lumps.setdefault(owner[link], []).append((float(dynamics[0]), np.asarray(state[0]),
                                                      _world_inertia(R, np.diag(dynamics[2]))))
        return {name: _lump(lumps[self.index[name]]) for name in self.body_joints}


__all__ = ["MAX_LINKS", "PybulletEngine"]
