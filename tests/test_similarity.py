"""course_dynamics/grading/similarity: near-identical submissions found on the syntax tree, independent ones left alone."""
from __future__ import annotations

import json
import re

import pytest
from submissions import CLOSED_FORMS, NEWTON_EULER, spatial_newton_euler

from course_dynamics.cli import main
from course_dynamics.core.robots import load
from course_dynamics.grading.similarity import THRESHOLD, fingerprints, read_starter, similar_pairs


def disguised(source: str) -> str:
    """What a student does to a copy: new names, comments, other spacing, the functions in another order."""
    source = source.replace("c2", "cos_q2").replace("h = ", "coupling = ").replace("h *", "coupling *")
    source = source.replace("-h ", "-coupling ").replace("    a = ", "    # off-diagonal\n    off  =  ")
    source = source.replace(", a]", ", off]").replace("[a,", "[off,")
    header, *functions = re.split(r"\n(?=def )", source)
    return "# my own work\n" + header + "\n\n" + "\n\n\n".join(reversed(functions))


def scores(sources: dict[str, str], starter=None) -> dict[frozenset, float]:
    found = [fingerprints(name, text, starter) for name, text in sources.items()]
    return {frozenset((p.first.student, p.second.student)): p.score for p in similar_pairs(found, threshold=0.0)}


def test_a_disguised_copy_is_found_and_independent_work_is_not():
    assert disguised(CLOSED_FORMS) != CLOSED_FORMS
    found = scores({"ada": CLOSED_FORMS, "bob": disguised(CLOSED_FORMS), "cy": NEWTON_EULER,
                    "dee": spatial_newton_euler(load("spatial_arm"))})
    assert found[frozenset(("ada", "bob"))] == 1.0
    for pair in (("ada", "cy"), ("bob", "cy"), ("cy", "dee"), ("ada", "dee")):
        assert found.get(frozenset(pair), 0.0) < 0.5, (pair, found)  # one algorithm, written twice: short runs only


def test_the_starter_code_is_common_ground():
    v_given = CLOSED_FORMS[CLOSED_FORMS.index("def V"):CLOSED_FORMS.index("def G")]
    starter = CLOSED_FORMS.replace(v_given, "def V(q, qd):\n    pass\n\n\n")  # all but V given
    own_v = ("def V(q, qd):\n    s = np.sin(q[1])\n    k = m2 * l1 * l2 * s\n    first = -k * qd[1] ** 2 - 2 * k * qd[0] * qd[1]"
             "\n    return np.array([first, k * qd[0] ** 2])\n")
    other_v = ("def V(q, qd):\n    out = np.zeros(2)\n    for i in range(2):\n        out[i] = (1 - 2 * i) * m2 * l1 * l2 "
               "* np.sin(q[1]) * (qd[0] ** 2 if i else -(qd[1] ** 2 + 2 * qd[0] * qd[1]))\n    return out\n")
    given = fingerprints("starter", starter)
    alone = {"eve": starter.replace("def V(q, qd):\n    pass\n", own_v), "fay": starter.replace("def V(q, qd):\n    pass\n", other_v)}
    pair = frozenset(("eve", "fay"))
    assert scores(alone)[pair] > 0.7  # without the starter, what everyone was given makes two V's look alike
    assert scores(alone, given).get(pair, 0.0) < 0.2  # with it, only their own V's are compared
    copied = dict(alone, gus=alone["eve"].replace("first", "a"))
    assert scores(copied, given)[frozenset(("eve", "gus"))] == 1.0


def test_unparsable_and_tiny_files_are_never_listed():
    found = [fingerprints("x", "def tau(q, qd, qdd)\n"), fingerprints("y", "def tau(q, qd, qdd)\n"),
             fingerprints("z", "x = 1\n"), fingerprints("w", "x = 1\n")]
    assert similar_pairs(found) == []


def test_a_bad_starter_is_one_clear_line(tmp_path):
    from course_dynamics import CourseDynamicsError

    (tmp_path / "starter.py").write_text("def tau(:\n")
    with pytest.raises(CourseDynamicsError, match="starter.py: the starter file is not Python"):
        read_starter(tmp_path / "starter.py")
    with pytest.raises(CourseDynamicsError, match="no such starter file"):
        read_starter(tmp_path / "missing.py")


ASSIGNMENT = 'robot = "two_link"\nsamples = 4\ntime_limit = 5\n[points]\ntau = 10\nG = 10\n'


def test_grade_lists_pairs_with_a_side_by_side_page(tmp_path, capsys):
    hostile = "<script>alert(1)</script>"
    sources = {"ada": CLOSED_FORMS + f"\nNOTE = '{hostile}'\n", "bob": disguised(CLOSED_FORMS), "cy": NEWTON_EULER}
    for name, text in sources.items():
        (tmp_path / f"{name}.py").write_text(text)
    (tmp_path / "a.toml").write_text(ASSIGNMENT)
    out = tmp_path / "out"
    argv = ["grade", str(tmp_path / "a.toml"), *(str(tmp_path / f"{n}.py") for n in sources), "--out", str(out)]
    assert main(["grade", "--similarity", *argv[1:], "--quiet", "--json"]) == 0  # the flag anywhere
    report = json.loads(capsys.readouterr().out)
    assert report["similar"] == [{"students": ["ada", "bob"], "score": 1.0, "page": "similar-1.html"}]
    page = (out / "similar-1.html").read_text()
    assert "<mark>" in page and "ada" in page and "bob" in page and hostile not in page and "a lead, not a verdict" in page
    summary = (out / "summary.html").read_text()
    assert "Similar submissions" in summary and 'href="similar-1.html"' in summary
    assert "from a score of 0.8" in summary and "no starter code given" in summary and "no starter code" in page
    assert [p.name for p in out.glob("similar-*.html")] == ["similar-1.html"]
    assert main([*argv[:-3], *argv[-2:], "--quiet"]) == 0  # one student fewer, without --similarity: no table
    assert "Similar submissions" not in (out / "summary.html").read_text()
    assert "still holds the feedback an earlier grade wrote for 1 student not graded now (cy)" in capsys.readouterr().err


@pytest.mark.parametrize("extra, message", [(["--similarity-threshold", "0"], "from 0 (exclusive) to 1"),
                                            (["--similarity-threshold", "1.5"], "from 0 (exclusive) to 1"),
                                            (["--starter", "missing.py"], "no such starter file")])
def test_bad_similarity_options(tmp_path, capsys, monkeypatch, extra, message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "ada.py").write_text(CLOSED_FORMS)
    (tmp_path / "a.toml").write_text(ASSIGNMENT)
    assert main(["grade", "a.toml", "ada.py", "--out", "out", *extra]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and message in err and err.count("\n") == 1
    assert not (tmp_path / "out").exists()


def test_a_student_named_like_a_similarity_page_is_refused(tmp_path, capsys):
    (tmp_path / "similar-1.py").write_text(CLOSED_FORMS)
    (tmp_path / "a.toml").write_text(ASSIGNMENT)
    assert main(["grade", str(tmp_path / "a.toml"), str(tmp_path / "similar-1.py"), "--out", str(tmp_path / "o")]) == 2
    assert "would overwrite the class's similar-1 file" in capsys.readouterr().err


def test_hostile_sources_cannot_stop_the_comparison():
    """A literal with no repr, a flood of tokens: each file is compared as far as it goes, the class still is."""
    huge = "BIG = 0x" + "f" * 4000 + "\n" + CLOSED_FORMS
    flood = "x = [" + "1, " * 300_000 + "]\n"
    found = [fingerprints("a", huge), fingerprints("b", CLOSED_FORMS), fingerprints("c", flood)]
    assert {frozenset((p.first.student, p.second.student)) for p in similar_pairs(found)} == {frozenset("ab")}


def test_imported_names_are_compared_and_pass_is_nothing():
    cosines = "from numpy import cos, log, array\n" + CLOSED_FORMS.replace("np.cos", "cos")
    logs = "from numpy import cos, log, array\n" + CLOSED_FORMS.replace("np.cos", "log")
    padded = "\n".join(line + ("\n    pass" if line.startswith("    ") and not line.rstrip().endswith(",") else "")
                       for line in cosines.splitlines())
    found = scores({"cos": cosines, "log": logs, "padded": padded})
    assert found[frozenset(("cos", "padded"))] == 1.0
    assert found[frozenset(("cos", "log"))] < found[frozenset(("cos", "padded"))]


def test_code_the_package_generates_for_the_robot_is_flagged_with_a_side_by_side_page(tmp_path, capsys):
    """derive's closed forms (each format, pasted by hand) and the compiled model's module: flagged, never scored
    down; a student's own Newton-Euler is not."""
    from generated import FORMATS, compiled_submission, derived_submission

    (tmp_path / "a.toml").write_text('robot = "two_link"\nsamples = 3\n[points]\ntau = 100\n')
    sources = {f"derive_{fmt}": derived_submission("two_link", fmt) for fmt in FORMATS}
    sources["numpy_prefixed"] = sources["derive_json"].replace("from numpy import cos, sin\n", "").replace(
        "sin(", "np.sin(").replace("cos(", "np.cos(")
    sources |= {"compiled": compiled_submission(load("two_link")), "own": NEWTON_EULER}
    for name, text in sources.items():
        (tmp_path / f"{name}.py").write_text(text)
    out = tmp_path / "out"
    assert main(["grade", str(tmp_path / "a.toml"), *(str(tmp_path / f"{n}.py") for n in sources), "--out", str(out),
                 "--similarity", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    flags = {s["student"]: s["flags"] for s in record["students"]}
    totals = {s["student"]: s["total"] for s in record["students"]}
    assert all(flags[n] == ["generated-code"] for n in sources if n != "own"), flags
    assert flags["own"] == [] and set(totals.values()) == {100.0}  # a flag never changes a score
    pages = {tuple(p["students"]): p["page"] for p in record["similar"]}
    assert ("compiled", "generated: compiled model") in pages and ("derive_latex", "generated: derive (joint names)") \
        in pages, pages
    page = (out / pages["compiled", "generated: compiled model"]).read_text()
    assert "the code course-dynamics generates for their robot" in page and "<mark>" in page
    with open(out / "gradebook.csv") as handle:
        assert "generated-code" in handle.read()
