"""course_dynamics/teaching/exercises.py and catalogue.py: each kind of check says right, wrong (and why) or not done
yet, never raises, never shows the expected value, and checks each student against their own robot and numbers."""
from __future__ import annotations

import re

import numpy as np
import pytest
import sympy

from course_dynamics.base.errors import InputError
from course_dynamics.teaching.exercises import (
    EXERCISES,
    check,
    given,
    hint,
    my_robot,
    show_values,
    student,
    symbols,
    use_student,
)


@pytest.fixture(autouse=True)
def course_student():
    """Every test starts as the default student, students' view (no values shown), and leaves it so."""
    use_student("course")
    show_values(False)
    yield
    use_student("course")
    show_values(False)


def closed_form_G(parameters, sign=1.0):
    """The two-link arm's G (6.62) with a student's own numbers (their ``my_robot("two_link").parameters``)."""
    m1, m2, l1, l2, g = (parameters[k] for k in ("m1", "m2", "l1", "l2", "g"))
    return lambda q: sign * np.array([m2 * l2 * g * np.cos(q[0] + q[1]) + (m1 + m2) * l1 * g * np.cos(q[0]),
                                      m2 * l2 * g * np.cos(q[0] + q[1])])


def test_not_done_yet_for_missing_placeholder_and_empty_function():
    assert check("M_two_link", None).status == "not done"
    assert check("omega_dot_C", ...).status == "not done"

    def empty(q):
        ...

    def unfinished(q):
        raise NotImplementedError

    assert check("M_two_link", empty).status == "not done"
    assert check("M_two_link", unfinished).status == "not done"
    assert check("k_pendulum").status == "not done"  # no such name in this test's globals


def test_a_function_of_the_robot_gets_the_graders_diagnosis():
    parameters = my_robot("two_link").parameters
    assert check("G_two_link", closed_form_G(parameters))
    verdict = check("G_two_link", closed_form_G(parameters, -1.0))
    assert verdict.status == "wrong" and not verdict
    assert any(line.startswith("has the opposite sign everywhere") and "[gravity-sign]" in line for line in verdict.lines)
    assert any("hint('G_two_link')" in line for line in verdict.lines)


def test_each_student_has_their_own_robot_and_numbers():
    use_student("ada")
    ada, ada_state = my_robot("two_link").parameters, given("v_dot_c1")
    ada_G = closed_form_G(ada)
    assert check("G_two_link", ada_G)
    use_student("grace")
    grace = my_robot("two_link").parameters
    assert ada != grace and not np.array_equal(ada_state["q"], given("v_dot_c1")["q"])
    assert check("G_two_link", ada_G).status == "wrong"  # Ada's solution does not pass Grace's check
    assert check("G_two_link", closed_form_G(grace)) and student() == "grace"
    use_student("course")  # a notebook without an id: a variant too, never the worked examples' robot
    assert my_robot("two_link").parameters["m1"] != 2.0


@pytest.mark.parametrize("bad", ["", "../x", "a b", "ada/../../etc", "é", "x" * 65, ".hidden", "ends."])
def test_ids_unsafe_as_file_names_are_refused(bad):
    with pytest.raises(InputError, match="student id"):
        use_student(bad)


def test_no_check_shows_the_expected_value():
    """The values a student could paste never appear: τ, G, a vector, a matrix, a formula at a point."""
    parameters = my_robot("two_link").parameters
    expected = [
        (check("G_two_link", closed_form_G(parameters, 1.01)), None),
        (check("v_dot_c1", np.zeros(3)), EXERCISES["v_dot_c1"].answer()),
        (check("Mx_value", np.eye(2)), EXERCISES["Mx_value"].answer()),
        (check("omega_dot_C", np.ones(3)), EXERCISES["omega_dot_C"].answer()),
        (check("tau_with_friction", np.zeros(2)), EXERCISES["tau_with_friction"].answer()),
    ]
    for verdict, value in expected:
        text = verdict.text()
        assert verdict.status == "wrong" and "expected" not in text and "the right one" not in text, text
        if value is not None:
            for x in np.ravel(value):
                if abs(x) > 1e-9:
                    assert f"{x:.6g}" not in text and f"{x:.4g}" not in text, (x, text)
    formula = check("k_pendulum", symbols("m") * symbols("l") ** 2 * symbols("theta_dot") ** 2).text()
    assert "yours gives" in formula and "the right one" not in formula
    show_values(True)  # the instructor's solution mode may show them
    assert "expected" in check("v_dot_c1", np.zeros(3)).text()


def test_hints_come_in_tiers_the_method_last():
    assert all(len(exercise.hints) >= 3 for exercise in EXERCISES.values())
    first, last = hint("G_two_link"), hint("G_two_link", 3)
    assert first.startswith("hint 1 of 3:") and "hint('G_two_link', 2)" in first
    assert "(6.73)" in last and "for more" not in last and hint("G_two_link", 99) == last


ASKED = {"tau": "τ", "M": "M", "V": "V", "G": "G"}  # what a term exercise asks for
FORMULAS = {"k_pendulum": "k", "u_pendulum": "u", "tau_pendulum": "τ", "B_rp_arm": "B", "C_rp_arm": "C",
            "J_tool": "J"}  # what a formula exercise asks for (I_corner's last hint is the parallel-axis theorem)
PRODUCT = re.compile(r"(?:[mlgsc][₁₂]+²?){3,}")  # m₂l₁l₂s₂, l₂²m₂, m₂l₂gc₁₂: a closed form's terms


@pytest.mark.parametrize("name", list(EXERCISES))
def test_no_hint_gives_the_answer(name):
    """A hint points at the method; it never holds the closed form a term or formula exercise asks for (the
    two-link arm's (6.60)–(6.62), a pendulum's k, u or τ, example 6.5's B and C, the tool Jacobian), nor the
    numbers a value exercise asks for."""
    exercise = EXERCISES[name]
    for text in exercise.hints:
        if exercise.kind == "term":
            assert not re.search(rf"(?<![\w(]){ASKED[exercise.term]}(\(Θ[^)]*\))? = ", text), (name, text)
            assert not PRODUCT.search(text), (name, text)
        if name in FORMULAS:
            assert not re.search(rf"(?<!\w)[³ᴬ]?{FORMULAS[name]} = ", text), (name, text)
            assert not PRODUCT.search(text.replace(" ", "")), (name, text)
        if exercise.kind == "value" and np.asarray(exercise.answer()).dtype != bool:
            numbers = [float(x) for x in np.ravel(exercise.answer()) if abs(float(x)) > 1e-9]
            for x in numbers:
                for shown in {f"{x:.3g}", f"{x:.2f}", f"{abs(x):.3g}"}:
                    assert len(shown.strip("-0.")) < 2 or shown not in text, (name, shown, text)


def test_values_name_their_wrong_entries():
    right = np.linalg.eigvalsh(given("principal_moments")["I"])
    assert check("principal_moments", right)
    wrong = right.copy()
    wrong[1] += 1.0
    verdict = check("principal_moments", wrong)
    assert re.search("entries 2 are wrong|entry 2 is wrong", verdict.text())
    assert "has shape (2,)" in check("principal_moments", right[:2]).text()


def test_values_get_the_graders_checks():
    """A value goes through grading.score like a graded term: the same named mistakes, in the same words."""
    tensor = given("principal_moments")["I"]
    counted_twice = check("principal_moments", np.linalg.eigvalsh(tensor + tensor)).text()
    assert "is the right answer times a constant factor of about 2.0" in counted_twice
    d = given("I_xy_corner")
    with_the_notes_minus = d["m"] * 0 - d["m"] * (d["w"] / 2) * (d["l"] / 2)  # ᶜI_xy − m x_c y_c, ᶜI_xy = 0
    assert "has the opposite sign everywhere" in check("I_xy_corner", with_the_notes_minus).text()
    assert "expected numbers, got 'abc'" in check("principal_moments", "abc").text()


def test_formulas_are_compared_exactly():
    m, l, g, theta, theta_dot = symbols("m", "l", "g", "theta", "theta_dot")
    assert check("k_pendulum", m * l**2 * theta_dot**2 / 2)
    assert "times 2" in check("k_pendulum", m * l**2 * theta_dot**2).text()
    assert "uses symbols x" in check("k_pendulum", sympy.Symbol("x")).text()
    assert check("u_pendulum", -m * g * l * sympy.cos(theta) + 42 * m * g)  # any reference height


def test_functions_on_random_inputs():
    assert check("euler_step", lambda q, qd, qdd, dt: (q + qd * dt + qdd * dt**2 / 2, qd + qdd * dt))
    verdict = check("euler_step", lambda q, qd, qdd, dt: (q + qd * dt, qd + qdd * dt))
    assert verdict.status == "wrong" and "value 1" in verdict.text()
    assert "raised ZeroDivisionError" in check("inward_force", lambda R, f, F: 1 / 0).text()


def test_autograde_mode_raises(monkeypatch):
    monkeypatch.setenv("NBGRADER_EXECUTION", "autograde")
    with pytest.raises(AssertionError, match="not done yet"):
        check("omega_dot_C", None)


def test_unknown_names_are_an_error():
    with pytest.raises(KeyError, match="no exercise named"):
        check("flux_capacitor", 1)


def spatial_links(slip=None):
    """A student's link-by-link recursion for their spatial arm (numpy, as written by hand), with one slip made."""
    model = my_robot("spatial_arm").model
    z = np.array([0.0, 0.0, 1.0])

    def rot_z(t):
        c, s = np.cos(t), np.sin(t)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

    def links(q, qd, qdd):
        bodies = model.bodies
        R = [b.R0 @ rot_z(q[i]) for i, b in enumerate(bodies)]
        w, wd, vd = np.zeros(3), np.zeros(3), -model.gravity
        out = {k: [] for k in ("omega", "omega_dot", "v_dot", "v_dot_c", "F", "N", "f", "n", "tau")}
        for i, b in enumerate(bodies):
            Rt = R[i] if slip == "rotation-transposed" else R[i].T
            vd = Rt @ (np.cross(wd, b.P) + np.cross(w, np.cross(w, b.P)) + vd)
            wd = Rt @ wd + np.cross(Rt @ w, qd[i] * z) + qdd[i] * z
            w = Rt @ w + qd[i] * z
            vc = np.cross(wd, b.p_com) + np.cross(w, np.cross(w, b.p_com)) + vd
            gyro = 0 if slip == "gyroscopic-missing" else np.cross(w, b.I_com @ w)
            for k, v in (("omega", w), ("omega_dot", wd), ("v_dot", vd), ("v_dot_c", vc), ("F", b.mass * vc),
                         ("N", b.I_com @ wd + gyro)):
                out[k].append(v)
        f, n = np.zeros(3), np.zeros(3)
        for i in reversed(range(len(bodies))):
            R_next = R[i + 1] if i + 1 < len(bodies) else np.eye(3)
            P_next = bodies[i + 1].P if i + 1 < len(bodies) else np.zeros(3)
            n = out["N"][i] + R_next @ n + np.cross(bodies[i].p_com, out["F"][i]) + np.cross(P_next, R_next @ f)
            f = R_next @ f + out["F"][i]
            out["f"].insert(0, f)
            out["n"].insert(0, n)
            out["tau"].insert(0, n @ z)
        return out

    return links


def test_newton_euler_on_the_spatial_arm_link_by_link():
    assert check("links_spatial_arm", spatial_links())
    gyroscopic = check("links_spatial_arm", spatial_links("gyroscopic-missing")).text()
    assert "ⁱNᵢ (6.50) is wrong for link 1, 2, 3" in gyroscopic and "[gyroscopic-missing]" in gyroscopic
    transposed = check("links_spatial_arm", spatial_links("rotation-transposed")).text()
    assert "ⁱωᵢ (6.45) is wrong" in transposed and "[rotation-transposed]" in transposed
    assert "expected" not in gyroscopic + transposed
    right = spatial_links()

    def columns(q, qd, qdd):  # links as columns: a 3 × 3 array read the wrong way round
        out = right(q, qd, qdd)
        return {**out, "omega": np.array(out["omega"]).T}

    assert "ⁱωᵢ (6.45) (key 'omega') should be one 3-vector per link, link 1 first: shape (3, 3), not" not in \
        check("links_spatial_arm", columns).text()  # same shape: judged on its values, which are wrong
    assert "is wrong for link" in check("links_spatial_arm", columns).text()
    flat = check("links_spatial_arm", lambda q, qd, qdd: {**right(q, qd, qdd), "F": np.ravel(right(q, qd, qdd)["F"])})
    assert "ⁱFᵢ (6.49) (key 'F') should be one 3-vector per link, link 1 first: shape (3, 3), not (9,)" in flat.text()


def rp_arm_lagrange(chain_rule=True, half_kinetic_of_d2=False):
    """Example 6.5 derived by Lagrange as on paper: θ₁(t), d₂(t), k and u written out, L differentiated in t."""
    from course_dynamics.teaching.exercises import time_functions

    m1, m2, l1, Izz1, Izz2, g = symbols("m1", "m2", "l1", "Izz1", "Izz2", "g")
    t, theta1, d2 = time_functions("theta1", "d2")
    v2_squared = d2.diff(t) ** 2 + (d2 ** 2 if not half_kinetic_of_d2 else d2 ** 2 / 2) * theta1.diff(t) ** 2
    k = (m1 * l1**2 + Izz1 + Izz2) * theta1.diff(t) ** 2 / 2 + m2 * v2_squared / 2
    u = g * (m1 * l1 + m2 * d2) * sympy.sin(theta1)
    L = k - u
    if chain_rule:
        return [sympy.diff(L.diff(x.diff(t)), t) - L.diff(x) for x in (theta1, d2)]
    # "d/dt replaces θ̇ by θ̈": right only where ∂L/∂θ̇ has constant coefficients
    return [L.diff(x.diff(t)).subs({theta1.diff(t): theta1.diff(t, 2), d2.diff(t): d2.diff(t, 2)}) - L.diff(x)
            for x in (theta1, d2)]


def test_example_6_5_by_lagrange_in_theta_of_t():
    assert check("lagrange_rp_arm", rp_arm_lagrange())
    tau1, tau2 = rp_arm_lagrange()
    assert check("lagrange_rp_arm", [sympy.expand(sympy.trigsimp(tau1)), sympy.factor(tau2)])  # any equivalent form
    without_chain_rule = check("lagrange_rp_arm", rp_arm_lagrange(chain_rule=False)).text()
    assert "V₁ lacks the Coriolis term 2*ḋ₂*d₂*m2*θ̇₁" in without_chain_rule
    halved = check("lagrange_rp_arm", rp_arm_lagrange(half_kinetic_of_d2=True)).text()  # three terms differ:
    assert "these parts differ from the right ones: M₁₁, V₁, V₂" in halved and "d₂" not in halved  # named, not shown
    nothing = check("lagrange_rp_arm", [0, 0]).text()
    assert "M₁₁, V₁, G₁, M₂₂, V₂, G₂" in nothing and "m2" not in nothing  # the answer is never the feedback
    assert "[joints-swapped]" in check("lagrange_rp_arm", [tau2, tau1]).text()
    g = symbols("g")
    assert "[gravity-sign]" in check("lagrange_rp_arm", [e.subs(g, -g) for e in (tau1, tau2)]).text()
    assert "write every parameter as its symbol (g, not 9.81)" in check("lagrange_rp_arm",
                                                                        [tau1.subs(g, 9.81), tau2]).text()
    swapped = [e.replace(sympy.sin, lambda x: sympy.Function("c")(x)).replace(sympy.cos, sympy.sin)
               .replace(sympy.Function("c"), sympy.cos) for e in (tau1, tau2)]
    assert "[sin-cos-swapped]" in check("lagrange_rp_arm", swapped).text()
    own = sympy.Symbol("m2")  # a student's own symbol, without the package's assumptions, is read by its name
    assert check("lagrange_rp_arm", [tau1.subs(symbols("m2"), own), tau2.subs(symbols("m2"), own)])
    assert "uses x" in check("lagrange_rp_arm", [tau1 + sympy.Symbol("x"), tau2]).text()
    assert "a list of 2 expressions" in check("lagrange_rp_arm", tau1).text()
    m2, d2 = symbols("m2", "d2")
    assert check("B_rp_arm", sympy.Matrix([[2 * m2 * d2], [0]])) and check("C_rp_arm", sympy.Matrix([[0, 0], [-m2 * d2, 0]]))
    assert "[coriolis-half]" in check("B_rp_arm", sympy.Matrix([[m2 * d2], [0]])).text()
    assert "entry (1, 1) is wrong" in check("B_rp_arm", sympy.Matrix([[3 * m2 * d2], [0]])).text()


HOMEWORK_SLIPS = [  # exercise, a student's answer with a slip, the code the check names
    ("omega_dot_propagation", lambda R, w, wd, qd, qdd: R @ wd + np.cross(R @ wd, qd * Z) + qdd * Z,
     "angular-acceleration-in-cross"),
    ("omega_dot_propagation", lambda R, w, wd, qd, qdd: R.T @ wd + np.cross(R.T @ w, qd * Z) + qdd * Z,
     "rotation-transposed"),
    ("v_dot_propagation", lambda R, w, wd, vd, P: R @ (np.cross(wd, P) + vd), "centripetal-missing"),
    ("v_dot_com", lambda w, wd, vd, P: np.cross(wd, P) + vd, "centripetal-missing"),
    ("inward_moment", lambda R, N, n, P_c, F, P, f: N + R @ n + np.cross(P_c, F), "moment-arm-missing"),
    ("prismatic_joint", lambda R, w, wd, vd, P, dd, ddd, f: (
        R @ (np.cross(wd, P) + np.cross(w, np.cross(w, P)) + vd) + np.cross(R @ w, dd * Z) + ddd * Z, f @ Z),
     "coriolis-half"),
    ("moving_point", lambda Vo, R, W, Wd, Q, V, Vd: Vo + R @ Vd + 3 * np.cross(W, R @ V) + np.cross(Wd, R @ Q)
     + np.cross(W, np.cross(W, R @ Q)), "coriolis-doubled"),
]
Z = np.array([0.0, 0.0, 1.0])


def right_homework():
    return {
        "omega_dot_propagation": lambda R, w, wd, qd, qdd: R @ wd + np.cross(R @ w, qd * Z) + qdd * Z,
        "v_dot_propagation": lambda R, w, wd, vd, P: R @ (np.cross(wd, P) + np.cross(w, np.cross(w, P)) + vd),
        "v_dot_com": lambda w, wd, vd, P: np.cross(wd, P) + np.cross(w, np.cross(w, P)) + vd,
        "inward_moment": lambda R, N, n, P_c, F, P, f: N + R @ n + np.cross(P_c, F) + np.cross(P, R @ f),
        "prismatic_joint": lambda R, w, wd, vd, P, dd, ddd, f: (
            R @ (np.cross(wd, P) + np.cross(w, np.cross(w, P)) + vd) + 2 * np.cross(R @ w, dd * Z) + ddd * Z, f @ Z),
        "moving_point": lambda Vo, R, W, Wd, Q, V, Vd: Vo + R @ Vd + 2 * np.cross(W, R @ V) + np.cross(Wd, R @ Q)
        + np.cross(W, np.cross(W, R @ Q)),
    }


@pytest.mark.parametrize("exercise", list(right_homework()))
def test_the_notes_homework_right(exercise):
    assert check(exercise, right_homework()[exercise])


@pytest.mark.parametrize("exercise, answer, code", HOMEWORK_SLIPS, ids=[f"{e}-{c}" for e, _, c in HOMEWORK_SLIPS])
def test_the_notes_homework_names_each_slip(exercise, answer, code):
    verdict = check(exercise, answer)
    assert verdict.status == "wrong" and any(line.startswith(f"[{code}]") for line in verdict.lines), verdict.text()


def test_checks_never_raise_whatever_they_are_given():
    """A student's notebook never gets a traceback from a check: odd types, huge numbers, callables without code."""
    import functools

    class Callable:
        def __call__(self, q):
            return np.zeros(2)

    odd = [("G_two_link", Callable()), ("G_two_link", functools.partial(lambda a, q: a * q, 1.0)),
           ("I_corner", 0), ("I_corner", "m*w"), ("k_pendulum", [1]), ("k_pendulum", 1j), ("v_dot_c1", 10**400),
           ("lagrange_rp_arm", [[1]]), ("links_spatial_arm", lambda q, qd, qdd: "abc"), ("euler_step", max)]
    for name, answer in odd:
        verdict = check(name, answer)
        assert verdict.status == "wrong", (name, verdict.text())
    assert "holds complex numbers" in check("v_dot_c1", np.array([1j, 0, 0])).text()
    assert hint("v_dot_c1", None).startswith("hint 1 of 3") and hint("v_dot_c1", float("nan")).startswith("hint 1")
    with pytest.raises(KeyError, match="no exercise named 'nope'"):
        hint("nope")


def test_an_answer_that_changes_its_inputs_is_judged_on_what_it_returns():
    def in_place(q, qd, qdd, dt):  # right, though it writes into its arguments
        qd += qdd * dt
        q += qd * dt
        return q, qd

    def zeroing(q, qd, qdd, dt):  # wrong: it zeroes the inputs the reference would be computed on
        q[...], qd[...], qdd[...] = 0, 0, 0
        return q.copy(), qd.copy()

    assert check("semi_implicit_step", in_place) and not check("euler_step", zeroing)


def test_a_function_that_never_returns_is_stopped(monkeypatch):
    from course_dynamics.teaching import exercises

    check("G_two_link", lambda q: np.zeros(2))  # the robot loaded, the closed forms derived: then the time is theirs
    monkeypatch.setattr(exercises, "CHECK_SECONDS", 3)

    def endless(q):
        while True:
            try:
                pass
            except Exception:  # a student's own handler cannot swallow the time limit
                pass

    verdict = check("G_two_link", endless)
    assert verdict.status == "wrong" and "took more than 3 s to check: an endless loop" in verdict.text()


def test_the_verdict_says_whose_numbers_it_checked():
    use_student("ada")
    assert "(ada's numbers)" in check("v_dot_c1", np.zeros(3)).text()
    use_student("course")
    assert "(no student id: the course's own numbers)" in check("v_dot_c1", np.zeros(3)).text()
    assert "numbers" not in check("k_pendulum", 1).text().splitlines()[0]  # a formula is the same for everyone


def test_a_value_from_the_recursion_names_the_slip():
    from course_dynamics.grading.slips import Slip
    from course_dynamics.teaching.catalogue import _v_dot_c1

    verdict = check("v_dot_c1", _v_dot_c1(Slip("centripetal-missing", ("6.48",))))
    assert verdict.lines[0].startswith("[centripetal-missing] it matches the centripetal term ω × (ω × P) left out in "
                                       "(6.48).")
    assert "[gravity-sign]" in check("v_dot_c1", _v_dot_c1(Slip("gravity-sign", ("base",)))).text()


def test_sys_exit_and_bare_excepts_do_not_escape_or_stall_a_check(monkeypatch):
    import sys
    import time

    from course_dynamics.teaching import exercises

    monkeypatch.setattr(exercises, "CHECK_SECONDS", 1)
    assert "SystemExit" in check("point_acceleration", lambda *a: sys.exit("x")).text()

    def stubborn(*arguments):
        while True:
            try:
                time.sleep(0.01)
            except:  # noqa: E722 — what a student may write; the time limit comes back until it gets through
                pass

    assert "took more than 1 s" in check("euler_step", stubborn).text()


def test_yes_or_no_answers_do_not_say_which_are_wrong():
    right = EXERCISES["physical"].answer()
    text = check("physical", ~right).text()
    assert "not all of them are right" in text and "entr" not in text


def test_every_numeric_exercise_runs_on_the_students_own_robot():
    """A value, a term, the links and a function's inputs (as its check draws them) all come from the student's own
    robot and numbers, and differ between two students; only a formula in symbols is the same for everyone."""
    from course_dynamics.teaching.catalogue import EXERCISES as CATALOGUE
    from course_dynamics.tools.variants import rng_for

    def made(name):
        exercise = CATALOGUE[name]
        if exercise.kind == "function":
            return exercise.inputs(rng_for(student(), name))
        if exercise.kind == "value":
            return exercise.answer()
        return my_robot(exercise.robot).parameters  # "term" and "links": the student's robot itself

    generic = {"euler_step", "semi_implicit_step"}  # notebook 8's integrators take rates of no robot
    numeric = [name for name, e in CATALOGUE.items() if e.kind not in ("formula", "equations") and name not in generic]
    assert len(numeric) >= 24
    use_student("ada")
    ada = {name: made(name) for name in numeric}
    use_student("grace")
    for name in numeric:
        theirs, mine = ada[name], made(name)
        if isinstance(mine, dict):
            assert theirs != mine, name
        else:
            flat = [np.ravel(np.asarray(x, dtype=float)) for x in (theirs if isinstance(theirs, list) else [theirs])]
            other = [np.ravel(np.asarray(x, dtype=float)) for x in (mine if isinstance(mine, list) else [mine])]
            assert any(a.shape != b.shape or not np.allclose(a, b) for a, b in zip(flat, other)), name


def test_the_predict_first_pose_has_an_answer_of_the_students_own():
    """Notebook 4's question (the sign of G₁ with link 1 raised by the student's θ₁ and link 2 pointing back) has
    either answer, depending on the student's arm and pose."""
    from course_dynamics import gravity_torques

    signs = set()
    for k in range(40):
        use_student(f"student{k}")
        theta1 = given("predict_G")["theta1"]
        signs.add(bool(gravity_torques(my_robot("two_link").model, [theta1, np.pi - theta1])[0] > 0))
    assert signs == {True, False}
