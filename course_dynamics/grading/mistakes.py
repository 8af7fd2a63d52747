"""The mistakes students make, each made on purpose by our own code, so that a wrong answer can be named.

Every mistake has a stable code (shown in brackets in the feedback, counted in
the class summary), its words and its advice in Craig's terms (:data:`MISTAKES`).
:func:`mistaken_terms` computes our τ, M, V and G made with each mistake, at the
grading states, in every variant a student makes it:

=============================  ==============================================================
made by                        mistakes
=============================  ==============================================================
the recursion with one slip    ``gravity-missing``, ``gravity-sign``, ``rotation-transposed``,
                               ``rotation-identity``, ``cross-reversed``, ``centripetal-missing``,
                               ``gyroscopic-missing``, ``inertia-about-origin``,
                               ``moment-arm-missing``, ``first-moment-missing``, ``gravity-frame``,
                               ``com-wrong-link``, ``tau-wrong-moment``, and the lecture notes'
                               misprints copied into code, ``notes-6.48``, ``notes-6.50``,
                               ``notes-6.51``, ``notes-6.52``; each wherever the
                               expression appears, in one iteration, or in one equation alone,
                               the printed ones on one link alone too
                               (a :class:`~course_dynamics.grading.slips.Slip` of
                               :func:`~course_dynamics.grading.slips.slips`); a slip whose
                               answers on this robot are the right ones, or those of a simpler
                               mistake (listed earlier), is dropped: on the two-link arm
                               gravity added unrotated is gravity left out
the (6.63) form                ``notes-6.65``: V = B[Θ̇Θ̇] + C[Θ̇²] with the notes' misprinted
                               [Θ̇²] = [θ̇₁² θ̇₁² …] (robots of 2 to :data:`CLOSED_FORM_JOINTS` joints)
closed form, one substitution  ``sin-cos-swapped`` (every sin read as cos and back),
                               ``c1-c12-swapped`` (cos θᵢ exchanged with the cosine of a sum such as
                               cos(θ₁ + θ₂)): for robots of up to :data:`CLOSED_FORM_JOINTS` joints,
                               whose closed forms students derive by hand
the inputs                     ``degrees``: the angles read as, or turned into, degrees
=============================  ==============================================================

Three more codes name findings of :mod:`~course_dynamics.grading.diagnosis`
that need no answer of ours: ``coriolis-half`` (every Coriolis coefficient
halved, seen in V's (6.63) coefficients), ``joints-swapped`` and, for G,
``gravity-sign`` as the opposite sign.

>>> sorted(MISTAKES)[:3]
['c1-c12-swapped', 'centripetal-missing', 'com-wrong-link']
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass, replace

import numpy as np

from ..core.joints import kind_of
from ..core.lagrange import configuration_space_terms, velocity_pairs
from ..core.model import Model
from ..core.newton_euler import newton_euler_links
from ..core.operations import EXACT, Operations
from ..core.sampling import relative_error
from ..core.symbolic import derive, numeric_functions
from .records import Answer, Finding
from .slips import slips

#: The most joints a robot may have for the closed-form mistakes to be made (their closed forms are derived).
CLOSED_FORM_JOINTS = 2  # closed forms are derived (about 0.7 s) for robots this small, as students derive them


@dataclass(frozen=True)
class Mistake:
    """A mistake's words (what was done) and advice (what is right, with the equation).

    Parameters
    ----------
    words : str
        What was done, as the feedback says it.
    advice : str
        What is right, with the equation.
    """

    words: str
    advice: str


#: Every mistake's code and its :class:`Mistake` (words and advice), as the feedback shows them.
MISTAKES = {
    "gravity-missing": Mistake(
        "gravity left out (is ⁰v̇₀ = −g?)",
        "Gravity enters Craig's recursion once, as the base's upward acceleration ⁰v̇₀ = −g, and (6.47) carries it "
        "into every frame; with ⁰v̇₀ = 0 and no gravity anywhere else the arm weighs nothing and G(Θ) = 0"),
    "rotation-identity": Mistake(
        "a rotation left out (read as the identity)",
        "A vector of frame i reaches frame i+1 only through ⁱ⁺¹ᵢR ((6.45)–(6.47)) and comes back through ⁱᵢ₊₁R "
        "((6.51), (6.52)); the notes' ⁱ⁺¹R^{i+1} in (6.52) and the worked example's ²R² in ²v̇₂ = ²R² ¹v̇_C₁ read "
        "as ²₂R = 1 leave it out: ²v̇₂ = ²₁R ¹v̇_C₁ (reference/errata.md)"),
    "first-moment-missing": Mistake(
        "the moment ⁱP_Cᵢ × ⁱFᵢ left out (every centre of mass at its frame origin)",
        "The inertial force ⁱFᵢ acts at the centre of mass, so (6.52) adds its moment about frame i's origin, "
        "ⁱP_Cᵢ × ⁱFᵢ; the notes' ⁱPᵢ × ⁱFᵢ, read with ⁱPᵢ = 0, leaves it out too (reference/errata.md)"),
    "rotation-transposed": Mistake(
        "the rotation used the wrong way round",
        "The outward iteration (6.45)–(6.47) carries vectors from frame i into frame i+1 with ⁱ⁺¹ᵢR, the transpose "
        "of the orientation ⁱᵢ₊₁R of frame i+1 that the link's transform gives; the inward iteration (6.51)–(6.52) "
        "carries them back with ⁱᵢ₊₁R"),
    "cross-reversed": Mistake(
        "a cross product in the wrong order",
        "Since a × b = −b × a, the order matters: ⁱ⁺¹ᵢR ⁱωᵢ × θ̇ᵢ₊₁Ẑ in (6.46), ω̇ × P + ω × (ω × P) in (6.47) "
        "and (6.48), ω × ᶜI ω in (6.50), and ⁱP_Cᵢ × ⁱFᵢ + ⁱPᵢ₊₁ × ⁱfᵢ₊₁ in (6.52)"),
    "centripetal-missing": Mistake(
        "the centripetal term ω × (ω × P) left out",
        "A point fixed in a turning link accelerates toward the axis even at constant ω, so (6.47) and (6.48) both "
        "carry ω × (ω × P), as (6.12) does"),
    "gyroscopic-missing": Mistake(
        "the gyroscopic term ω × ᶜI ω left out",
        "Euler's equation (6.50) is ⁱNᵢ = ᶜⁱIᵢ ⁱω̇ᵢ + ⁱωᵢ × ᶜⁱIᵢ ⁱωᵢ, whose second term vanishes only when ω lies "
        "along a principal axis of the link"),
    "inertia-about-origin": Mistake(
        "the inertia tensor taken about the frame origin instead of the centre of mass",
        "Euler's equation (6.50) uses ᶜⁱIᵢ, the tensor about the centre of mass, because the moment of ⁱFᵢ about "
        "the origin is added separately, as ⁱP_Cᵢ × ⁱFᵢ in (6.52)"),
    "moment-arm-missing": Mistake(
        "the moment arm of the child's force left out",
        "The force that link i+1 exerts at the origin of frame i+1 has a moment about the origin of frame i, the "
        "term ⁱPᵢ₊₁ × ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁ of (6.52)"),
    "gravity-sign": Mistake(
        "gravity with the wrong sign",
        "In Craig's recursion the base accelerates upward, ⁰v̇₀ = −g, so that G(Θ) holds the arm up against gravity "
        "(the notes' pendulum equation m l² ω̇ − m g l sin θ = 0 has this sign slip: it is m l² θ̈ + m g l sin θ)"),
    "gravity-frame": Mistake(
        "gravity added link by link in the wrong frame",
        "⁰g is a vector of the base frame: in frame i it is ⁱ₀R ⁰g with ⁱ₀R = ⁰ᵢRᵀ, the transpose of frame i's "
        "orientation ⁰ᵢR. Craig avoids the rotation altogether: gravity enters once, as the base's upward "
        "acceleration ⁰v̇₀ = −g, and (6.47) carries it into every frame"),
    "com-wrong-link": Mistake(
        "another link's centre of mass",
        "Each link's (6.48) and (6.52) use its own centre of mass ⁱP_Cᵢ, in its own frame i: check the index of "
        "Pc, since Python's Pc[i - 1] is link i−1's (and Pc[-1], for link 1, the last link's)"),
    "tau-wrong-moment": Mistake(
        "τ read from the wrong moment",
        "τᵢ = ⁱnᵢᵀ ⁱẐᵢ (6.53): the moment ⁱnᵢ that link i−1 exerts on link i, which (6.52) gives after adding the "
        "children's moments, not the inertial moment ⁱNᵢ of (6.50) (the notes' words at (6.43) say so, the "
        "equation does not), and not the child's ⁱ⁺¹nᵢ₊₁"),
    "notes-6.48": Mistake(
        "(6.48) as the lecture notes misprint it",
        "The notes print (6.48) with ω̇ᵢ and ⁱ⁺¹Pᵢ₊₁; the centre of mass of link i+1 accelerates with link i+1's own "
        "angular acceleration about its own centre of mass: ⁱ⁺¹v̇_Cᵢ₊₁ = ⁱ⁺¹ω̇ᵢ₊₁ × ⁱ⁺¹P_Cᵢ₊₁ + ⁱ⁺¹ωᵢ₊₁ × "
        "(ⁱ⁺¹ωᵢ₊₁ × ⁱ⁺¹P_Cᵢ₊₁) + ⁱ⁺¹v̇ᵢ₊₁ (reference/errata.md). The worked example's ¹F₁ = m₁ ¹v̇₁ and its "
        "²v̇_C₂ with ¹ω̇₁ are the same misprint"),
    "notes-6.50": Mistake(
        "(6.50) as the lecture notes misprint it",
        "The notes print the gyroscopic term of (6.50) with ⁱ⁺¹Iᵢ₊₁, the tensor about the frame origin; both terms "
        "use ᶜⁱIᵢ about the centre of mass: ⁱNᵢ = ᶜⁱIᵢ ⁱω̇ᵢ + ⁱωᵢ × ᶜⁱIᵢ ⁱωᵢ (reference/errata.md; the worked "
        "example's ¹N₁ has the same slip)"),
    "notes-6.51": Mistake(
        "(6.51) as the lecture notes misprint it",
        "The notes print (6.51) with a stray inertia tensor ⁱIᵢ₊₁ (link i+1's, I[i + 1] in code) before the "
        "rotation; a force is only rotated: ⁱfᵢ = ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁ + ⁱFᵢ, as (6.41) (reference/errata.md)"),
    "notes-6.52": Mistake(
        "(6.52) as the lecture notes misprint it",
        "The notes print (6.52) with the child's Nᵢ₊₁, ⁱPᵢ × ⁱFᵢ and the identity ⁱ⁺¹R^{i+1}; it is link i's own "
        "ⁱNᵢ, the lever ⁱP_Cᵢ of its centre of mass and the rotation ⁱᵢ₊₁R: ⁱnᵢ = ⁱNᵢ + ⁱᵢ₊₁R ⁱ⁺¹nᵢ₊₁ + "
        "ⁱP_Cᵢ × ⁱFᵢ + ⁱPᵢ₊₁ × ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁, as (6.42) (reference/errata.md)"),
    "notes-6.65": Mistake(
        "(6.65) as the lecture notes misprint it",
        "The notes print [Θ̇²] = [θ̇₁² θ̇₁² … θ̇ₙ²]; it is the vector of every joint's squared rate, [θ̇₁² θ̇₂² … "
        "θ̇ₙ²]ᵀ, so that C(Θ)[Θ̇²] in (6.63) multiplies column j of C by θ̇ⱼ² (reference/errata.md)"),
    "coriolis-half": Mistake(
        "half the Coriolis coefficient",
        "The sum Σⱼₖ Γᵢⱼₖ θ̇ⱼθ̇ₖ holds each product θ̇ⱼθ̇ₖ (j ≠ k) twice, so Craig's B is 2Γᵢⱼₖ (6.63), as in the "
        "two-link arm's −2m₂l₁l₂s₂θ̇₁θ̇₂ (6.61)"),
    "sin-cos-swapped": Mistake(
        "sin and cos exchanged (or gravity along the wrong axis)",
        "Check each sᵢ and cᵢ against the geometry: at θ = 0 a link along X₀ has its largest gravity moment "
        "(cos θ) and no change of height (sin θ)"),
    "c1-c12-swapped": Mistake(
        "the cosine of one angle exchanged with the cosine of a sum",
        "c₁ belongs to link 1's direction θ₁ and c₁₂ = cos(θ₁ + θ₂) to link 2's, so write down the angle each link "
        "makes with X₀ before reading off its moment arm"),
    "degrees": Mistake(
        "the angles in degrees",
        "Every input is in radians, and numpy's trigonometry takes radians, so no np.deg2rad or np.rad2deg"),
    "joints-swapped": Mistake(
        "the joints in the wrong order",
        "Entries follow the joint order that `course-dynamics info` prints"),
}


def _unit(j: int, shape) -> np.ndarray:
    e = np.zeros(shape)
    e[..., j] = 1.0
    return e


def _terms_by_recursion(model: Model, q, qd, qdd, ops: Operations) -> dict[str, np.ndarray]:
    """τ, G, V and M of the recursion run with the operations ``ops``, by differences as the library derives them."""
    def tau(qd_, qdd_):
        return np.asarray(newton_euler_links(model, q, qd_, qdd_, ops).tau, dtype=float) @ model.S   # τ = Sᵀ τ_bodies

    zero = np.zeros_like(q)
    G = tau(zero, zero)
    M = np.stack([tau(zero, _unit(j, q.shape)) - G for j in range(model.n)], axis=-1)
    return {"tau": tau(qd, qdd), "G": G, "V": tau(qd, zero) - G, "M": M}


def _fingerprint(model: Model) -> str:
    numbers = [model.joint_names] + [(b.joint_type, b.parent, b.R0.tobytes(), b.P.tobytes(), b.axis.tobytes(),
                                      float(b.mass), b.p_com.tobytes(), b.I_com.tobytes()) for b in model.bodies]
    return hashlib.sha256(repr((numbers, model.gravity.tobytes())).encode()).hexdigest()


_DERIVED: dict[str, object] = {}


def _derivation(model: Model):
    """The model's closed forms, derived once per model in this process."""
    key = _fingerprint(model)
    if key not in _DERIVED:
        _DERIVED[key] = derive(model)
    return _DERIVED[key]


def _substitutions(derivation) -> dict[tuple[str, str], dict]:
    """The closed-form slips: (code, variant) → a simultaneous substitution of trigonometric functions."""
    import sympy  # heavy: only for the small robots whose closed forms are derived

    expressions = [*derivation.tau, *derivation.G]
    found = set().union(*(sympy.sympify(e).atoms(sympy.cos, sympy.sin) for e in expressions))
    arguments = sorted({f.args[0] for f in found}, key=sympy.default_sort_key)
    made = {("sin-cos-swapped", ""): {f: (sympy.cos if f.func is sympy.sin else sympy.sin)(f.args[0]) for f in found}}
    angles = [a for a in arguments if a.is_Symbol]
    for a in angles:
        for b in arguments:
            if not b.is_Symbol and a in b.free_symbols and sympy.cos(a) in found and sympy.cos(b) in found:
                names = f"(cos({a}) and cos({b}) exchanged)".replace("q_", "")
                made["c1-c12-swapped", names] = {sympy.cos(a): sympy.cos(b),
                                                                            sympy.cos(b): sympy.cos(a)}
    return made


def _terms_by_closed_form(model: Model, q, qd, qdd) -> dict[tuple[str, str], dict[str, np.ndarray]]:
    derivation = _derivation(model)
    made = {}
    for key, substitution in _substitutions(derivation).items():
        def swap(e, substitution=substitution):
            return e.xreplace(substitution) if hasattr(e, "xreplace") else e

        slipped = replace(derivation, G=[swap(e) for e in derivation.G], V=[swap(e) for e in derivation.V],
                          M=[[swap(e) for e in row] for row in derivation.M])
        functions = numeric_functions(slipped)
        M, V, G = functions["M"](q), functions["V"](q, qd), functions["G"](q)
        # τ = M Θ̈ + V + G (6.59) from the slipped parts, as a student assembles it from the closed forms they wrote
        made[key] = {"tau": np.einsum("...ij,...j->...i", M, qdd) + V + G, "G": G, "V": V, "M": M}
    return made


def mistaken_terms(model: Model, q, qd, qdd) -> dict[str, dict[tuple[str, str], np.ndarray]]:
    """Per term (τ, M, V, G), (code, variant) → our answers made with that mistake at the states (N, n) given.

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("pendulum")
    >>> made = mistaken_terms(arm, np.array([[0.5]]), np.array([[1.0]]), np.array([[0.0]]))
    >>> made["G"]["gravity-sign", "in the base acceleration ⁰v̇₀"].round(4).tolist()   # −m g l sin θ
    [[-4.7032]]

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (N, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : array_like, shape (N, n)
        Joint velocities Θ̇, rad/s (m/s).
    qdd : array_like, shape (N, n)
        Joint accelerations Θ̈, rad/s² (m/s²).

    Returns
    -------
    dict
        Per term (``tau``, ``M``, ``V``, ``G``), a dict of (code, variant) to that term made with that mistake at
        the states: shape (N, n), or (N, n, n) for M.
    """
    q, qd, qdd = (np.asarray(a, dtype=float) for a in (q, qd, qdd))
    made: dict[str, dict[tuple[str, str], np.ndarray]] = {t: {} for t in ("tau", "M", "V", "G")}
    kept = [(("", ""), _terms_by_recursion(model, q, qd, qdd, EXACT))]
    for slip in slips(model.n_bodies):
        terms = _terms_by_recursion(model, q, qd, qdd, slip)
        if any(key[0] != slip.code or key[1] == slip.variant for key, other in kept if _same(terms, other)):
            continue  # the right answer, a simpler mistake's (listed earlier) or this one made in more places
        kept.append(((slip.code, slip.variant), terms))  # the same slip's other ways that agree are named together
        for term, value in terms.items():
            made[term][slip.code, "in " + slip.where] = value
    revolute = np.array([kind_of(b).rotates for b in model.coordinate_bodies])   # per coordinate Θ[j]
    for variant, factor in (("read as degrees", np.pi / 180), ("turned into degrees", 180 / np.pi)):
        scale = np.where(revolute, factor, 1.0)
        for rates, (q_, qd_, qdd_) in (("positions", (q * scale, qd, qdd)),
                                       ("positions, velocities and accelerations",
                                        (q * scale, qd * scale, qdd * scale))):
            for term, value in _terms_by_recursion(model, q_, qd_, qdd_, EXACT).items():
                made[term]["degrees", f"({rates} {variant})"] = value
    if model.n <= CLOSED_FORM_JOINTS and revolute.any():
        for key, terms in _terms_by_closed_form(model, q, qd, qdd).items():
            for term, value in terms.items():
                made[term][key] = value
    if 1 < model.n <= CLOSED_FORM_JOINTS:
        right = _terms_by_recursion(model, q, qd, qdd, EXACT)
        V = _printed_6_65(model, q, qd)
        made["V"]["notes-6.65", "(every centrifugal coefficient times θ̇₁²)"] = V
        made["tau"]["notes-6.65", "(every centrifugal coefficient times θ̇₁²)"] = right["tau"] - right["V"] + V
    return made


SAME = 1e-12  # two slips whose every term agrees to this, relative to the term's largest entry, are one on the robot


def _same(terms: dict[str, np.ndarray], other: dict[str, np.ndarray]) -> bool:
    return all(np.allclose(terms[t], other[t], rtol=0, atol=SAME * max(float(np.abs(other[t]).max(initial=0)), 1e-300))
               for t in terms)


def _printed_6_65(model: Model, q, qd) -> np.ndarray:
    """V = B(Θ)[Θ̇Θ̇] + C(Θ)[Θ̇²] (6.63) with [Θ̇²] = [θ̇₁² θ̇₁² … θ̇ₙ²] as the notes print (6.65): the second
    entry θ̇₁² where θ̇₂² belongs, every other entry right (the notes' row ends in θ̇ₙ²)."""
    B, C = configuration_space_terms(model, q)
    products = np.stack([qd[..., j] * qd[..., k] for j, k in velocity_pairs(model.n)], axis=-1)
    squares = qd**2
    squares[..., 1] = qd[..., 0] ** 2
    return np.einsum("...ij,...j->...i", B, products) + np.einsum("...ij,...j->...i", C, squares)


# ---------------------------------------------------------------------------------------- the checks that name them
def matching_mistakes(answer: Answer) -> dict[str, list[str]]:
    """The mistakes whose answers agree with the student's: code → the variants that do, the commonest code first.
    A mistake whose answer is zero everywhere (G with τ read from ⁱNᵢ) names nothing: zeros are said as zeros."""
    made = answer.reference.mistakes.get(answer.term, {}) if answer.reference is not None else {}
    found: dict[str, list[str]] = {}
    for (code, variant), values in made.items():
        if np.any(values) and answer.agrees_with(values):
            found.setdefault(code, []).append(variant)
    return {code: found[code] for code in sorted(found, key=lambda code: code != "gravity-sign")}


def described(found: dict[str, list[str]]) -> str:
    """"[a] [b] … made with A in …; or, equally, with B in …": the mistakes found, in words."""
    said = [MISTAKES[c].words + "".join(f" {v}" for v in variants[:1] if v) + "".join(f", or {v}" for v in variants[1:])
            for c, variants in found.items()]
    return (" ".join(f"[{c}]" for c in found) + " matches the right answer computed with this slip: "
            + "; or, equally, with this one: ".join(said))


def explained(found: dict[str, list[str]]) -> str:
    """The mistakes found (:func:`matching_mistakes`), in words, then each one's advice.

    Parameters
    ----------
    found : dict of str to list of str
        Each mistake's code and the variants of it that agree with the answer.

    Returns
    -------
    str
        "[code] matches the right answer computed with this slip: … . Advice."
    """
    return described(found) + ". " + " ".join(_sentence(MISTAKES[c].advice) for c in found)


def named_mistake(answer: Answer) -> Finding | None:
    """Agrees with our answers made with a mistake (:data:`MISTAKES`); where several give the same answer (G alone
    cannot tell gravity's sign from reversed moments), all are named, the commonest first."""
    found = matching_mistakes(answer)
    return None if not found else Finding(explained(found), tuple(found), True)


def _sentence(text: str) -> str:
    return text + ("" if text.endswith(".") else ".")


#: How close a wrong answer must be to one of our mistaken answers to be called "closest to" it, the median over the
#: states of the largest entry's difference relative to that mistaken answer's own size being below CLOSE (5 %),
#: and ten times nearer it than the right answer.
CLOSE = 0.05
OWN_SIZE_FLOOR = 1e-3  # a mistaken answer near zero is measured against a thousandth of the term's scale, not against 0


def closest_mistake(answer: Answer) -> Finding | None:
    """Within :data:`CLOSE` of one of our mistaken answers (relative to its own size) and ten times nearer it than
    the right one, without agreeing: that mistake and another? When none is that close, a plain sentence says so
    (no mistake is named for being merely the least far)."""
    made = answer.reference.mistakes.get(answer.term, {}) if answer.reference is not None else {}
    if not made or not answer.usable:
        return None

    def distance(candidates, own_size: bool):
        return float(np.median([relative_error(answer.values[k], candidates[k],
                                               OWN_SIZE_FLOOR * answer.scales[k] if own_size else answer.scales[k])
                                for k in answer.usable]))

    right = distance(answer.expected, False)
    (code, variant), nearest = min(((key, distance(values, True)) for key, values in made.items()), key=lambda x: x[1])
    shown = _below(nearest, CLOSE)
    if not nearest < min(CLOSE, right / 10) or shown is None:
        return Finding(f"no mistake the grader names is within {CLOSE:.0%} of it: more than one thing is wrong, or "
                       "something else; the entries and the worst state below show where", ())
    return Finding(f"closest to [{code}] {MISTAKES[code].words}{' ' + variant if variant else ''} (relative error "
                   f"{shown} from that, {right:.1g} from the right answer, less than {CLOSE:.0%}): that mistake "
                   "and another?", (f"closest to {code}",))


def _below(x: float, limit: float) -> str | None:
    """``x`` to one significant digit (more, up to three, where fewer would round up to ``limit``), or None when
    even three would print ``limit``: a value shown beside "less than" is less than it."""
    for digits in (1, 2, 3):
        text = f"{x:.{digits}g}"
        if float(text) < limit:
            return text
    return None


__all__ = ["CLOSE", "CLOSED_FORM_JOINTS", "MISTAKES", "Mistake", "mistaken_terms"]
