"""One URDF in four engines, each called through its own API as its users call it, in our joint order.

Every adapter answers the same five questions at one state, in course_dynamics' joint order and units
(joints are matched by name), and gives each moving body's mass and inertia as it placed them:

==========  ======================================================================================
method      course_dynamics / Pinocchio / MuJoCo / PyBullet
==========  ======================================================================================
``tau``     ``inverse_dynamics`` / ``rnea`` / ``mj_inverse`` ``qfrc_inverse`` /
            ``calculateInverseDynamics``
``M``       ``mass_matrix`` / ``crba`` / ``mj_fullM`` / ``calculateMassMatrix``
``G``       ``gravity_torques`` / ``computeGeneralizedGravity`` / ``qfrc_bias`` at Θ̇ = 0 /
            inverse dynamics at Θ̇ = Θ̈ = 0
``bias``    V + G / ``nonLinearEffects`` / ``qfrc_bias`` / inverse dynamics at Θ̈ = 0
``forward`` ``forward_dynamics`` / ``aba`` / ``mj_forward`` ``qacc`` (τ as ``qfrc_applied``) /
            M⁻¹(τ − bias) from its own M and bias (PyBullet has no forward-dynamics call)
``bodies``  per moving body (a body and what fixed joints hold to it): m (kg), ⁰P_C (3,) m, the
            inertia about the centre of mass in base axes (3, 3) kg·m²
==========  ======================================================================================

PyBullet's adapter is in :mod:`course_dynamics_reference.engines_pybullet`. Where an engine adds something
course_dynamics does not (MuJoCo's joint damping, friction loss, armature and constraints; PyBullet's 1 kg
for a link without ``<inertial>``), the adapter holds a second, plain
model without it, and :meth:`Engine.parts` gives what each addition contributes: the engine's own answer
minus its answer without that addition, measured, never assumed. ``notes`` are what the adapter did to load
the model (an inertia raised to the engine's bound, a gravity set, joints matched by name).

==================  ============================================================
symbol              meaning
==================  ============================================================
Θ, Θ̇, Θ̈ (q, qd, qdd)  joint positions (rad, m), velocities, accelerations
τ                   joint torques, N·m (N for a prismatic joint)
M, G, bias          mass matrix, gravity torques, C(Θ, Θ̇)Θ̇ + G(Θ)
==================  ============================================================
"""
from __future__ import annotations

import contextlib
import copy
import os
import re
import sys
import tempfile
from pathlib import Path

import numpy as np

from course_dynamics import forward_dynamics, forward_kinematics, gravity_torques, inverse_dynamics, mass_matrix
from course_dynamics import velocity_torques
from course_dynamics.core.drives import Drives

ENGINES = ("course_dynamics", "pinocchio", "mujoco", "pybullet")
MUJOCO_INERTIA_BOUND = 1e-15  # MuJoCo's mjMINVAL: the least mass (kg) and inertia (kg·m²) it takes for a moving body
MUJOCO_COMPILER = ('<mujoco><compiler discardvisual="true" fusestatic="false" inertiafromgeom="false"{bound}/>'
                   '</mujoco>')


class EngineUnavailable(Exception):
    """The engine's Python package is not installed or cannot be imported: the engine is skipped with a note."""


class EngineRefused(Exception):
    """The engine would not load the model; ``str(exc)`` is its reason, in one line."""


def import_engine(package: str):
    """Import an engine's package; any failure (not installed, a missing system library) is a skip with its reason.

    Parameters
    ----------
    package : str
        ``"pinocchio"``, ``"mujoco"`` or ``"pybullet"``.

    Returns
    -------
    module
        The package.

    Raises
    ------
    EngineUnavailable
        If it cannot be imported; the message says why in one line.
    """
    try:
        with _quiet_descriptors():  # PyBullet prints its build time when imported
            return __import__(package)
    except ImportError as exc:
        raise EngineUnavailable(f"{package} is not installed ({exc})") from None
    except Exception as exc:  # an engine's import runs native code: a missing libGL is an OSError, and so on
        raise EngineUnavailable(f"{package} cannot be imported ({type(exc).__name__}: {exc})") from None


@contextlib.contextmanager
def _quiet_descriptors():
    """File descriptors 1 and 2 into a temporary file while an engine's C code prints (PyBullet, urdfdom)."""
    sys.stdout.flush()
    sys.stderr.flush()
    with tempfile.TemporaryFile() as sink:
        saved = [os.dup(1), os.dup(2)]
        os.dup2(sink.fileno(), 1)
        os.dup2(sink.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)


def _world_inertia(R, inertia) -> np.ndarray:
    return R @ inertia @ R.T


def _lump(parts) -> tuple[float, np.ndarray, np.ndarray]:
    """(m, centre of mass, inertia about it) of rigidly joined parts, each (m, ⁰P_C, ⁰I_C)."""
    mass = sum(m for m, _, _ in parts)
    com = sum(m * c for m, c, _ in parts) / mass if mass > 0 else np.zeros(3)
    inertia = np.zeros((3, 3))
    for m, c, I in parts:
        d = c - com
        inertia += I + m * (d @ d * np.eye(3) - np.outer(d, d))  # parallel axes
    return float(mass), com, inertia


class Engine:
    """What every adapter answers; the course_dynamics adapter is this class itself.

    Parameters
    ----------
    model : course_dynamics.Model
        The robot as course_dynamics loaded it (its joint order and gravity are the comparison's).
    rotors : array_like, shape (n,), optional
        Rotor inertias (kg·m², kg) course_dynamics adds as its own drives
        (:class:`~course_dynamics.core.drives.Drives`, no offsets): τ + Iₐ Θ̈, M + diag(Iₐ), and Θ̈ through
        both. Their addition is then no convention of an engine that has it too (``included``).
    """

    name = "course_dynamics"
    call = {"tau": "inverse_dynamics", "M": "mass_matrix", "G": "gravity_torques", "bias": "velocity_torques + G",
            "forward": "forward_dynamics"}

    def __init__(self, model, rotors=None):
        self.model = model
        self.notes: list[str] = []
        self.joint_order: list[str] = list(model.joint_names)  # the engine's own order of our joints
        self.drives = None if rotors is None else Drives(armature=rotors, offset=np.zeros(model.n))
        self.included = () if rotors is None else ("armature",)   # additions course_dynamics makes itself

    def tau(self, q, qd, qdd):
        tau = inverse_dynamics(self.model, q, qd, qdd)
        return tau if self.drives is None else tau + self.drives.torques(qdd)

    def M(self, q):
        M = mass_matrix(self.model, q)
        return M if self.drives is None else self.drives.mass_matrix(M)

    def G(self, q):
        return gravity_torques(self.model, q)

    def bias(self, q, qd):
        return velocity_torques(self.model, q, qd) + gravity_torques(self.model, q)

    def forward(self, q, qd, tau):
        return forward_dynamics(self.model, q, qd, tau, drives=self.drives)

    def parts(self, term: str, *state) -> dict[str, np.ndarray]:
        """What each of the engine's own additions contributes to ``term`` at ``state`` (none here)."""
        return {}

    def close(self) -> None:
        """Let the engine's resources go (PyBullet's physics client)."""

    def bodies(self, q) -> dict[str, tuple[float, np.ndarray, np.ndarray]]:
        placed = forward_kinematics(self.model, q)
        return {b.joint: (float(b.mass), placed.P_com[i], _world_inertia(placed.R[i], np.asarray(b.I_com)))
                for i, b in enumerate(self.model.bodies)}


class LoadedVariants(Engine):
    """An engine holding the URDF loaded several ways (as given, then with its own additions turned off one by
    one): the terms are those of the first, ``_term(k, …)`` of the k-th.

    ``_term`` works on one coordinate per moving joint of the file, a mimic joint's included (``body_joints``,
    our body order); :meth:`_at` gives it our states at θ = S Θ + b and maps what it returns onto our coordinates
    by Sᵀ (Sᵀ M S for M), and Θ̈ as the solution of (Sᵀ M S) Θ̈ = τ − Sᵀ bias (the convention "mimic joints
    coupled here").
    """

    def __init__(self, model):
        super().__init__(model)
        self.body_joints = [body.joint for body in model.bodies]

    def _at(self, term: str, k: int, *state):
        if not self.model.has_mimic:
            return getattr(self, f"_{term}")(k, *state)
        S, b = self.model.S, self.model.b
        if term == "forward":
            q, qd, tau = state
            return np.linalg.solve(self._at("M", k, q), np.asarray(tau, dtype=float) - self._at("bias", k, q, qd))
        q, *rates = (np.asarray(x, dtype=float) for x in state)
        value = getattr(self, f"_{term}")(k, S @ q + b, *(S @ rate for rate in rates))
        return S.T @ value @ S if term == "M" else S.T @ value

    def tau(self, q, qd, qdd):
        return self._at("tau", 0, q, qd, qdd)

    def M(self, q):
        return self._at("M", 0, q)

    def G(self, q):
        return self._at("G", 0, q)

    def bias(self, q, qd):
        return self._at("bias", 0, q, qd)

    def forward(self, q, qd, tau):
        return self._at("forward", 0, q, qd, tau)


class PinocchioEngine(Engine):
    """Pinocchio through :class:`~course_dynamics_reference.pinocchio_oracle.PinocchioOracle`."""

    name = "pinocchio"
    call = {"tau": "rnea", "M": "crba", "G": "computeGeneralizedGravity", "bias": "nonLinearEffects",
            "forward": "aba"}

    def __init__(self, model, urdf):
        super().__init__(model)
        import_engine("pinocchio")
        from course_dynamics.base.errors import InputError

        from .pinocchio_oracle import PinocchioOracle

        try:
            self.oracle = PinocchioOracle(urdf, model.joint_names, model.gravity)
        except (InputError, ValueError, RuntimeError) as exc:  # urdfdom's and Pinocchio's C++ exceptions
            raise EngineRefused(str(exc).split(": ", 1)[-1]) from None
        pin_model = self.oracle.plain
        self.joint_order = [pin_model.names[j] for j in range(1, pin_model.njoints)]
        self.continuous = [name for name, nq in zip(model.joint_names, self.oracle.nq) if nq == 2]

    def tau(self, q, qd, qdd):
        return self.oracle.tau(q, qd, qdd)

    def M(self, q):
        return self.oracle.M(q)

    def G(self, q):
        return self.oracle.G(q)

    def bias(self, q, qd):
        return self.oracle.V(q, qd) + self.oracle.G(q)

    def forward(self, q, qd, tau):
        return self.oracle.aba(q, qd, tau)

    def parts(self, term, *state):
        armature = np.array(self.oracle.model.armature, dtype=float)
        if not armature.any():
            return {}
        value = getattr(self, term)(*state)
        self.oracle.model.armature = np.zeros_like(armature)
        try:
            plain = getattr(self, term)(*state)
        finally:
            self.oracle.model.armature = armature
        return {"armature": value - plain}

    def bodies(self, q):
        import pinocchio as pin

        plain, data = self.oracle.plain, self.oracle.plain_data  # every moving joint's body, a mimic's included
        pin.forwardKinematics(plain, data, self.oracle.plain_configuration(q))
        out = {}
        for body in self.model.bodies:
            name = body.joint
            joint = plain.getJointId(name)
            placement, inertia = data.oMi[joint], plain.inertias[joint]
            R = placement.rotation
            out[name] = (float(inertia.mass), placement.translation + R @ inertia.lever,
                         _world_inertia(R, np.asarray(inertia.inertia)))
        return out


def geometry_free(text: str) -> str:
    """A URDF's text without ``<visual>`` and ``<collision>`` (meshes, ``package://`` paths): dynamics need none."""
    for tag in ("visual", "collision"):
        text = re.sub(rf"<{tag}\b[^>]*/>|<{tag}\b.*?</{tag}>", "", text, flags=re.S)
    return text


def _flush_subnormal(text: str) -> tuple[str, str]:
    """``text`` with every number smaller in size than the least normal double written as 0, and what was."""
    found = []

    def flush(match):
        value = float(match.group(0))
        if 0.0 < abs(value) < sys.float_info.min:
            found.append(abs(value))
            return "0"
        return match.group(0)

    text = re.sub(r"[-+]?(\d+\.?\d*|\.\d+)[eE][-+]?\d+", flush, text)
    many = f"{len(found)} numbers" if len(found) > 1 else "1 number"
    return text, (f"{many} of size at most {max(found):.3g} read as 0" if found else "")


class MujocoEngine(LoadedVariants):
    """MuJoCo's URDF importer, with the compiler told to keep fixed bodies and read inertias from the file."""

    name = "mujoco"
    call = {"tau": "mj_inverse", "M": "mj_fullM", "G": "qfrc_bias at qd = 0", "bias": "qfrc_bias",
            "forward": "mj_forward"}
    # What MuJoCo adds that course_dynamics does not, in the order the plain model drops them.
    ADDITIONS = ("damping", "frictionloss", "armature", "equality", "limits")
    DISABLE = {"equality": "mjDSBL_EQUALITY", "limits": "mjDSBL_LIMIT"}

    def __init__(self, model, urdf, armature=None):
        super().__init__(model)
        self.mj = mujoco = import_engine("mujoco")
        text = geometry_free(re.sub(r"<\?xml.*?\?>", "", Path(urdf).read_text(encoding="utf-8"), flags=re.S))
        raw = self._compile(text, "")
        self.subnormal = None
        if isinstance(raw, str) and "number is too large" in raw:  # its reader refuses a subnormal number
            text, self.subnormal = _flush_subnormal(text)
            self.subnormal = f"{raw}; {self.subnormal}" if self.subnormal else None
            raw = self._compile(text, "") if self.subnormal else raw
        if isinstance(raw, str):
            first = raw
            raw = self._compile(text, f' boundmass="{MUJOCO_INERTIA_BOUND:g}" boundinertia="{MUJOCO_INERTIA_BOUND:g}"')
            if isinstance(raw, str):
                raise EngineRefused(first)
            self.bounded = first
        else:
            self.bounded = None
        names = [raw.joint(j).name for j in range(raw.njnt)]
        missing = [name for name in self.body_joints if name not in names]
        if missing:
            raise EngineRefused(f"no joint {', '.join(missing)} in MuJoCo's model")
        joints = [names.index(name) for name in self.body_joints]
        self.joint_order = [name for name in names if name in self.body_joints]
        self.qpos = np.array([raw.jnt_qposadr[j] for j in joints])
        self.dof = np.array([raw.jnt_dofadr[j] for j in joints])
        if armature is not None:
            own = np.zeros(model.n_bodies)  # on each coordinate's own joint (a mimic joint has no rotor of its own)
            own[list(model.coordinates)] = armature
            raw.dof_armature[self.dof] = own  # as MuJoCo's users set it: the URDF cannot say it
        raw.opt.gravity[:] = model.gravity
        self.models = [raw]
        for addition in self.ADDITIONS:  # each plain model drops one more of MuJoCo's additions
            plain = self._copy(self.models[-1])
            if addition in self.DISABLE:
                plain.opt.disableflags |= int(getattr(mujoco.mjtDisableBit, self.DISABLE[addition]))
            else:
                getattr(plain, f"dof_{addition}")[:] = 0.0
            self.models.append(plain)
        self.data = [mujoco.MjData(m) for m in self.models]
        self.body_owner = self._owners(raw)

    def _compile(self, text: str, bound: str):
        extension = MUJOCO_COMPILER.format(bound=bound)
        text = re.sub(r"<mujoco\b[^>]*/>|<mujoco\b.*?</mujoco>", "", text, flags=re.S)  # ours replaces the URDF's own
        text = re.sub(r"(<robot\b[^>]*>)", lambda m: m.group(1) + extension, text, count=1)
        try:
            return self.mj.MjModel.from_xml_string(text)
        except (ValueError, RuntimeError) as exc:
            return " ".join(str(exc).split()).removeprefix("Error: ")

    def _copy(self, model):
        return copy.copy(model)

    def _owners(self, m) -> dict[int, int]:
        owner = {0: -1}
        for b in range(1, m.nbody):
            owner[b] = b if m.body_jntnum[b] > 0 else owner[int(m.body_parentid[b])]
        return owner

    def _state(self, k: int, q, qd=None, qdd=None, applied=None):
        m, d = self.models[k], self.data[k]
        d.qpos[:] = 0.0
        d.qvel[:] = 0.0
        d.qacc[:] = 0.0
        d.qfrc_applied[:] = 0.0
        d.qpos[self.qpos] = q
        if qd is not None:
            d.qvel[self.dof] = qd
        if qdd is not None:
            d.qacc[self.dof] = qdd
        if applied is not None:
            d.qfrc_applied[self.dof] = applied
        return m, d

    def _tau(self, k, q, qd, qdd):
        m, d = self._state(k, q, qd, qdd)
        self.mj.mj_inverse(m, d)
        return d.qfrc_inverse[self.dof].copy()

    def _M(self, k, q):
        m, d = self._state(k, q)
        self.mj.mj_forward(m, d)
        full = np.zeros((m.nv, m.nv))
        try:
            self.mj.mj_fullM(m, d, full)  # MuJoCo ≥ 3.4
        except TypeError:
            self.mj.mj_fullM(m, full, d.qM)
        return full[np.ix_(self.dof, self.dof)]

    def _bias(self, k, q, qd):
        m, d = self._state(k, q, qd)
        self.mj.mj_forward(m, d)
        return d.qfrc_bias[self.dof].copy()

    def _forward(self, k, q, qd, tau):
        m, d = self._state(k, q, qd, applied=tau)
        self.mj.mj_forward(m, d)
        return d.qacc[self.dof].copy()

    def _G(self, k, q):
        return self._bias(k, q, np.zeros(len(self.dof)))

    def parts(self, term, *state):
        values = [self._at(term, k, *state) for k in range(len(self.models))]
        return {addition: values[k] - values[k + 1] for k, addition in enumerate(self.ADDITIONS)}

    def bodies(self, q):
        m, d = self._state(0, self.model.S @ np.asarray(q, dtype=float) + self.model.b)
        self.mj.mj_kinematics(m, d)
        lumps: dict[int, list] = {}
        for b, owner in self.body_owner.items():
            if owner >= 0:
                R = d.ximat[b].reshape(3, 3)
                lumps.setdefault(owner, []).append((float(m.body_mass[b]), d.xipos[b].copy(),
                                                    _world_inertia(R, np.diag(m.body_inertia[b]))))
        by_joint = {m.joint(j).name: int(m.jnt_bodyid[j]) for j in range(m.njnt)}
        return {name: _lump(lumps[by_joint[name]]) for name in self.body_joints}


def load_engine(name: str, model, urdf, armature=None) -> Engine:
    """The adapter of engine ``name`` (one of :data:`ENGINES`) for ``model``, loaded from ``urdf``.

    Parameters
    ----------
    name : str
        ``"course_dynamics"``, ``"pinocchio"``, ``"mujoco"`` or ``"pybullet"``.
    model : course_dynamics.Model
        The robot as course_dynamics loaded it from ``urdf``.
    urdf : str or Path
        The URDF file.
    armature : array_like, shape (n,), optional
        Rotor inertias (kg·m², kg) set on the joints of the engines that model them (MuJoCo's ``dof_armature``,
        Pinocchio's ``armature``) after loading, as their users set them: a URDF cannot say them.

    Returns
    -------
    Engine
        The loaded adapter.

    Raises
    ------
    EngineUnavailable
        If the engine's package is not installed.
    EngineRefused
        If the engine would not load the model (its reason is the message).
    """
    if name == "course_dynamics":
        return Engine(model)
    if name == "pinocchio":
        engine = PinocchioEngine(model, urdf)
        if armature is not None:
            engine.oracle.set_armature(armature)
        return engine
    if name == "mujoco":
        return MujocoEngine(model, urdf, armature)
    if name == "pybullet":
        from .engines_pybullet import PybulletEngine

        return PybulletEngine(model, urdf)
    raise ValueError(f"unknown engine {name!r}; engines: {', '.join(ENGINES)}")


__all__ = ["ENGINES", "Engine", "EngineRefused", "EngineUnavailable", "LoadedVariants", "MujocoEngine",
           "PinocchioEngine", "geometry_free", "import_engine", "load_engine"]
