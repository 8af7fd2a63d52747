"""Why engines disagree on one URDF: course_dynamics, Pinocchio, MuJoCo and PyBullet at seeded states.

Each engine (:mod:`course_dynamics_reference.engines`) gives τ, M, G, the bias forces C(Θ, Θ̇)Θ̇ + G and the
forward dynamics Θ̈ at the same seeded states, called as its users call it. Every difference from
course_dynamics is either within the tolerance (relative, as ``validate`` measures it) or explained by one of
the named conventions of :data:`CONVENTIONS`, each shown with its size: the largest absolute amount it
accounts for, per term, over the states (or, for conventions of representation, what it concerns). What no
convention explains is reported as such, with the first body (parents first) whose mass, centre of mass or
inertia the engine placed differently. A convention belongs to the engines known to have it, at the size they
have it (:data:`KNOWN_REFUSALS`, :data:`ROTATING_ENGINES`); Pinocchio is the reference, so when it differs from
course_dynamics unexplained, no other engine's inertia convention explains a difference either. Θ̈ is compared
as the torque M·Θ̈ it stands for, so that an ill-conditioned M does not turn round-off into a difference.

==================  ============================================================
symbol              meaning
==================  ============================================================
Θ, Θ̇, Θ̈             joint positions (rad, m), velocities, accelerations
τ                   joint torques, N·m (N for a prismatic joint)
M, G                mass matrix (kg·m², kg), gravity torques (N·m, N)
bias                C(Θ, Θ̇)Θ̇ + G(Θ), N·m (N)
forward             Θ̈ from τ, rad/s² (m/s²)
==================  ============================================================
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from importlib import metadata
from pathlib import Path

import numpy as np

from course_dynamics.core.model import STANDARD_GRAVITY
from course_dynamics.core.robots import load, resolve
from course_dynamics.core.sampling import random_states, relative_error, term_scales

from . import TOLERANCE
from .engines import ENGINES, MUJOCO_INERTIA_BOUND, Engine, EngineRefused, EngineUnavailable, load_engine

TERMS = ("tau", "M", "G", "bias", "forward")
TERM_TITLES = {"tau": "τ", "M": "M", "G": "G", "bias": "bias", "forward": "forward"}
DEFAULT_GRAVITY = {"pinocchio": STANDARD_GRAVITY, "mujoco": STANDARD_GRAVITY, "pybullet": (0.0, 0.0, 0.0)}
PACKAGES = {"pinocchio": "pin", "mujoco": "mujoco", "pybullet": "pybullet"}

#: The named conventions: what each engine does differently, and how the comparison undoes it.
CONVENTIONS = {
    "fixed joints merged": "course_dynamics and Pinocchio merge a link held by a fixed joint into its parent's "
                           "body; MuJoCo (fusestatic off) and PyBullet keep it as a body, lumped here per body",
    "joint order": "the engine orders the joints its own way; they are matched by name",
    "continuous joints as cos/sin": "Pinocchio gives a continuous joint two configuration entries (cos θ, sin θ)",
    "gravity": "the engine's default gravity is not the model's; it was set (setGravity, opt.gravity, "
               "model.gravity): the size is what the default would have got wrong in G",
    "damping": "mj_inverse adds the URDF's joint damping b·Θ̇ to τ and mj_forward subtracts it (course_dynamics "
               "does with --friction urdf)",
    "frictionloss": "MuJoCo turns the URDF's joint friction into friction-loss constraint forces",
    "armature": "the engine adds rotor inertia to M's diagonal (MuJoCo's dof_armature, Pinocchio's armature)",
    "mimic joints as equality constraints": "MuJoCo's importer couples a <mimic> joint to its leader by an "
                                            "equality constraint, whose force it adds to τ and Θ̈ (none at states "
                                            "that keep the coupling, as those given here do)",
    "mimic joints coupled here": "the engine gives a <mimic> joint a coordinate of its own (PyBullet ignores "
                                 "<mimic>; MuJoCo holds it by the equality constraint): it is given each state at "
                                 "θ = multiplier · θ_leader + offset, its τ, G and bias are mapped onto the leaders by "
                                 "Sᵀ, M by Sᵀ M S, and Θ̈ solves (Sᵀ M S) Θ̈ = τ − Sᵀ bias; course_dynamics and "
                                 "Pinocchio (mimic=True) honour <mimic> themselves",
    "joint limits": "MuJoCo applies joint-limit constraint forces at a state at or beyond a limit",
    "massless links": "PyBullet gives a link without <inertial> 1 kg and unit inertia; here it is given an explicit "
                      "zero one",
    "principal axes approximated": "PyBullet keeps an inertia as principal moments in axes it finds iteratively, "
                                   "to about 1e-9 relative: course_dynamics with PyBullet's inertias agrees, mass, "
                                   "centre of mass and principal moments are the same, and no term differs by more "
                                   "than 1e-6 relative",
    "subnormal numbers": "MuJoCo's URDF reader refuses a number smaller in size than 2.2e-308 (the least normal "
                         "double); such numbers are given to it as 0",
    "inertia refused": "the engine refuses or alters an inertia: MuJoCo raises a massless moving body or a point "
                       "mass's zero rotational inertia to its least value (1e-15), refuses one that breaks the "
                       "triangle inequality, which PyBullet alters",
    "engine limit": "the engine cannot hold the model: PyBullet's getLinkState fails for a body of more than 128 "
                    "links",
    "mimic form refused": "Pinocchio's mimic=True cannot build a mimic joint whose leader comes later in the tree, "
                          "a mimic of a mimic, or a continuous joint coupled to one that is not (configurations of "
                          "different sizes); course_dynamics honours them (Model.mimic_forms names each)",
}
#: What a check with drives says of them: compared (Pinocchio, MuJoCo), not compared (PyBullet, the offsets).
DRIVE_NOTES = {
    "armature": "the drives' rotor inertias are set on the engine and added by course_dynamics: compared as they are",
    "pybullet": "PyBullet has no rotor inertia: compared without the drives",
    "offset": "the drives' torque offsets are no engine's: they are added after the dynamics, and not compared",
}
#: The refusals a convention explains: engine → (a phrase of its message, the convention).
KNOWN_REFUSALS = {
    "mujoco": (("inertia must satisfy A + B >= C", "inertia refused"),
               ("inertia must have positive eigenvalues", "inertia refused"),
               ("mass and inertia of moving bodies must be larger than mjMINVAL", "inertia refused")),
    "pybullet": (("getLinkState serves a body of at most", "engine limit"),),
    "pinocchio": (("cannot build mimic joint", "mimic form refused"),),
}
#: Engines whose inertias may differ from the URDF's in their axes only, and by how much (relative, per term).
ROTATING_ENGINES = {"pybullet": 1e-6}
#: The conventions that rest on an engine's inertias differing from ours: void when Pinocchio differs too.
INERTIA_CONVENTIONS = ("principal axes approximated", "inertia refused")
ADDITION_CONVENTIONS = {"damping": "damping", "frictionloss": "frictionloss", "armature": "armature",
                        "equality": "mimic joints as equality constraints", "limits": "joint limits",
                        "massless links": "massless links"}


@dataclass
class EngineCheck:
    """One engine against course_dynamics: its status, its worst relative residual per term, its conventions."""

    engine: str
    status: str  # "compared", "skipped" (cannot be imported) or "refused"
    version: str = ""
    reason: str = ""
    calls: dict[str, str] = field(default_factory=dict)
    raw: dict[str, float] = field(default_factory=dict)       # before any convention is undone
    residual: dict[str, float] = field(default_factory=dict)  # after
    conventions: list[dict] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    first_link: str | None = None   # the URDF link of the first body the engine places differently
    first_joint: str | None = None  # the joint that carries it
    explained: bool = True

    def as_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass
class CrossCheck:
    """The whole comparison of one URDF."""

    robot: str
    urdf: str
    joints: list[str]
    samples: int
    seed: int
    tolerance: float
    engines: list[EngineCheck]

    @property
    def compared(self) -> bool:
        """At least one engine was compared (not every one skipped or refused)."""
        return any(e.status == "compared" for e in self.engines)

    @property
    def ok(self) -> bool:
        """Some engine was compared, and every engine agrees or differs by named conventions only (a missing
        engine is a note)."""
        return self.compared and all(e.explained for e in self.engines)

    def as_dict(self) -> dict:
        return {"robot": self.robot, "urdf": Path(self.urdf).name, "joints": self.joints, "samples": self.samples,
                "seed": self.seed, "tolerance": self.tolerance, "ok": self.ok,
                "conventions": CONVENTIONS, "engines": [e.as_dict() for e in self.engines]}


def _version(engine: str) -> str:
    if engine == "course_dynamics":
        engine = "course-dynamics"
    try:
        return metadata.version(engine)
    except metadata.PackageNotFoundError:
        return "unknown"


def _states(model, samples, seed):
    q, qd, qdd = random_states(model, samples, seed)
    return list(zip(q, qd, qdd))


def _arguments(term, q, qd, qdd, tau):
    return {"tau": (q, qd, qdd), "M": (q,), "G": (q,), "bias": (q, qd), "forward": (q, qd, tau)}[term]


def _scales(ours: Engine, q, qd, qdd) -> dict[str, float]:
    M, G = ours.M(q), ours.G(q)
    s = term_scales(M, G, qd, qdd, ours.model.gravity)
    return {"tau": s["tau"], "M": s["M"], "G": s["G"], "bias": s["V"] + s["G"], "forward": float(np.abs(qdd).max())}


def _evaluate(engine: Engine, ours: Engine, states, reference=None) -> tuple[dict, dict, dict]:
    """Worst raw and residual relative errors per term, and each addition's largest absolute part per term."""
    raw = {t: 0.0 for t in TERMS}
    residual = {t: 0.0 for t in TERMS}
    parts: dict[str, dict[str, float]] = {}
    reference = reference or ours
    for q, qd, qdd in states:
        tau = ours.tau(q, qd, qdd)
        scales = _scales(ours, q, qd, qdd)
        M = ours.M(q)
        for term in TERMS:
            arguments = _arguments(term, q, qd, qdd, tau)
            expected = getattr(reference, term)(*arguments)
            value = getattr(engine, term)(*arguments)
            added = {k: v for k, v in engine.parts(term, *arguments).items() if k not in ours.included}
            plain = value - sum(added.values()) if added else value
            # Θ̈ is compared as the torque M·Θ̈ it stands for: an ill-conditioned M turns a round-off in τ into a
            # large ΔΘ̈ along its softest direction, which M·ΔΘ̈ weighs back to the round-off it is.
            weigh = (lambda x: M @ x) if term == "forward" else (lambda x: x)
            scale = scales["tau"] if term == "forward" else scales[term]
            raw[term] = max(raw[term], relative_error(weigh(value), weigh(expected), scale))
            residual[term] = max(residual[term], relative_error(weigh(plain), weigh(expected), scale))
            for name, part in added.items():
                sizes = parts.setdefault(name, {t: 0.0 for t in TERMS})
                sizes[term] = max(sizes[term], float(np.abs(part).max(initial=0.0)))
    return raw, residual, parts


def _nonphysical(urdf) -> set[str]:
    """Joints whose body holds a URDF link (its own inertia, before any lumping) that is not positive
    semi-definite or breaks the triangle inequality, as strictly as MuJoCo and PyBullet test it."""
    from course_dynamics.core.urdf import read_description

    robot = read_description(urdf)
    parent_joint = {j.child: j for j in robot.joints}
    out = set()
    for link in robot.links:
        if link.inertial is None or link.inertial.inertia is None:
            continue
        moments = np.sort(np.linalg.eigvalsh(np.asarray(link.inertial.inertia, dtype=float)))
        slack = 1e-12 * max(moments[-1], 1e-300)
        if moments[0] >= -slack and moments[2] <= moments[0] + moments[1] + slack:
            continue
        name = link.name
        while name in parent_joint and parent_joint[name].type == "fixed":  # its body's joint
            name = parent_joint[name].parent
        if name in parent_joint:
            out.add(parent_joint[name].name)
    return out


def with_inertias_of(engine: Engine, model, q):
    """``model`` with each body's m, ⁱP_C and ᶜⁱI as ``engine`` placed them at ``q`` (in our body frames).

    Parameters
    ----------
    engine : Engine
        The engine whose imported inertias are taken.
    model : course_dynamics.Model
        The robot as course_dynamics loaded it.
    q : array_like, shape (n,)
        The joint positions the engine's bodies are read at, rad (m).

    Returns
    -------
    course_dynamics.Model
        The same joints and frames, the engine's inertias.
    """
    from course_dynamics import forward_kinematics

    placed, theirs = forward_kinematics(model, q), engine.bodies(q)
    bodies = []
    for i, body in enumerate(model.bodies):
        mass, com, inertia = theirs[body.joint]
        R = placed.R[i]
        bodies.append(replace(body, mass=mass, p_com=R.T @ (com - placed.P[i]), I_com=R.T @ inertia @ R))
    return replace(model, bodies=tuple(bodies))


def first_parting(engine: Engine, ours: Engine, q, tolerance: float, joints=None) -> str | None:
    """The joint of the first body (parents first) whose m, m·⁰P_C or ⁰I_C the engine places differently.

    Parameters
    ----------
    engine, ours : Engine
        The engine compared and course_dynamics.
    q : array_like, shape (n,)
        Joint positions, rad (m).
    tolerance : float
        Relative, against the largest mass, first moment m·⁰P_C and inertia of all bodies.
    joints : sequence of str, optional
        The bodies (by joint) looked at; default all.

    Returns
    -------
    str or None
        The joint carrying the body, or None when every body agrees.
    """
    def moments(bodies):  # m, m·⁰P_C (a massless body's centre is anywhere) and ⁰I_C
        return {j: (m, m * c, I) for j, (m, c, I) in bodies.items()}

    theirs, mine = moments(engine.bodies(q)), moments(ours.bodies(q))
    scale = [max(float(np.abs(mine[j][k]).max()) for j in mine) for k in range(3)]
    for joint in [b.joint for b in ours.model.bodies] if joints is None else joints:
        for k in range(3):
            if relative_error(theirs[joint][k], mine[joint][k], scale[k]) > tolerance:
                return joint
    return None


ROTATION_TOLERANCE = 1e-6  # relative: principal moments an engine found iteratively (PyBullet) are this close


def _rotated(engine: Engine, ours: Engine, q, joint: str, tolerance: float) -> bool:
    """The engine's body of ``joint`` has our mass, centre of mass and principal moments: only its axes differ."""
    (m, c, I), (m0, c0, I0) = engine.bodies(q)[joint], ours.bodies(q)[joint]
    scale = max(float(np.abs(I0).max()), np.finfo(float).tiny)
    moments = np.linalg.eigvalsh(I) - np.linalg.eigvalsh(I0)
    return (relative_error(m, m0) <= tolerance and relative_error(m * c, m0 * c0, m0) <= tolerance
            and float(np.abs(moments).max()) <= ROTATION_TOLERANCE * scale)


def _fixed_joints(model) -> int:
    return max(0, len(model.frames) - 1 - model.n_bodies)


def _representation(engine: Engine, model, states) -> list[dict]:
    """The conventions of representation that apply to this engine and robot (sizes as counts or orders)."""
    out = []
    if engine.name in ("mujoco", "pybullet") and _fixed_joints(model):
        out.append({"name": "fixed joints merged", "size": f"{_fixed_joints(model)} links held by fixed joints"})
    if engine.joint_order != [b.joint for b in model.bodies]:
        out.append({"name": "joint order", "size": "its order: " + ", ".join(engine.joint_order)})
    if engine.name in ("mujoco", "pybullet") and model.has_mimic:
        coupled = [f"{b.joint} = {a:g}·{model.joint_names[j]} {'-' if c < 0 else '+'} {abs(c):g}"
                   for b, (j, a, c) in zip(model.bodies, model.coupling) if b.mimic]
        out.append({"name": "mimic joints coupled here", "size": ", ".join(coupled)})
    continuous = getattr(engine, "continuous", [])
    if continuous:
        out.append({"name": "continuous joints as cos/sin", "size": ", ".join(continuous)})
    default = np.asarray(DEFAULT_GRAVITY.get(engine.name, model.gravity), dtype=float)
    if not np.array_equal(default, model.gravity):
        ours = Engine(model)
        otherwise = Engine(replace(model, gravity=default))
        size = max(float(np.abs(ours.G(q) - otherwise.G(q)).max(initial=0.0)) for q, _, _ in states)
        out.append({"name": "gravity", "size": {"G": size}, "detail": f"default {default.tolist()} m/s^2"})
    return out


def check_engine(name: str, model, urdf, states, tolerance: float, armature=None, drives=None) -> EngineCheck:
    """One engine against course_dynamics on ``states``; see :func:`crosscheck`.

    Parameters
    ----------
    name : str
        One of :data:`~course_dynamics_reference.engines.ENGINES` other than course_dynamics.
    model : course_dynamics.Model
        The robot as course_dynamics loaded it.
    urdf : Path
        Its URDF.
    states : list of tuple of numpy.ndarray
        (Θ, Θ̇, Θ̈), each (n,).
    tolerance : float
        Relative.
    armature : array_like, shape (n,), optional
        Rotor inertias set on the engines that model them, kg·m² (kg).
    drives : course_dynamics.core.drives.Drives, optional
        Drives course_dynamics adds itself: their armature is set on the engines that model them and compared
        with ours (no convention); an engine without rotor inertia (PyBullet) is compared without them.

    Returns
    -------
    EngineCheck
        Its status, raw and residual errors, conventions, notes and, when unexplained, the first body that parts.
    """
    version = _version(PACKAGES.get(name, name))
    rotors = None if drives is None or name == "pybullet" else drives.armature
    try:
        engine = load_engine(name, model, urdf, armature if rotors is None else rotors)
    except EngineUnavailable as exc:
        return EngineCheck(name, "skipped", reason=str(exc), notes=[f"{name} skipped: {exc}"])
    except EngineRefused as exc:
        reason = str(exc)
        known = [c for phrase, c in KNOWN_REFUSALS.get(name, ()) if phrase in reason][:1]
        return EngineCheck(name, "refused", version=version, reason=reason, explained=bool(known),
                           conventions=[{"name": c, "size": reason} for c in known])
    try:
        check = _compared(engine, model, urdf, version, states, tolerance, rotors)
        if drives is not None:
            check.notes += [DRIVE_NOTES["pybullet" if rotors is None else "armature"]]
            check.notes += [DRIVE_NOTES["offset"]] if drives.offset.any() else []
        return check
    except EngineRefused as exc:  # an engine's call failed part way (one of its limits)
        return EngineCheck(name, "refused", version=version, reason=str(exc), explained=False)
    finally:
        engine.close()


def _compared(engine: Engine, model, urdf, version: str, states, tolerance: float, rotors=None) -> EngineCheck:
    """The check of a loaded engine: residuals, conventions and, for what they leave, the first body that parts."""
    name, ours = engine.name, Engine(model, rotors)
    raw, residual, parts = _evaluate(engine, ours, states)
    check = EngineCheck(name, "compared", version=version, calls=dict(engine.call), raw=raw, residual=residual,
                        notes=list(engine.notes))
    check.conventions = _representation(engine, model, states)
    check.conventions += [{"name": ADDITION_CONVENTIONS[k], "size": sizes} for k, sizes in parts.items()
                          if any(sizes.values())]
    if getattr(engine, "subnormal", None):
        check.conventions.append({"name": "subnormal numbers", "size": engine.subnormal})
    if getattr(engine, "bounded", None):
        check.conventions.append({"name": "inertia refused",
                                  "size": f"{engine.bounded}; loaded with boundmass={MUJOCO_INERTIA_BOUND:g} kg and "
                                          f"boundinertia={MUJOCO_INERTIA_BOUND:g} kg·m²: each such body gains at "
                                          f"most {MUJOCO_INERTIA_BOUND:g} kg and {MUJOCO_INERTIA_BOUND:g} kg·m²"})
    if all(v <= tolerance for v in residual.values()):
        return check
    check.first_joint = first_parting(engine, ours, states[0][0], tolerance)
    if check.first_joint is None:
        check.explained = False
        return check
    check.first_link = next(b.name for b in model.bodies if b.joint == check.first_joint)
    as_placed = Engine(with_inertias_of(engine, model, states[0][0]))
    _, against_placed, _ = _evaluate(engine, ours, states, reference=as_placed)
    if all(v <= tolerance for v in against_placed.values()):  # the engine's inertias are the whole difference
        differing = [b.joint for b in model.bodies if first_parting(engine, ours, states[0][0], tolerance, [b.joint])]
        if engine.name in ("mujoco", "pybullet") and set(differing) <= _nonphysical(urdf):
            name = "inertia refused"
        elif (max(residual.values()) <= ROTATING_ENGINES.get(engine.name, 0.0)
              and all(_rotated(engine, ours, states[0][0], j, tolerance) for j in differing)):
            name = "principal axes approximated"
        else:
            check.explained = False
            return check
        sizes = {t: 0.0 for t in TERMS}
        for q, qd, qdd in states:
            tau = ours.tau(q, qd, qdd)
            for t in TERMS:
                difference = getattr(ours, t)(*_arguments(t, q, qd, qdd, tau)) - getattr(as_placed, t)(
                    *_arguments(t, q, qd, qdd, tau))
                sizes[t] = max(sizes[t], float(np.abs(difference).max()))
        links = [b.name for b in model.bodies if b.joint in differing]
        check.conventions.append({"name": name, "size": sizes, "detail": "the inertia of " + ", ".join(links)})
        check.residual, check.first_link, check.first_joint = against_placed, None, None
        return check
    check.explained = False
    return check


def _against_the_reference(checks: list[EngineCheck]) -> None:
    """When Pinocchio, the reference, differs from course_dynamics unexplained, another engine's difference is no
    inertia convention of its own: engines agreeing with each other and not with us point at us."""
    reference = next((e for e in checks if e.engine == "pinocchio" and e.status == "compared"), None)
    if reference is None or reference.explained:
        return
    for e in checks:
        voided = [c for c in e.conventions if c["name"] in INERTIA_CONVENTIONS and isinstance(c["size"], dict)]
        if e is not reference and voided:
            e.conventions = [c for c in e.conventions if c not in voided]
            e.explained = False
            e.notes.append("Pinocchio, the reference, differs from course_dynamics too: "
                           + ", ".join(c["name"] for c in voided) + " does not explain it")


def crosscheck(name_or_path: str, samples: int = 3, seed: int = 0, tolerance: float = TOLERANCE,
               engines=ENGINES[1:], gravity=None, allow_nonphysical_inertia: bool = False,
               armature=None, drives=None) -> CrossCheck:
    """The same URDF through course_dynamics and each engine at seeded random states.

    Parameters
    ----------
    name_or_path : str
        A URDF file or a shipped robot's name.
    samples : int, optional
        Seeded random states (within the joint limits), default 3.
    seed : int, optional
        The states' seed.
    tolerance : float, optional
        Relative, per term, as ``validate`` measures it.
    engines : sequence of str, optional
        Which of Pinocchio, MuJoCo and PyBullet (default all three).
    gravity : array_like, shape (3,), optional
        m/s² in the base frame, set on every engine (default the model's).
    allow_nonphysical_inertia : bool, optional
        Load a link whose inertia breaks the triangle inequality (with a warning).
    armature : array_like, shape (n,), optional
        Rotor inertias, kg·m² (kg), set on MuJoCo and Pinocchio after loading (a URDF cannot say them).
    drives : course_dynamics.core.drives.Drives, optional
        A drives file's: its armature set on MuJoCo and Pinocchio and added by course_dynamics too, so that the
        engines check our drives (:func:`check_engine`); instead of ``armature``.

    Returns
    -------
    CrossCheck
        Every engine's result; ``ok`` when each difference is within ``tolerance`` or a named convention.

    Raises
    ------
    InputError
        If course_dynamics cannot read the URDF (as every command reports it).
    """
    urdf = resolve(name_or_path)
    options = dict(allow_nonphysical_inertia=allow_nonphysical_inertia,
                   **({} if gravity is None else {"gravity": gravity}))
    model = load(urdf, **options)
    states = _states(model, samples, seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the variants a convention is checked against warn as the model did
        checks = [check_engine(name, model, Path(urdf), states, tolerance, armature, drives) for name in engines]
    _against_the_reference(checks)
    return CrossCheck(model.name, str(urdf), list(model.joint_names), samples, seed, tolerance, checks)


__all__ = ["CONVENTIONS", "CrossCheck", "EngineCheck", "KNOWN_REFUSALS", "ROTATING_ENGINES", "TERMS", "check_engine",
           "crosscheck", "first_parting"]
