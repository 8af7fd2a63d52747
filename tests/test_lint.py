"""course_dynamics/tools/lint.py (and lint_classes, lint_geometry, cli/commands/lint.py): the URDF physics linter.

Every class of finding has a URDF with one thing changed (tests/helpers.py's two-link arm) that the linter
names by class and by link or joint; the robots we ship lint without an error, with the notes and warnings
listed here, each read and judged; what the loader refuses is a finding (exit 1), and only a file that is no
URDF at all is an ``error:`` line (exit 2).
"""
from __future__ import annotations

import json

import pytest
from helpers import BAD_URDFS, JOINT, LINK, ROOT, arm_urdf, assert_one_line_error, run

from course_dynamics.core.robots import load, robot_names, robot_path
from course_dynamics.tools.lint import lint_urdf, mass_findings, sarif
from course_dynamics.tools.lint_classes import CLASSES, SEVERITIES

LINK2 = LINK.format(name="link2", mass="1.0", ixx="0.01", iyy="0.01", izz="0.01")
LINK1 = LINK.format(name="link1", mass="1.0", ixx="0.01", iyy="0.01", izz="0.01")
LIMIT = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'


def second(text: str, old: str, new: str) -> str:
    """``text`` with the second ``old`` (joint2's, link2's) replaced by ``new``."""
    first = text.index(old)
    at = text.index(old, first + len(old))
    return text[:at] + new + text[at + len(old):]


def with_box(size: str, at: str = "0.1 0 0", **link) -> str:
    """The arm whose link2 has a collision box of ``size`` centred at ``at`` (and ``link``'s mass and inertia)."""
    values = dict(mass="1.0", ixx="0.01", iyy="0.01", izz="0.01") | link
    body = LINK.format(name="link2", **values).replace(
        "</inertial>", f'</inertial><collision><origin xyz="{at}" rpy="0 0 0"/><geometry><box size="{size}"/>'
                       "</geometry></collision>")
    return arm_urdf().replace(LINK2, body)


# class → (URDF text with one thing changed, the link or joint (or robot) the finding names)
MUTATIONS = {
    "unreadable-number": (arm_urdf(mass="heavy"), "link2"),
    "xml-namespace": (BAD_URDFS["default namespace"][0], "joint1"),
    "empty-name": (arm_urdf().replace('name="joint2"', 'name=""'), ""),
    "duplicate-name": (arm_urdf().replace('name="joint2"', 'name="joint1"'), "joint1"),
    "unusable-name": (arm_urdf().replace('name="joint2"', 'name="joint&#9;2"'), "joint\t2"),
    "undefined-link": (BAD_URDFS["undefined link"][0], "j3"),
    "unsupported-joint": (arm_urdf(joint_type="floating"), "joint2"),
    "not-a-tree": (BAD_URDFS["kinematic loop"][0], "loop"),
    "nothing-moves": (arm_urdf().replace('type="revolute"', 'type="fixed"'), "probe"),
    "refused": (arm_urdf().replace("</inertial></link>", "</inertial><collision><geometry/></collision></link>", 1),
                "probe"),
    "no-mass": (arm_urdf().replace(LINK1, '<link name="link1"/>').replace(LINK2, '<link name="link2"/>'), "probe"),
    "joint-carries-nothing": (arm_urdf().replace(LINK2, '<link name="link2"/>'), "joint2"),
    "missing-inertial": (arm_urdf().replace(LINK1, '<link name="link1"/>'), "link1"),
    "negative-mass": (arm_urdf(mass="-1"), "link2"),
    "zero-mass": (arm_urdf(mass="0"), "link2"),
    "inertia-not-psd": (arm_urdf(ixx="-0.01"), "link2"),
    "triangle-inequality": (arm_urdf(izz="0.05"), "link2"),
    "inertia-on-boundary": (arm_urdf(izz="0.02"), "link2"),
    "point-mass": (arm_urdf(ixx="0", iyy="0", izz="0"), "link2"),
    "inertial-rpy": (second(arm_urdf(), 'rpy="0 0 0"/><mass', 'rpy="0 0 1.5707963267948966"/><mass'), "link2"),
    "implausible-density": (with_box("0.1 0.1 0.1", mass="30"), "link2"),    # 30 000 kg/m³: denser than osmium
    "gyration-exceeds-link": (with_box("0.1 0.1 0.1", ixx="0.05", iyy="0.05", izz="0.05"), "link2"),
    "com-outside-geometry": (with_box("0.1 0.1 0.1", at="0 0 0"), "link2"),  # the COM 0.1 m out, the box 0.05
    "units-slip": (with_box("0.1 0.1 0.1", mass="2700"), "link2"),            # aluminium, in grams
    "missing-limit": (second(arm_urdf(), LIMIT, ""), "joint2"),
    "reversed-limits": (second(arm_urdf(), LIMIT, LIMIT.replace('lower="-1" upper="1"', 'lower="1" upper="-1"')),
                        "joint2"),
    "zero-range": (second(arm_urdf(), LIMIT, '<limit effort="1" velocity="1"/>'), "joint2"),
    "huge-limits": (second(arm_urdf(), LIMIT, LIMIT.replace('"-1"', '"-1.7976931348623157e308"')), "joint2"),
    "zero-effort-velocity": (second(arm_urdf(), LIMIT, LIMIT.replace('effort="1"', 'effort="0"')), "joint2"),
    "negative-effort-velocity": (second(arm_urdf(), LIMIT, LIMIT.replace('velocity="1"', 'velocity="-1"')),
                                 "joint2"),
    "zero-axis": (arm_urdf(axis="0 0 0"), "joint2"),
    "axis-not-unit": (arm_urdf(axis="0 0 2"), "joint2"),
    "mimic-joint": (second(arm_urdf(), LIMIT, LIMIT + '<mimic joint="joint1" multiplier="1"/>'), "joint2"),
    "mimic-on-fixed": (arm_urdf(extra='<link name="plate"/><joint name="bolt" type="fixed"><parent link="link2"/>'
                                      '<child link="plate"/><mimic joint="joint1" multiplier="nan"/></joint>'), "bolt"),
    "mimic-pinocchio-cannot-build": (second(arm_urdf(), LIMIT, LIMIT + '<mimic joint="joint1" multiplier="0.5"/>')
                                     .replace("</robot>", LINK.format(name="link3", mass="1.0", ixx="0.01",
                                                                      iyy="0.01", izz="0.01")
                                              + JOINT.format(name="joint3", type="revolute", parent="link2",
                                                             child="link3", axis="0 0 1").replace(
                                                  "</joint>", '<mimic joint="joint2"/></joint>') + "</robot>"),
                                     "joint3"),
    "damping-friction": (second(arm_urdf(), LIMIT, LIMIT + '<dynamics damping="0.1" friction="0.2"/>'), "joint2"),
    "padded-number": (arm_urdf(mass="1.0 "), "link2"),
    "incomplete-inertial": (second(arm_urdf(), '<mass value="1.0"/>', ""), "link2"),
    "base-inertia-not-physical": (arm_urdf(extra=LINK.format(name="plate", mass="1.0", ixx="-0.01", iyy="0.01",
                                                             izz="0.01")
                                           + JOINT.format(name="bolted", type="fixed", parent="base", child="plate",
                                                          axis="1 0 0")), "plate"),
    "placeholder-inertia": (with_box("0.001 0.001 0.001", at="0.1 0 0", mass="0.0001", ixx="1e-9", iyy="1e-9",
                                     izz="1e-9"), "link2"),                    # 1e5 kg/m³, but 1e-4 of the robot
    "mass-beyond-effort": (arm_urdf(mass="1000"), "joint1"),                   # 1 N m to hold 1001 kg at 0.14 m
}
UNREAD = {"not-a-urdf"}   # a class of the command line's: a file lint_urdf cannot read (tested below)

# What the shipped robots get, read one by one: (robot, class, link or joint).
SHIPPED = {
    # The textbook's point masses (Craig's two-link arm, the notes' pendulum): as the course means them.
    "two_link": [("point-mass", "link1"), ("point-mass", "link2")],
    "pendulum": [("point-mass", "bob")],
    "rp_arm": [], "rrr_arm": [], "spatial_arm": [], "ur5": [],
    # Panda: a damping of 0.003 per arm joint and 0.3 per finger (used only with --friction urdf), and its second
    # finger mimics the first: honoured (no coordinate of its own), which the note says.
    "panda": [("damping-friction", f"panda_joint{i}") for i in range(1, 8)]
    + [("damping-friction", "panda_finger_joint1"), ("mimic-joint", "panda_finger_joint2"),
       ("damping-friction", "panda_finger_joint2")],
    # example-robot-data's double pendulum is a CAD export: lower = upper = 0 and effort = velocity = 0 on both
    # revolute joints (so a limit-enforcing engine holds it still), and a damping of 0.05.
    "double_pendulum": [(rule, joint) for joint in ("joint1", "joint2") for rule in
                        ("zero-range", "zero-effort-velocity", "zero-effort-velocity", "damping-friction")],
    "double_pendulum_continuous": [(rule, joint) for joint in ("joint1", "joint2") for rule in
                                   ("zero-effort-velocity", "zero-effort-velocity", "damping-friction")],
}


def lint_text(tmp_path, text: str, name: str = "probe.urdf"):
    path = tmp_path / name
    path.write_text(text)
    return lint_urdf(path)


def test_every_class_has_a_mutated_urdf_and_the_unchanged_arm_has_no_finding(tmp_path):
    assert set(MUTATIONS) | UNREAD == set(CLASSES)
    assert lint_text(tmp_path, arm_urdf()).findings == ()
    assert {c.severity for c in CLASSES.values()} == set(SEVERITIES)


@pytest.mark.parametrize("rule", list(MUTATIONS))
def test_each_class_is_named_with_its_link_or_joint(tmp_path, rule):
    text, name = MUTATIONS[rule]
    report = lint_text(tmp_path, text)
    named = [f for f in report.findings if f.rule == rule]
    assert named, [(f.rule, f.name, f.message) for f in report.findings]
    assert name in {f.name for f in named}, [(f.name, f.message) for f in named]
    finding = next(f for f in named if f.name == name)
    assert finding.severity == CLASSES[rule].severity and finding.fix == CLASSES[rule].fix
    assert finding.line == 1 and finding.message  # these files are one line
    assert report.fails("error") == any(f.severity == "error" for f in report.findings)
    assert {f.rule for f in report.findings} <= {rule} | ALSO.get(rule, set())  # one thing changed, one class


# What a mutation also brings, of necessity: a robot with no inertial has links with none; an <inertial> without
# its <mass> has mass 0 under its inertia; 2700 kg (aluminium in grams) on a joint of 1 N m is beyond its effort.
# (An inertia with a negative moment that also breaks the triangle
# inequality is one finding: one per tensor.)
ALSO = {"no-mass": {"missing-inertial"}, "joint-carries-nothing": {"missing-inertial"},
        "incomplete-inertial": {"zero-mass"}, "units-slip": {"mass-beyond-effort"},
        "mimic-pinocchio-cannot-build": {"mimic-joint"}}


@pytest.mark.parametrize("robot", list(robot_names()))
def test_the_shipped_robots_lint_without_an_error_and_with_the_findings_reviewed(robot):
    report = lint_urdf(robot_path(robot))
    assert not report.fails("error")
    assert [(f.rule, f.name) for f in report.findings] == SHIPPED[robot]


def test_panda_mimic_finding_says_how_it_is_read():
    finding = next(f for f in lint_urdf(robot_path("panda")).findings if f.rule == "mimic-joint")
    assert "honoured, it moves with that joint's coordinate and has none of its own" in finding.message
    assert "panda_finger_joint1" in finding.message and finding.severity == "note"


@pytest.mark.parametrize("case", [c for c in BAD_URDFS if c != "malformed XML"])
def test_what_the_loader_refuses_is_an_error_finding_with_exit_1(tmp_path, capsys, case):
    (tmp_path / "bad.urdf").write_text(BAD_URDFS[case][0])
    code, out, err = run(capsys, "lint", str(tmp_path / "bad.urdf"))
    assert code == 1 and " error [" in out and not err, (out, err)


@pytest.mark.parametrize("text, fragment", [
    ('<robot name="x"><link name="a"></robot>', "malformed XML"),
    ('<?xml version="1.0"?><sdf version="1.6"><model name="x"/></sdf>', "not a URDF: its root element is <sdf>"),
    ("", "empty file"),
])
def test_a_file_that_is_no_urdf_is_one_error_line_with_exit_2(tmp_path, capsys, text, fragment):
    (tmp_path / "no.urdf").write_text(text)
    assert_one_line_error(*run(capsys, "lint", str(tmp_path / "no.urdf"))[::2], fragment)


def test_a_file_over_the_loaders_size_limit_is_exit_2(tmp_path, capsys, monkeypatch):
    import course_dynamics.core.urdf as urdf

    monkeypatch.setattr(urdf, "MAX_URDF_BYTES", 100)
    (tmp_path / "big.urdf").write_text(arm_urdf())
    assert_one_line_error(*run(capsys, "lint", str(tmp_path / "big.urdf"))[::2], "big.urdf", "100")


def test_exit_status_follows_fail_on(tmp_path, capsys):
    (tmp_path / "warned.urdf").write_text(MUTATIONS["axis-not-unit"][0])
    (tmp_path / "noted.urdf").write_text(MUTATIONS["point-mass"][0])
    assert run(capsys, "lint", str(tmp_path / "warned.urdf"))[0] == 0
    assert run(capsys, "lint", str(tmp_path / "warned.urdf"), "--fail-on", "warning")[0] == 1
    assert run(capsys, "lint", str(tmp_path / "noted.urdf"), "--fail-on", "warning")[0] == 0
    assert run(capsys, "lint", str(tmp_path / "noted.urdf"), "--fail-on", "note")[0] == 1
    code, out, _ = run(capsys, "lint", str(tmp_path / "warned.urdf"))
    assert "warning [axis-not-unit] joint 'joint2': axis [0.0, 0.0, 2.0] has length 2" in out
    assert f"    fix: {CLASSES['axis-not-unit'].fix}" in out
    assert out.strip().endswith("robot 'probe': 0 errors, 1 warning, 0 notes")


def multiline_urdf() -> str:
    """The arm with every tag on lines of its own, and joint2's attributes on three lines."""
    text = arm_urdf(axis="0 0 3").replace("><", ">\n<")
    return text.replace('<joint name="joint2" type="revolute">', '<joint\n  name="joint2"\n  type="revolute">')


def test_json_and_sarif_give_each_finding_with_the_line_its_element_starts_on(tmp_path, capsys):
    path = tmp_path / "arm.urdf"
    path.write_text(multiline_urdf())
    start = path.read_text().splitlines().index("<joint") + 1
    code, out, _ = run(capsys, "lint", str(path), "--json", "--sarif", str(tmp_path / "lint.sarif"))
    document = json.loads(out)
    assert code == 0 and document["ok"] and document["fail_on"] == "error"
    (report,) = document["files"]
    assert (report["robot"], report["errors"], report["warnings"], report["notes"]) == ("probe", 0, 1, 0)
    (finding,) = report["findings"]
    assert finding == dict(rule="axis-not-unit", severity="warning", element="joint", name="joint2", line=start,
                           message="joint 'joint2': axis [0.0, 0.0, 3.0] has length 3",
                           fix=CLASSES["axis-not-unit"].fix)
    log = json.loads((tmp_path / "lint.sarif").read_text())
    assert log["version"] == "2.1.0"
    (run_,) = log["runs"]
    assert [r["id"] for r in run_["tool"]["driver"]["rules"]] == list(CLASSES)
    assert {r["id"]: r["defaultConfiguration"]["level"] for r in run_["tool"]["driver"]["rules"]} == {
        c.name: c.severity for c in CLASSES.values()}
    (result,) = run_["results"]
    assert (result["ruleId"], result["level"]) == ("axis-not-unit", "warning")
    assert run_["tool"]["driver"]["rules"][result["ruleIndex"]]["id"] == "axis-not-unit"
    assert result["message"]["text"].startswith("joint 'joint2': axis [0.0, 0.0, 3.0] has length 3")
    location = result["locations"][0]["physicalLocation"]
    assert location == dict(artifactLocation=dict(uri=path.as_uri()), region=dict(startLine=start))


def test_sarif_of_a_relative_path_is_a_relative_uri(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "arm.urdf").write_text(MUTATIONS["mimic-joint"][0])
    result = sarif([lint_urdf("arm.urdf")])["runs"][0]["results"][0]
    assert result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "arm.urdf"


def test_a_units_slip_names_the_likely_unit():
    findings = {}
    for name, text in (("grams", with_box("0.1 0.1 0.1", mass="2700")),
                       ("millimetres", with_box("100 100 100", at="100 0 0", mass="2.7")),
                       ("kg mm^2", with_box("0.1 0.1 0.1", ixx="10", iyy="10", izz="10"))):
        import tempfile
        from pathlib import Path

        with tempfile.TemporaryDirectory() as folder:
            findings[name] = [f.message for f in lint_text(Path(folder), text).findings if f.rule == "units-slip"]
    assert "the mass in grams?" in findings["grams"][0]
    assert "the shapes in millimetres?" in findings["millimetres"][0]
    assert "kg mm^2" in findings["kg mm^2"][0]


def test_inertial_rpy_gives_the_tensor_in_the_links_axes(tmp_path):
    text = second(arm_urdf(ixx="0.01", iyy="0.02", izz="0.025"), 'rpy="0 0 0"/><mass',
                  'rpy="0 0 1.5707963267948966"/><mass')
    (finding,) = [f for f in lint_text(tmp_path, text).findings if f.rule == "inertial-rpy"]
    assert 'ixx="0.02" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.025"' in finding.message


def test_validate_and_terms_warn_of_a_joint_that_carries_nothing(tmp_path, capsys):
    path = tmp_path / "empty.urdf"
    path.write_text(MUTATIONS["joint-carries-nothing"][0])
    (finding,) = mass_findings(load(path))
    assert (finding.rule, finding.name) == ("joint-carries-nothing", "joint2")
    code, out, err = run(capsys, "terms", str(path), "--q", "0,0")
    assert code == 0 and "warning: robot 'probe': joint 'joint2' moves link 'link2'" in err
    assert "[joint-carries-nothing]" in err
    code, out, err = run(capsys, "validate", str(path), "--samples", "3", "--quiet")
    assert code == 0
    assert out.splitlines()[-1].startswith("all robots agree, but empty.urdf: no mass where a joint moves")
    assert "[joint-carries-nothing]" in err
    code, out, err = run(capsys, "validate", str(path), "two_link", "--samples", "3", "--quiet", "--json")
    assert json.loads(out)["massless"] == ["empty.urdf"]


def test_a_robot_without_any_mass_is_one_no_mass_warning(tmp_path, capsys):
    path = tmp_path / "fanuc.urdf"
    path.write_text(MUTATIONS["no-mass"][0])
    assert [f.rule for f in mass_findings(load(path))] == ["no-mass"]
    code, out, err = run(capsys, "terms", str(path), "--q", "0,0")
    assert "warning: robot 'probe': no link it moves has a mass or an inertia" in err and "[no-mass]" in err


def test_a_shipped_robot_with_its_masses_draws_no_mass_warning(capsys):
    for robot in robot_names():
        assert mass_findings(load(robot)) == [], robot
    code, out, err = run(capsys, "terms", "two_link", "--q", "0,0")
    assert code == 0 and "carries" not in err and "no-mass" not in err


def test_lint_with_no_argument_lints_every_shipped_robot(capsys):
    code, out, err = run(capsys, "lint", "--json")
    assert code == 0
    assert [f["robot"] for f in json.loads(out)["files"]] == [
        lint_urdf(robot_path(name)).robot for name in robot_names()]


def test_joints_and_links_are_read_whatever_the_others_hold(tmp_path):
    """Two findings in one file, of different elements, are both reported (the linter does not stop at one)."""
    rules = {(f.rule, f.name) for f in lint_text(tmp_path, arm_urdf(mass="-1", axis="0 0 0")).findings}
    assert {("negative-mass", "link2"), ("zero-axis", "joint2")} <= rules


def test_the_inertial_rpy_fix_gives_the_same_body(tmp_path):
    """Writing the tensor the finding gives, with rpy="0 0 0", loads the same inertia (to its 12 printed digits)."""
    import re

    text = second(arm_urdf(), 'rpy="0 0 0"/><mass', 'rpy="0.3 -0.2 0.5"/><mass').replace(
        'ixx="0.01" iyy="0.01" izz="0.01" ixy="0"', 'ixx="0.03" iyy="0.02" izz="0.025" ixy="0.004"')
    (tmp_path / "rotated.urdf").write_text(text)
    (finding,) = [f for f in lint_urdf(tmp_path / "rotated.urdf").findings if f.rule == "inertial-rpy"]
    entries = " ".join(re.findall(r'i[xyz]{2}="[^"]*"', finding.message))
    fixed = text.replace('rpy="0.3 -0.2 0.5"/><mass', 'rpy="0 0 0"/><mass')
    start = fixed.index("<inertia ", fixed.index('<link name="link2">'))
    fixed = fixed[:start] + f"<inertia {entries}/>" + fixed[fixed.index("</inertial>", start):]
    (tmp_path / "fixed.urdf").write_text(fixed)
    assert lint_urdf(tmp_path / "fixed.urdf").findings == ()
    rotated, unrotated = load(tmp_path / "rotated.urdf").bodies[1].I_com, load(tmp_path / "fixed.urdf").bodies[1].I_com
    assert abs(rotated - unrotated).max() <= 1e-9 * abs(rotated).max()


def test_the_site_lists_every_class_with_its_severity_and_fix():
    page = (ROOT / "docs" / "guides" / "engineer-lint.md").read_text()
    rows = [line for line in page.splitlines() if line.startswith("| `")]
    assert rows == [f"| `{c.name}` | {c.severity} | {c.summary} | {c.fix} |" for c in CLASSES.values()]


def test_a_robot_name_with_a_control_character_is_unusable(tmp_path):
    report = lint_text(tmp_path, arm_urdf().replace('name="probe"', 'name="pro&#10;be"'))
    assert [(f.rule, f.element) for f in report.findings] == [("unusable-name", "robot")]


def ur5_with(pattern: str, scale: float, text: str | None = None) -> str:
    """The shipped UR5 (its links drawn by meshes only), or ``text``, with every number of the attributes
    ``pattern`` matches multiplied by ``scale``."""
    import re

    def scaled(match):
        numbers = " ".join(repr(float(x) * scale) for x in match.group(2).split())
        return f'{match.group(1)}="{numbers}"'

    return re.sub(pattern, scaled, robot_path("ur5").read_text() if text is None else text)


ORIGIN_XYZ = r'(<origin[^>]*? xyz)="([^"]*)"'


@pytest.mark.parametrize("slip, pattern, scale, rule, words", [
    ("grams", r'(<mass value)="([^"]*)"', 1e3, "units-slip", "masses in grams"),
    ("kg mm^2", r'(i[xyz]{2})="([^"]*)"', 1e6, "units-slip", "kg mm^2"),
    ("millimetres", ORIGIN_XYZ, 1e3, "units-slip", "lengths in millimetres"),
    ("SolidWorks' mm, g", ORIGIN_XYZ, 1e3, "units-slip", "lengths in millimetres"),
    ("1e-300 kg", r'(<mass value)="(2.275)"', 1e-300, "gyration-exceeds-link", "the mass too small"),
    ("1e-320 kg", r'(<mass value)="(2.275)"', 1e-320, "gyration-exceeds-link", "beyond 1e308 m"),
    ("1e9 kg", r'(<mass value)="(2.275)"', 1e9 / 2.275, "mass-beyond-effort", "times its effort limit 150 N m"),
])
def test_a_units_slip_is_found_on_a_robot_drawn_by_meshes_only(tmp_path, slip, pattern, scale, rule, words):
    text = ur5_with(pattern, scale)
    if slip.startswith("SolidWorks"):   # and the masses in grams, the inertias in g mm^2: consistent, but 1000 m long
        text = ur5_with(r'(i[xyz]{2})="([^"]*)"', 1e9, ur5_with(r'(<mass value)="([^"]*)"', 1e3, text))
    report = lint_text(tmp_path, text)
    assert [f.rule for f in report.findings] == [rule], [f.message for f in report.findings]
    assert words in report.findings[0].message
    assert lint_urdf(robot_path("ur5")).findings == ()


def test_a_robot_whose_masses_add_to_nothing_is_a_no_mass_error(tmp_path):
    report = lint_text(tmp_path, ur5_with(r'(<mass value)="([^"]*)"', 1e-300))
    (finding,) = [f for f in report.findings if f.severity == "error"]
    assert finding.rule == "no-mass" and "effectively none" in finding.message


def test_a_placeholder_mass_is_one_note_and_a_link_gets_one_diagnosis(tmp_path):
    """A sensor's 1 g in a 1 mm cube is a placeholder note, not a units slip; a link that fits its shapes neither
    in density nor in reach is diagnosed once."""
    (note,) = lint_text(tmp_path, MUTATIONS["placeholder-inertia"][0]).findings
    assert "a placeholder" in note.message and "0.0001 of the robot's 1 kg" in note.message
    assert not note.message.endswith("?")   # no units slip is blamed
    both = with_box("0.1 0.1 0.1", mass="2700", ixx="1e4", iyy="1e4", izz="1e4")   # grams, and 20 times its reach
    link2 = [f.rule for f in lint_text(tmp_path, both).findings if f.name == "link2"]
    assert link2 == ["units-slip"]


def test_an_inertia_the_loader_reads_is_checked_by_the_loaders_rule_once(tmp_path):
    """A tensor fixed to the base (the loader reads none) is a warning; a tensor breaking both tests is one
    finding; eigenvalue round-off is printed as 0."""
    text, _ = MUTATIONS["base-inertia-not-physical"]
    (tmp_path / "plate.urdf").write_text(text)
    load(tmp_path / "plate.urdf")   # loads: the plate moves nothing
    assert not lint_urdf(tmp_path / "plate.urdf").fails("error")
    (finding,) = lint_text(tmp_path, arm_urdf(ixx="-0.01")).findings   # negative, and -0.01 + 0.01 < 0.01
    assert finding.rule == "inertia-not-psd"
    rod = second(arm_urdf(ixx="1e-6", iyy="2e-6", izz="0"), 'ixy="0"', 'ixy="1.4142135623730951e-6"')  # rank 1
    (finding,) = lint_text(tmp_path, rod).findings
    assert finding.rule == "triangle-inequality" and "(principal moments 0, 0, 3e-06 kg m^2)" in finding.message


def test_what_urdfdom_reads_otherwise_is_a_finding(tmp_path):
    (padded,) = lint_text(tmp_path, MUTATIONS["padded-number"][0]).findings
    assert '<mass value="1.0 ">' in padded.message and "drops the <inertial>" in padded.message
    missing = [f for f in lint_text(tmp_path, MUTATIONS["incomplete-inertial"][0]).findings if f.severity == "error"]
    assert [f.rule for f in missing] == ["incomplete-inertial"] and "has no <mass>" in missing[0].message


def test_a_file_that_is_no_urdf_among_others_is_a_finding_and_the_rest_is_linted(tmp_path, capsys):
    (tmp_path / "log.csv").write_text("t,q1\n0,0\n")
    (tmp_path / "arm.urdf").write_text(MUTATIONS["point-mass"][0])
    code, out, err = run(capsys, "lint", str(tmp_path / "log.csv"), str(tmp_path / "arm.urdf"), "--json")
    assert code == 1 and not err
    unread, read = json.loads(out)["files"]
    assert [f["rule"] for f in unread["findings"]] == ["not-a-urdf"] and "malformed XML" in unread["findings"][0][
        "message"]
    assert [f["rule"] for f in read["findings"]] == ["point-mass"]
    code, out, err = run(capsys, "lint", str(tmp_path / "log.csv"), str(tmp_path / "missing.urdf"))
    assert code == 2 and out.count("error [not-a-urdf]") == 2 and not err


def test_sarif_on_standard_output_is_the_only_output(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "my robot#1.urdf").write_text(MUTATIONS["mimic-joint"][0])
    code, out, err = run(capsys, "lint", "my robot#1.urdf", "--sarif", "-")
    log = json.loads(out)   # one document, no text around it
    uri = log["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
    assert code == 0 and uri == "my%20robot%231.urdf"
    assert_one_line_error(*run(capsys, "lint", "my robot#1.urdf", "--sarif", "-", "--json")[::2],
                          "--sarif - and --json")


def test_the_wording_says_what_is_true(tmp_path):
    (empty,) = lint_text(tmp_path, '<robot name="ur3"/>').findings[:1]
    assert empty.rule == "not-a-tree" and "no <link> at all" in empty.message
    assert "continuous" not in CLASSES["huge-limits"].fix.split("(")[0]   # a prismatic joint has one too
    assert "MuJoCo and PyBullet" in CLASSES["axis-not-unit"].fix and "scale" not in CLASSES["axis-not-unit"].fix
    text = arm_urdf(mass="-1").replace("><", ">\n<")    # an inertial finding gives its link's line
    lines = text.splitlines()
    (finding,) = [f for f in lint_text(tmp_path, text).findings if f.rule == "negative-mass"]
    assert finding.line == lines.index('<link name="link2">') + 1


def test_what_the_loader_refuses_about_a_joint_is_on_that_joints_line(tmp_path):
    """A cycle of mimics: the refusal names joint 'ja' and points at its element, not at <robot>."""
    lines = ['<?xml version="1.0"?>', '<robot name="cycle">', '<link name="base"/>', LINK1, LINK2,
             JOINT.format(name="ja", type="revolute", parent="base", child="link1", axis="0 0 1").replace(
                 "</joint>", '<mimic joint="jb"/></joint>'),
             JOINT.format(name="jb", type="revolute", parent="link1", child="link2", axis="0 0 1").replace(
                 "</joint>", '<mimic joint="ja"/></joint>'), "</robot>"]
    refused = [f for f in lint_text(tmp_path, "\n".join(lines)).findings if f.rule == "refused"]
    assert [(f.element, f.name, f.line, f.severity) for f in refused] == [("joint", "ja", 6, "error")], refused
    assert "its mimics form a cycle" in refused[0].message


@pytest.mark.parametrize("mimic, fragment", [
    ('<mimic joint="joint1" multiplier="1e200"/>', "multiplier of 1e+200"),
    ('<mimic joint="joint1" multiplier="1e308"/>', "multiplier of 1e+308"),
    ('<mimic joint="joint1" multiplier="2"/><mimic joint="joint1" multiplier="3"/>', "2 <mimic> elements"),
])
def test_a_coupling_the_loader_refuses_is_an_error_on_the_mimics_line(tmp_path, capsys, mimic, fragment):
    (tmp_path / "bad.urdf").write_text(second(arm_urdf(), LIMIT, LIMIT + mimic))
    code, out, err = run(capsys, "lint", str(tmp_path / "bad.urdf"))
    assert code == 1 and not err and f"error [refused] joint 'joint2': " in out and fragment in out, out
