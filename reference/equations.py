"""The lecture notes' equation labels, and where each one is covered: a test and a notebook cell.

:data:`EQUATIONS` lists every label of the notes ("Chapter 6. Manipulator Dynamics", the text file
:data:`NOTES_FILE`), written as the notes write it: (6.1) … (6.117), the pair (6.49, 6.50) as its two labels,
and the primed (6.15′), (6.15″), which the notes write (6.15') and (6.15''). Each label has the kind of place
it has in the notes:

==============  ==================================================================================
kind            the label in the notes
==============  ==================================================================================
``printed``     beside an equation: at the end of an equation display, or on the line after one ((6.37))
``empty``       alone in a display, with no equation next to it: (6.15'), (6.15'')
``range``       only as the end of a range of labels, "(6.31)-(6.37)": (6.31)
``cited``       only named in the text, "from (6.99), (6.60), (6.61), and (6.62)"
``unlabelled``  not in the notes: the equation is printed without its number ((6.116))
==============  ==================================================================================

For each label: the tests that check it (pytest node ids under ``tests/``) and the notebook cell that shows it
(a notebook under ``notebooks/`` and a short text of that cell), or, with no notebook, why none does. For an
empty, range-only or cited label, ``reading`` says which equation we take it to be. The errata
(``reference/errata.md``) lists what is misprinted; this list says where every label is checked.

:func:`labels_in` and :func:`kind_in` read the notes' text, so that ``tests/test_equations.py`` checks this list
against the notes themselves: no label of the notes can be missing, and none has a kind it does not have there.

>>> [e.label for e in EQUATIONS][:4], len(EQUATIONS)
(['(6.1)', '(6.2)', '(6.5)', '(6.7)'], 54)
>>> kind_in("$$(6.15')$$\\nForward (6.31)-(6.37).\\n$$F = m a \\\\quad (6.37)$$", "(6.31)")
'range'
"""
from __future__ import annotations

import re
from dataclasses import dataclass

NOTES_FILE = "chapter6-manipulator-dynamics.txt"

PRINTED, EMPTY, RANGE, CITED, UNLABELLED = "printed", "empty", "range", "cited", "unlabelled"
KINDS = (PRINTED, EMPTY, RANGE, CITED, UNLABELLED)

LABEL = re.compile(r"\((6\.\d+'*(?:\s*,\s*6\.\d+'*)*)\)")  # (6.12), (6.15''), (6.49, 6.50)
LABEL_RANGE = re.compile(r"\(6\.\d+'*\)\s*[-–]\s*\(6\.\d+'*\)")  # (6.45)-(6.53)


@dataclass(frozen=True)
class Equation:
    """One label of the notes and where it is covered.

    ``notebook`` is a path under ``notebooks/`` and ``cell`` a short text of the cell that shows the equation;
    with ``notebook`` None, ``cell`` says "none, because …".
    """

    label: str
    kind: str
    tests: tuple[str, ...]
    notebook: str | None
    cell: str
    reading: str = ""


def labels_in(text: str) -> list[str]:
    """Every chapter-6 label of the notes' text, as "(6.n)", in the order of first appearance.

    >>> labels_in("see (6.45)-(6.53); $$N = 0 \\\\quad (6.49, 6.50)$$ and (5.45)")
    ['(6.45)', '(6.53)', '(6.49)', '(6.50)']
    """
    found = []
    for match in LABEL.finditer(text):
        for number in re.split(r"\s*,\s*", match.group(1)):
            if f"({number})" not in found:
                found.append(f"({number})")
    return found


def kind_in(text: str, label: str) -> str:
    """The kind of place ``label`` ("(6.n)") has in the notes' text (the table of the module docstring).

    >>> kind_in("From (6.12) and (6.10),\\n$$a = b \\\\quad (6.12)$$", "(6.12)"), kind_in("From (6.10),", "(6.10)")
    ('printed', 'cited')
    """
    number = label[1:-1]
    lines = [line.strip() for line in text.splitlines()]
    places = [(k, match) for k, line in enumerate(lines) for match in LABEL.finditer(line)
              if number in re.split(r"\s*,\s*", match.group(1))]
    if not places:
        return UNLABELLED
    for k, match in places:
        line, printed_as = lines[k], match.group(0)
        if line == f"$${printed_as}$$":
            return EMPTY
        before = [previous for previous in lines[:k] if previous]
        if line.endswith(printed_as + "$$") or (line == printed_as and before and before[-1].endswith("$$")):
            return PRINTED
    in_a_range = all(any(r.start() <= m.start() and m.end() <= r.end() for r in LABEL_RANGE.finditer(lines[k]))
                     for k, m in places)
    return RANGE if in_a_range else CITED


ERRATA, MISPRINTS = "tests/test_errata.py::", "tests/test_misprints.py::"
MISPRINT, STEP = (MISPRINTS + "test_printed_is_wrong_and_corrected_is_right",
                  MISPRINTS + "test_step_agrees_with_its_truth")
NB01, NB03, NB04 = "notebooks/01_acceleration.py", "notebooks/03_newton_euler.py", "notebooks/04_structure.py"
NB05, NB06, NB08 = "notebooks/05_lagrange.py", "notebooks/06_cartesian.py", "notebooks/08_simulation.py"
NB09 = "notebooks/09_errata.py"
TRACE = "tests/test_trace.py::test_every_entry_agrees_with_pinocchio"
LINKS = "tests/test_newton_euler.py::test_link_quantities_are_consistent_with_tau"
CARTESIAN = "tests/test_cartesian.py::test_cartesian_terms_from_pinocchio_quantities"
CLOSED_FORM = "tests/test_textbook.py::test_symbolic_two_link_is_craig_6_60_to_6_62"

EQUATIONS: tuple[Equation, ...] = (
    Equation("(6.1)", PRINTED, (ERRATA + "test_6_1_and_6_2_are_limits_of_difference_quotients",), NB01, "(6.1)"),
    Equation("(6.2)", PRINTED, (ERRATA + "test_6_1_and_6_2_are_limits_of_difference_quotients",
                                ERRATA + "test_6_2_is_the_angular_velocity_of_frame_B"), NB01, "(6.2)"),
    Equation("(6.5)", PRINTED, (MISPRINT + "[(6.5) restated before (6.34)]",), NB01, "(6.5)"),
    Equation("(6.7)", PRINTED, (STEP + "[(6.7)]",), NB09, "(6.7)"),
    Equation("(6.8)", PRINTED, (STEP + "[(6.8)]",), NB09, "(6.8)"),
    Equation("(6.10)", PRINTED, (ERRATA + "test_6_10_printed_has_an_extra_coriolis_term",), NB01, "(6.10)"),
    Equation("(6.12)", PRINTED, (ERRATA + "test_6_12_fixed_point_is_correct",), NB01, "(6.12)"),
    Equation("(6.13)", PRINTED, (ERRATA + "test_6_13_angular_velocities_add",), NB01, "(6.13)"),
    Equation("(6.15)", PRINTED, (ERRATA + "test_6_15_angular_acceleration_is_correct",), NB01, "(6.15)"),
    Equation("(6.15')", EMPTY, (STEP + "[(6.15')]",), NB09, "(6.15′)",
             "the first step from (6.15) to (6.32): (6.15) with {A} = {0}, {B} = {i}, {C} = {i+1}, where joint i+1 "
             "gives ᴮΩ_C = θ̇ᵢ₊₁ ⁱẐᵢ₊₁ and ᴮΩ̇_C = θ̈ᵢ₊₁ ⁱẐᵢ₊₁: "
             "⁰ω̇ᵢ₊₁ = ⁰ω̇ᵢ + ⁰ᵢR θ̈ᵢ₊₁ ⁱẐᵢ₊₁ + ⁰ωᵢ × ⁰ᵢR θ̇ᵢ₊₁ ⁱẐᵢ₊₁"),
    Equation("(6.15'')", EMPTY, (STEP + "[(6.15'')]",), NB09, "(6.15″)",
             "the second step: (6.15′) in the axes of frame i+1 (multiplied by ⁱ⁺¹₀R, which carries a cross product "
             "over), ⁱ⁺¹ω̇ᵢ₊₁ = ⁱ⁺¹ᵢR ⁱω̇ᵢ + θ̈ᵢ₊₁ ⁱ⁺¹Ẑᵢ₊₁ + ⁱ⁺¹ᵢR ⁱωᵢ × θ̇ᵢ₊₁ ⁱ⁺¹Ẑᵢ₊₁, which is (6.32)"),
    Equation("(6.31)", RANGE, (STEP + "[(6.31)]", MISPRINT + "[the (5.45) line of (6.32)'s derivation]"), NB09,
             "(6.31)",
             "the first equation of the outward iteration the range (6.31)–(6.37) names, the angular velocity "
             "propagation (5.45), ⁱ⁺¹ωᵢ₊₁ = ⁱ⁺¹ᵢR ⁱωᵢ + θ̇ᵢ₊₁ ⁱ⁺¹Ẑᵢ₊₁: what the notes' \"from (5.45)\" line means, "
             "and what (6.45) restates"),
    Equation("(6.32)", PRINTED, (STEP + "[(6.15'')]", TRACE, MISPRINT + "[the prismatic remark after (6.32)]"), NB03,
             "&& (6.46)"),
    Equation("(6.34)", PRINTED, (TRACE, ERRATA + "test_6_45_to_6_47_rotation_is_inverted_in_print",
                                 MISPRINT + "[setting {A} = {i+1} before (6.34)]"), NB03, "&& (6.47)"),
    Equation("(6.35)", PRINTED, (STEP + "[(6.35)]",), NB09, "(6.35)"),
    Equation("(6.36)", PRINTED, (ERRATA + "test_6_48_com_acceleration", TRACE), NB03, "&& (6.48)"),
    Equation("(6.37)", PRINTED, (TRACE, LINKS), NB03, "(6.37)"),
    Equation("(6.38)", PRINTED, (STEP + "[(6.38)]",), NB09, "(6.38)"),
    Equation("(6.39)", PRINTED, (STEP + "[(6.39)]",), NB09, "(6.39)"),
    Equation("(6.41)", PRINTED, (ERRATA + "test_6_51_and_6_52_inward_iteration[6.51]", TRACE), NB03, "&& (6.51)"),
    Equation("(6.42)", PRINTED, (ERRATA + "test_6_51_and_6_52_inward_iteration[6.52]", TRACE), NB03, "&& (6.52)"),
    Equation("(6.43)", PRINTED, (MISPRINT + "[(6.43), in words]", LINKS), NB03, "&& (6.53)"),
    Equation("(6.44)", PRINTED, (STEP + "[(6.44)]", LINKS), NB09, "(6.44)"),
    Equation("(6.45)", PRINTED, (ERRATA + "test_6_45_to_6_47_rotation_is_inverted_in_print",), NB03, "&& (6.45)"),
    Equation("(6.46)", PRINTED, (ERRATA + "test_6_45_to_6_47_rotation_is_inverted_in_print",), NB03, "&& (6.46)"),
    Equation("(6.47)", PRINTED, (ERRATA + "test_6_45_to_6_47_rotation_is_inverted_in_print",), NB03, "&& (6.47)"),
    Equation("(6.48)", PRINTED, (ERRATA + "test_6_48_com_acceleration",), NB03, "&& (6.48)"),
    Equation("(6.49)", PRINTED, (LINKS, ERRATA + "test_worked_example_F1_uses_the_com_acceleration"), NB03,
             "&& (6.49)"),
    Equation("(6.50)", PRINTED, (ERRATA + "test_6_50_euler_uses_the_com_inertia_twice",), NB03, "&& (6.50)"),
    Equation("(6.51)", PRINTED, (ERRATA + "test_6_51_and_6_52_inward_iteration[6.51]",), NB03, "&& (6.51)"),
    Equation("(6.52)", PRINTED, (ERRATA + "test_6_51_and_6_52_inward_iteration[6.52]",), NB03, "&& (6.52)"),
    Equation("(6.53)", PRINTED, (LINKS, "tests/test_newton_euler.py::test_tau_agrees_with_pinocchio_rnea"), NB03,
             "&& (6.53)"),
    Equation("(6.59)", PRINTED, ("tests/test_dynamics.py::test_dynamics_terms_fit_the_state_space_equation",), NB04,
             "(6.59)"),
    Equation("(6.60)", CITED, (CLOSED_FORM,), NB04, "(6.60)–(6.62)", "Craig's two-link M(Θ)"),
    Equation("(6.61)", CITED, (CLOSED_FORM,), NB04, "(6.60)–(6.62)", "Craig's two-link V(Θ, Θ̇)"),
    Equation("(6.62)", CITED, (CLOSED_FORM,), NB04, "(6.60)–(6.62)", "Craig's two-link G(Θ)"),
    Equation("(6.63)", PRINTED, ("tests/test_lagrange.py::test_configuration_space_split_reproduces_V",
                                 MISPRINT + "[(6.63) legend]", ERRATA + "test_two_link_split_shapes"), NB04, "(6.63)"),
    Equation("(6.64)", PRINTED, ("tests/test_lagrange.py::test_configuration_space_split_reproduces_V",), NB04,
             "(6.64)"),
    Equation("(6.65)", PRINTED, (ERRATA + "test_6_65_centrifugal_vector",), NB04, "(6.65)"),
    Equation("(6.69)", PRINTED, ("tests/test_lagrange.py::test_kinetic_energy_is_the_quadratic_form",
                                 MISPRINT + "[(6.69)]"), NB05, "(6.69)"),
    Equation("(6.71)", PRINTED, ("tests/test_lagrange.py::test_kinetic_energy_is_the_quadratic_form",), NB05, "(6.71)"),
    Equation("(6.73)", PRINTED, ("tests/test_kinematics.py::test_potential_energy_agrees_with_pinocchio",
                                 MISPRINT + "[(6.73)]"), NB05, "(6.73)"),
    Equation("(6.75)", PRINTED, (ERRATA + "test_6_75_and_6_77_give_the_rp_arms_torques",), NB05, "(6.75)"),
    Equation("(6.77)", PRINTED, (ERRATA + "test_6_75_and_6_77_give_the_rp_arms_torques",
                                 "tests/test_lagrange.py::test_lagrangian_terms_agree_with_pinocchio"), NB05, "(6.77)"),
    Equation("(6.91)", PRINTED, (CARTESIAN,), NB06, "(6.91)"),
    Equation("(6.94)", PRINTED, (CARTESIAN,), NB06, "(6.94)"),
    Equation("(6.97)", PRINTED, (ERRATA + "test_6_105_has_M_x_and_the_joint_space_gravity",
                                 "tests/test_cartesian.py::test_two_link_is_craig_example_6_6"), NB06, "(6.97)"),
    Equation("(6.98)", PRINTED, (CARTESIAN,), NB06, "(6.98)"),
    Equation("(6.99)", PRINTED, (CARTESIAN, "tests/test_cartesian.py::test_two_link_is_craig_example_6_6"), NB06,
             "(6.99)"),
    Equation("(6.104)", PRINTED, ("tests/test_cartesian.py::test_two_link_is_craig_example_6_6",), NB06, "(6.104)"),
    Equation("(6.105)", PRINTED, (ERRATA + "test_6_105_has_M_x_and_the_joint_space_gravity",
                                  "tests/test_cartesian.py::test_6_105_with_B_x_and_C_x_agrees_with_pinocchio"), NB09,
             "(6.105)"),
    Equation("(6.115)", PRINTED, ("tests/test_forward_dynamics.py::test_forward_dynamics_agrees_with_aba",
                                  ERRATA + "test_6_115_solves_the_joint_space_equation_with_friction"), NB08,
             "(6.115)"),
    Equation("(6.116)", UNLABELLED, ("tests/test_simulation.py::test_euler_step_is_exactly_6_116_and_6_117",), NB08,
             "(6.116)", "the velocity step printed without its number, Θ̇(t + Δt) = Θ̇(t) + Θ̈(Δt), Θ̈(Δt) a product"),
    Equation("(6.117)", PRINTED, (MISPRINT + "[(6.117)]",
                                  "tests/test_simulation.py::test_euler_step_is_exactly_6_116_and_6_117"), NB08,
             "(6.117)"),
)
