"""course_dynamics/grading: a class of submissions written for the tests, graded through the CLI.

Every scoring pattern must be named in the feedback and every hostile behaviour
must end in a clear status with no points, while nothing is written outside the
output folder and nothing the submissions started is left running.
"""
from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest
from submissions import (
    CLOSED_FORMS,
    FILL_MOUNTS,
    FLAGGED,
    HIDDEN_MEMORY,
    HOSTILE,
    INJECTION,
    INJECTION_NAME,
    ODD_ANSWERS,
    PROCESSES,
    SCORING,
    SNOOP,
)

from course_dynamics import CourseDynamicsError
from course_dynamics.cli import main
from course_dynamics.grading import EXAMPLE, load_assignment

ASSIGNMENT = """\
robot = "two_link"
samples = 12
seed = 3
tolerance = 1e-6
time_limit = 1
memory_limit = 512
output_limit = 100000
[points]
tau = 40
M = 20
V = 20
G = 10
C = 10
"""
POINTS = {"tau": 40, "M": 20, "V": 20, "G": 10, "C": 10}
SLEEPS = (b"sleep\x004242", b"sleep\x004243", b"sleep\x004244")


def write_class(root: Path, sources: dict[str, str]) -> list[Path]:
    """One folder per student, as a class would hand the files in."""
    paths = []
    for name, source in sources.items():
        folder = root / "submissions" / f"student_{len(paths):02d}"
        folder.mkdir(parents=True)
        (folder / f"{name}.py").write_text(source)
        paths.append(folder / f"{name}.py")
    (root / "assignment.toml").write_text(ASSIGNMENT)
    return paths


def snapshot(root: Path, skip: Path) -> dict[str, bytes]:
    return {str(p): p.read_bytes() for p in root.rglob("*") if p.is_file() and skip not in p.parents}


def running_sleeps() -> list[str]:
    found = []
    for cmdline in Path("/proc").glob("[0-9]*/cmdline"):
        try:
            text = cmdline.read_bytes()
        except OSError:
            continue
        if any(text.startswith(s) for s in SLEEPS):
            found.append(text.decode(errors="replace"))
    return found


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    root = tmp_path_factory.mktemp("class")
    sources = {name: spec[0] for name, spec in SCORING.items()} | {name: spec[0] for name, spec in HOSTILE.items()}
    sources |= {"processes": PROCESSES, "snoop": SNOOP, INJECTION_NAME: INJECTION, "fill_mounts": FILL_MOUNTS,
                "hidden_memory": HIDDEN_MEMORY, "odd_answers": ODD_ANSWERS}
    sources |= {name: spec[0] for name, spec in FLAGGED.items()}
    paths = write_class(root, sources)
    out = root / "out"
    before = snapshot(root, out)
    code = main(["grade", str(root / "assignment.toml"), *map(str, paths), "--out", str(out), "--quiet"])
    with open(out / "gradebook.csv", newline="") as handle:
        book = {row["student"]: row for row in csv.DictReader(handle)}
    return dict(root=root, out=out, code=code, before=before, book=book)


def feedback(graded, name: str) -> str:
    """The student's Markdown feedback with Markdown's escapes removed, as a reader sees it."""
    return (graded["out"] / f"{name}.md").read_text().replace("\\", "")


def test_gradebook_has_every_student_and_sums_its_terms(graded):
    assert graded["code"] == 0
    with open(graded["out"] / "gradebook.csv", newline="") as handle:
        header = next(csv.reader(handle))
    assert header == ["student", "tau", "M", "V", "G", "C", "total", "status", "sandbox", "flags"]
    assert len(graded["book"]) == len(SCORING) + len(HOSTILE) + len(FLAGGED) + 6
    for row in graded["book"].values():
        assert float(row["total"]) == pytest.approx(sum(float(row[t]) for t in POINTS))
        assert row["sandbox"] == "bubblewrap"


@pytest.mark.parametrize("name", sorted(SCORING))
def test_scoring_pattern_is_scored_and_named(graded, name):
    _, status, losing, words = SCORING[name]
    row = graded["book"][name]
    assert row["status"] == status
    for term, full in POINTS.items():
        points = float(row[term])
        if term not in losing:
            assert points == full, (term, feedback(graded, name))
        elif losing[term] == 0:
            assert points == 0, (term, feedback(graded, name))
        else:
            assert 0 < points < full, (term, feedback(graded, name))
    text = feedback(graded, name)
    for word in words:
        assert word in text, (word, text)
    if losing:  # a state to check against, with our answer (and the student's, where there is one)
        assert "state #" in text and "expected" in text


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_hostile_submission_gets_a_clear_status_and_zero(graded, name):
    _, status, words = HOSTILE[name]
    row = graded["book"][name]
    assert row["status"] == status, feedback(graded, name)
    assert float(row["total"]) == 0
    text = feedback(graded, name)
    for word in words:
        assert word in text, (word, text)


def test_nothing_the_submissions_started_survives(graded):
    assert running_sleeps() == []
    printed = feedback(graded, "processes")
    assert "fork refused after" in printed  # the process limit held
    children = int(printed.split("fork refused after")[1].split()[0])
    assert children < 100


def test_a_submission_sees_only_itself_and_no_network(graded):
    printed = feedback(graded, "snoop")
    assert "/submission ['snoop.py']" in printed
    for other in ("closed_forms", "newton_euler", "gradebook", "assignment.toml"):
        assert other not in printed
    assert "network: Network is unreachable" in printed
    for hidden in ("/etc/shadow", "/etc/shadow-", "/etc/gshadow-", "/proc/self/mountinfo", "/proc/1/cmdline"):
        assert f"{hidden} has" not in printed and f"{hidden} unreadable" in printed
    etc = eval(printed.split("/etc ", 1)[1].splitlines()[0])  # the listing the submission printed
    assert set(etc) <= {"ld.so.cache", "ld.so.conf", "ld.so.conf.d", "alternatives", "localtime"}, etc


def test_no_writable_mount_holds_more_than_its_share_of_the_memory_limit(graded):
    """Without a memory cgroup a tmpfs of half the RAM would let a submission fill the host's memory."""
    printed = feedback(graded, "fill_mounts")
    filled = {line.split()[1]: int(line.split()[2]) for line in printed.splitlines() if line.startswith("filled ")}
    assert set(filled) == {"/dev/shm", "/tmp", "/scratch", "/", "/dev"}
    assert filled["/"] == filled["/dev"] == 0
    memory_limit = 512  # MiB, ASSIGNMENT's
    assert sum(filled.values()) <= memory_limit, filled
    assert graded["book"]["fill_mounts"]["status"] == "ok"


def test_memory_outside_the_limits_cannot_be_taken(graded):
    """A memfd or a System V segment would hold memory no address-space limit or mount size counts."""
    printed = feedback(graded, "hidden_memory")
    assert "memfd: Operation not permitted" in printed and "shmget: Operation not permitted" in printed


def test_odd_answers_are_graded_not_mislabelled(graded):
    row = graded["book"]["odd_answers"]
    assert row["status"] == "ok" and float(row["G"]) == 0 and float(row["M"]) == 0
    assert "4 dimensions" in feedback(graded, "odd_answers")


def test_the_sandbox_shows_no_other_software(graded):
    """Only what a Python needs of /usr: no other program's vendored packages, no site folders via /lib."""
    printed = feedback(graded, "snoop")
    usr = eval(printed.split("/usr ", 1)[1].splitlines()[0])
    assert set(usr) <= {"bin", "lib", "lib64", "sbin"}, usr
    assert "/lib/python3/dist-packages exists: False" in printed


def test_forged_results_affect_only_their_own_grade(graded):
    """Submissions that wrote the results channel themselves: the class is graded, each of them is invalid."""
    assert graded["code"] == 0
    forged = [name for name in graded["book"] if name.startswith("forged_")]
    assert len(forged) == 6
    assert all(graded["book"][name]["status"] == "invalid result" for name in forged)
    assert graded["book"]["closed_forms"]["total"] == "100"
    with open(graded["out"] / "gradebook.csv", newline="") as handle:
        text = handle.read()
    assert "HYPERLINK" not in text


def test_gradebook_cells_from_students_are_never_formulas():
    from course_dynamics.grading.feedback import spreadsheet_text

    for name in ("=1+1", "+1", "-1", "@SUM(A1)", "\t=1+1", "\r=1+1", " =1+1", "|cmd"):
        assert spreadsheet_text(name).startswith("'"), name
    assert spreadsheet_text("alice") == "alice" and spreadsheet_text("o'brien") == "o'brien"


def test_nothing_is_written_outside_the_output_folder(graded):
    assert snapshot(graded["root"], graded["out"]) == graded["before"]


def test_every_student_gets_markdown_html_and_gradescope_json(graded):
    for student in graded["book"]:
        for suffix in (".md", ".html", ".json"):
            path = graded["out"] / f"{student}{suffix}"
            assert path.is_file() and path.stat().st_size < 1_000_000
        result = json.loads((graded["out"] / f"{student}.json").read_text())
        assert set(result) >= {"score", "tests"}
        assert [t["name"] for t in result["tests"]] == [*POINTS, "integrity flags (instructors only)"]
        assert all(set(t) >= {"name", "score", "max_score", "output", "visibility"} for t in result["tests"])
        assert result["tests"][-1]["visibility"] == "hidden" and result["tests"][-1]["max_score"] == 0
        assert result["score"] == pytest.approx(sum(t["score"] for t in result["tests"]))


@pytest.mark.parametrize("name", sorted(FLAGGED))
def test_what_a_submission_tried_is_flagged_without_changing_its_score(graded, name):
    _, codes = FLAGGED[name]
    row = graded["book"][name]
    assert row["status"] == "ok" and row["total"] == "100", feedback(graded, name)
    assert row["flags"] == ";".join(codes)
    hidden = json.loads((graded["out"] / f"{name}.json").read_text())["tests"][-1]["output"]
    assert all(f"[{code}]" in hidden for code in codes) and (codes or hidden == "none")
    assert "integrity" not in feedback(graded, name)  # the student's page says nothing unless the instructor asks


def test_honest_submissions_are_never_flagged(graded):
    for name in SCORING:
        assert graded["book"][name]["flags"] == "", (name, graded["book"][name]["flags"])


def test_hostile_submissions_are_flagged_for_what_they_tried(graded):
    flags = {name: set(graded["book"][name]["flags"].split(";")) for name in ("tamper", "path_hunt", "snoop",
                                                                               "processes", "hidden_memory")}
    assert "file-write" in flags["tamper"]
    assert "list-folder" in flags["path_hunt"]
    assert {"list-folder", "file-read", "socket"} <= flags["snoop"]
    assert "process" in flags["processes"] and "ctypes" in flags["hidden_memory"]
    summary = (graded["out"] / "summary.html").read_text()
    assert "Integrity flags" in summary and "/root/.bashrc" in summary and "not proof" in summary
    unwatched = summary.split("Not run, so not watched: ")[1].split(" (refused")[0].split(", ")
    assert {"syntax_error", "forbidden_import"} <= set(unwatched)
    assert "crash" not in unwatched and "forbidden_hidden" not in unwatched  # a computed name is found only by running


def test_flags_reach_the_student_only_when_the_assignment_says_so(tmp_path):
    paths = write_class(tmp_path, {"reads_home": FLAGGED["reads_home"][0]})
    (tmp_path / "assignment.toml").write_text(ASSIGNMENT.replace("[points]", "flags_in_feedback = true\n[points]"))
    out = tmp_path / "out"
    assert main(["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(out), "--quiet"]) == 0
    assert "integrity flag [file-read]" in feedback({"out": out}, "reads_home")
    assert "/root/.bashrc" in json.loads((out / "reads_home.json").read_text())["output"]


def tagged(nonce: str, *bodies: bytes, start: int = 0) -> bytes:
    """Lines as the integrity hook writes them: each tagged under the next key from ``nonce``."""
    from course_dynamics.grading.integrity import first_key, next_key, tag

    key, out = first_key(nonce), b""
    for _ in range(start):
        key = next_key(key)
    for body in bodies:
        out, key = out + b"\n" + body + b"\t" + tag(key, body) + b"\n", next_key(key)
    return out


def test_the_flag_channel_is_read_as_hostile():
    import hashlib

    from course_dynamics.grading.results import FLAGS_BYTES, read_flags

    results = b'{"status": "ok"}'
    end = b"end\t" + hashlib.sha256(results).hexdigest().encode()
    assert read_flags(tagged("N", b"file-read\t/etc/x", end), "N", results) == [("file-read", "/etc/x")]
    assert read_flags(tagged("N", b"file-read\t/etc/x"), "N", results) == [("file-read", "/etc/x"),
                                                                            ("channel-closed", "")]
    assert read_flags(b"", "N", None) == []  # no results: the status says what happened
    forged = tagged("N", b"made-up\tx", b"=HYPERLINK()\tx", b"channel-closed\tfake", b"end\twrong") + \
        tagged("N", b"socket\t" + b"x" * FLAGS_BYTES, start=4)
    flags = read_flags(forged, "N", results)
    assert flags == [("channel-closed", "")]  # the flood is cut off before its tag: no line of it is a flag
    assert read_flags(tagged("", end), "", results) == [("channel-closed", "")]  # an empty nonce never closes


def test_lines_the_submission_writes_on_the_flag_channel_are_not_flags():
    """Only lines tagged under the run's keys count: an untagged line, one tagged under another run's nonce, a line
    replayed, or anything after the closing line makes the channel ``channel-closed`` and is never a flag."""
    import hashlib

    from course_dynamics.grading.results import read_flags

    results = b'{"status": "ok"}'
    end = b"end\t" + hashlib.sha256(results).hexdigest().encode()
    honest = tagged("N", b"file-read\t/etc/x", end)
    written = [b"\nprocess\t<script>alert(2)</script>\n", tagged("other", b"process\tx"),
               tagged("N", b"file-read\t/etc/x")]  # untagged, another run's key, a replay of the first line
    for line in written:
        assert read_flags(honest[:-1] + line, "N", results) == [("file-read", "/etc/x"),
                                                                ("channel-closed", "written to by the submission")]
    early = tagged("N", end, b"process\tos.system true")  # a closing line that came before the end
    assert read_flags(early, "N", results) == [("channel-closed", "written to by the submission")]
    assert read_flags(tagged("N", b"end\t" + b"0" * 64), "N", results) == [("channel-closed", "")]  # other results


def test_one_oversized_term_costs_that_term_alone(tmp_path):
    """G returns 10 000 values (the harness would send them all back, more than the results document may hold):
    G alone is wrong, and M, V and tau (written without G) are still graded."""
    from submissions import OVERSIZED_G

    paths = write_class(tmp_path, {"oversized": OVERSIZED_G})
    (tmp_path / "assignment.toml").write_text(ASSIGNMENT.replace("samples = 12", "samples = 40").replace("C = 10\n", ""))
    out = tmp_path / "out"
    assert main(["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(out), "--quiet"]) == 0
    with open(out / "gradebook.csv", newline="") as handle:
        row = next(csv.DictReader(handle))
    assert row["status"] == "ok", row
    assert float(row["G"]) == 0 and float(row["M"]) == 20 and float(row["V"]) == 20 and float(row["tau"]) == 40, row
    assert "returned 10000 values" in (out / "oversized.md").read_text().replace("\\", "")


def test_student_text_is_escaped(graded):
    row = graded["book"][INJECTION_NAME]
    assert row["status"] == "crashed"
    for path in graded["out"].glob("*.html"):
        text = path.read_text()
        assert "<img" not in text and "<script>alert" not in text, path.name
    markdown = (graded["out"] / f"{INJECTION_NAME}.md").read_text()
    assert "<script>" not in markdown and "<img" not in markdown


def test_summary_shows_the_class(graded):
    summary = (graded["out"] / "summary.html").read_text()
    assert "<svg" in summary and "Score distribution" in summary
    assert "Most common mistakes" in summary and "gravity-sign" in summary
    assert "timeout" in summary and "forbidden import" in summary


def test_the_summary_lists_mistakes_the_same_way_every_run(graded):
    # Most common first, ties by name: a set's order (which changes from run to run) never shows.
    import re

    summary = (graded["out"] / "summary.html").read_text()
    table = summary.split("Most common mistakes", 1)[1].split("</table>", 1)[0]
    rows = [(name, int(count)) for name, count in re.findall(r"<tr><td>(.*?)</td><td>(\d+)</td></tr>", table)]
    assert len(rows) > 3 and rows == sorted(rows, key=lambda row: (-row[1], row[0]))


def test_without_a_sandbox_it_refuses_unless_asked(tmp_path, monkeypatch, capsys):
    import course_dynamics.grading.sandbox as sandbox

    paths = write_class(tmp_path, {"closed_forms": SCORING["closed_forms"][0], "processes": PROCESSES})
    monkeypatch.setattr(sandbox, "bwrap_executable", lambda: None)
    out = tmp_path / "out"
    code = main(["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: no sandbox") and "--no-sandbox" in err and err.count("\n") == 1
    assert not out.exists()
    code = main(["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(out), "--no-sandbox",
                 "--quiet"])
    assert code == 0 and "without a sandbox" in capsys.readouterr().err
    with open(out / "gradebook.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert [r["sandbox"] for r in rows] == ["none", "none"] and [r["total"] for r in rows] == ["100", "100"]
    assert "graded without a sandbox" in (out / "closed_forms.md").read_text()
    assert running_sleeps() == []


def test_without_a_sandbox_or_cgroups_nothing_a_submission_detached_survives(tmp_path, monkeypatch, capsys):
    import course_dynamics.grading.sandbox as sandbox

    monkeypatch.setattr(sandbox.ControlGroups, "_make", staticmethod(lambda *args: None))
    paths = write_class(tmp_path, {"processes": PROCESSES})
    try:
        code = main(["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(tmp_path / "out"),
                     "--no-sandbox", "--quiet"])
        assert code == 0
        assert running_sleeps() == []
    finally:
        import os
        import signal

        for cmdline in Path("/proc").glob("[0-9]*/cmdline"):  # never leave the sleeps behind, even on failure
            try:
                if any(cmdline.read_bytes().startswith(s) for s in SLEEPS):
                    os.kill(int(cmdline.parent.name), signal.SIGKILL)
            except OSError:
                pass


def test_without_a_sandbox_forbidden_packages_are_not_on_the_path(tmp_path, capsys):
    paths = write_class(tmp_path, {"guard_removed": HOSTILE["guard_removed"][0]})
    code = main(["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(tmp_path / "out"),
                 "--no-sandbox", "--quiet"])
    assert code == 0
    with open(tmp_path / "out" / "gradebook.csv", newline="") as handle:
        row = next(csv.DictReader(handle))
    assert row["status"] == "crashed" and row["total"] == "0"
    assert "No module named 'pinocchio'" in (tmp_path / "out" / "guard_removed.md").read_text().replace("\\", "")


def test_a_huge_or_special_submission_file_is_refused_without_reading_it(tmp_path):
    import os
    import time

    from course_dynamics.grading import load_assignment
    from course_dynamics.grading.grade import inspect_source

    write_class(tmp_path, {})
    assignment = load_assignment(tmp_path / "assignment.toml")
    sparse = tmp_path / "sparse.py"
    with open(sparse, "wb") as handle:
        handle.truncate(3 * 2**30)  # 3 GB that take no disk
    start = time.perf_counter()
    assert inspect_source(sparse, assignment)[0] == "not python"
    assert time.perf_counter() - start < 1
    fifo = tmp_path / "fifo.py"
    os.mkfifo(fifo)
    assert inspect_source(fifo, assignment) == ("not python", "not a regular file")


def test_example_assignment_is_a_valid_assignment(tmp_path, capsys):
    assert main(["grade", "--example-assignment"]) == 0
    text = capsys.readouterr().out
    assert text == EXAMPLE
    (tmp_path / "a.toml").write_text(text)
    assignment = load_assignment(tmp_path / "a.toml")
    assert assignment.terms == ("tau", "M", "V", "G") and assignment.robot.name == "two_link"


def test_the_assignment_sets_gravity_and_the_inertia_check(tmp_path):
    from helpers import arm_urdf

    (tmp_path / "planar.urdf").write_text(arm_urdf(ixx="0", iyy="0", izz="0.05"))
    (tmp_path / "a.toml").write_text("robot = 'planar.urdf'\ngravity = [0, -9.81, 0]\n"
                                     "allow_nonphysical_inertia = true\n[points]\ntau = 1\n")
    assignment = load_assignment(tmp_path / "a.toml")
    assert assignment.robot.gravity.tolist() == [0, -9.81, 0]
    (tmp_path / "a.toml").write_text("robot = 'planar.urdf'\n[points]\ntau = 1\n")
    with pytest.raises(CourseDynamicsError, match="--allow-nonphysical-inertia"):
        load_assignment(tmp_path / "a.toml")


def test_json_summary(tmp_path, capsys):
    paths = write_class(tmp_path, {"closed_forms": SCORING["closed_forms"][0], "only_gravity": SCORING["only_gravity"][0]})
    code = main(["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(tmp_path / "out"), "--json"])
    assert code == 0
    document = json.loads(capsys.readouterr().out)
    assert [s["total"] for s in document["students"]] == [100.0, 10.0]
    assert document["students"][1]["terms"]["G"] == 10.0


@pytest.mark.parametrize("text, message", [
    ("robot = 'two_link'\n", "[points] must give points"),
    ("robot = 'two_link'\n[points]\nJ = 3\n", "points: unknown term 'J'"),
    ("robot = 'two_link'\ncolour = 1\n[points]\ntau = 1\n", "unknown key 'colour'"),
    ("robot = 'two_link'\nsamples = 0\n[points]\ntau = 1\n", "samples must be positive"),
    ("robot = 'two_link'\ntolerance = -1\n[points]\ntau = 1\n", "tolerance must be positive"),
    ("robot = 'r2d2'\n[points]\ntau = 1\n", "robot 'r2d2' is neither a shipped robot"),
    ("robot = 'missing.urdf'\n[points]\ntau = 1\n", "missing.urdf: no such file"),
    ("robot = 'two_link'\npartial_credit = 'half'\n[points]\ntau = 1\n", "partial_credit must be one of states, none"),
    ("robot = \n", "not valid TOML"),
    ("robot = 'two_link'\ngravity = [0, 9.81]\n[points]\ntau = 1\n", "gravity must be three finite numbers"),
    ("robot = 'two_link'\nallow_nonphysical_inertia = 'yes'\n[points]\ntau = 1\n", "must be true or false"),
])
def test_bad_assignment_is_one_clear_line(tmp_path, capsys, text, message):
    (tmp_path / "a.toml").write_text(text)
    (tmp_path / "s.py").write_text(SCORING["closed_forms"][0])
    code = main(["grade", str(tmp_path / "a.toml"), str(tmp_path / "s.py"), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: ") and err.count("\n") == 1 and message in err, err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("argv, message", [
    (["grade"], "grade needs ASSIGNMENT.toml"),
    (["grade", "a.toml", "missing.py", "--out", "o"], "missing.py: no such submission file"),
    (["grade", "a.toml", "one/same.py", "two/same.py", "--out", "o"], "two submissions named 'same'"),
    (["grade", "a.toml", "one/same.py", "--out", "o", "--jobs", "0"], "--jobs must be at least 1"),
])
def test_bad_grade_arguments(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a.toml").write_text(ASSIGNMENT)
    for folder in ("one", "two"):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "same.py").write_text("x = 1\n")
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count("\n") == 1, err


def test_grading_from_a_python_installed_under_tmp(tmp_path):
    """A venv in /tmp (as CI makes one) stays visible in the sandbox, whose own /tmp is private.

    The venv sees this environment's packages through a .pth file: ``--system-site-packages`` would give it the
    base's, without those of a venv the tests run in."""
    import os
    import subprocess
    import sys

    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    purelib = subprocess.run([venv / "bin" / "python", "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                             capture_output=True, text=True, check=True).stdout.strip()
    outer = [p for p in sys.path if p.endswith(("site-packages", "dist-packages")) and os.path.isdir(p)]
    (Path(purelib) / "outer-environment.pth").write_text(f"import site; list(map(site.addsitedir, {outer!r}))\n")
    paths = write_class(tmp_path, {"closed_forms": SCORING["closed_forms"][0]})
    result = subprocess.run([venv / "bin" / "python", "-m", "course_dynamics.cli", "grade", str(tmp_path / "assignment.toml"),
                             *map(str, paths), "--out", str(tmp_path / "out"), "--json"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["students"][0]["total"] == 100.0


def test_the_sandbox_shows_the_standard_library_without_what_is_installed_beside_it(tmp_path):
    """This Python (pyenv) keeps site-packages inside its standard library's folder: a submission that removes the
    guard and goes looking there can neither list it, open a file in it nor import from it; without the sandbox,
    its path is the standard library's and numpy's alone."""
    from probes import NAMES, found, nothing_found, probe

    from course_dynamics.grading.environment import describe, base_interpreter
    from course_dynamics.grading.grade import grade_class

    paths = write_class(tmp_path, {"hunt": probe(), "trusting": probe(hunt=False)})
    assignment = load_assignment(tmp_path / "assignment.toml")
    hunt, trusting = grade_class(assignment, paths, sandbox=True)
    assert hunt.status == "ok" and nothing_found(found(hunt.stdout)) == [], hunt.stdout
    import os

    stdlib = os.path.dirname(os.__file__)
    assert found(hunt.stdout)["listed"][os.path.join(stdlib, "site-packages")] == "PermissionError"
    _, trusting = grade_class(assignment, paths, sandbox=False)
    report = found(trusting.stdout)
    assert trusting.status == "ok" and nothing_found(report) == []
    assert [p for p in report["path"][1:] if os.path.exists(p)] == describe(base_interpreter())["path"]
    assert set(report["imported"]) == set(NAMES)


def test_a_grader_reaching_its_packages_through_a_link_still_hides_those_of_the_standard_library(tmp_path):
    """The course in a venv over a Python with other packages in its base (conda-forge's Pinocchio): the base's
    site-packages is not on the grader's path under its own name, and is hidden all the same."""
    import os
    import subprocess
    import sys

    from probes import found, nothing_found, probe

    site = Path(np.__file__).resolve().parent.parent  # where this Python's packages are: inside its stdlib
    (tmp_path / "packages").symlink_to(site)
    paths = write_class(tmp_path, {"hunt": probe(folders=[site])})
    script = ("import json, site, sys\n"
              "sys.path[:] = [p for p in sys.path if not p.endswith('-packages')]\n"
              f"site.addsitedir({str(tmp_path / 'packages')!r})\n"
              "from course_dynamics.grading import grade_class, load_assignment\n"
              f"grade, = grade_class(load_assignment({str(tmp_path / 'assignment.toml')!r}), [{str(paths[0])!r}])\n"
              "print(json.dumps([grade.status, grade.stdout]))\n")
    result = subprocess.run([sys.executable, "-S", "-c", script], capture_output=True, text=True,
                            env={k: v for k, v in os.environ.items() if not k.startswith("PYTHON")})
    assert result.returncode == 0, result.stderr
    status, stdout = json.loads(result.stdout.splitlines()[-1])
    assert status == "ok" and nothing_found(found(stdout)) == [], stdout


@pytest.mark.parametrize("name, message", [
    (b"caf\xe9", "the file name is not UTF-8"),
    (b"new\nline", "holds a control character"),
    (b"tab\tname", "holds a control character"),
    ("\u202eevil".encode(), "holds a control character"),
    (b"x" * 220, "longer than 200 bytes"),
])
def test_a_file_name_that_cannot_name_a_student_is_one_clear_line(tmp_path, capsys, name, message):
    """Any bytes a file name can hold: refused before grading, never a traceback or a broken gradebook."""
    import os

    write_class(tmp_path, {})
    path = os.path.join(os.fsencode(tmp_path), name + b".py")
    with open(path, "w") as handle:
        handle.write(SCORING["closed_forms"][0])
    code = main(["grade", str(tmp_path / "assignment.toml"), os.fsdecode(path), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and err.startswith("error: ") and message in err, err
    assert "Traceback" not in err and not (tmp_path / "out").exists()


def test_grade_into_an_existing_folder_replaces_only_its_own_files(tmp_path, capsys):
    """An instructor's folder: a re-run replaces the class's files, never a file of theirs, and checks first."""
    paths = write_class(tmp_path, {"alice": SCORING["closed_forms"][0]})
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("the instructor's notes")
    argv = ["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(out), "--quiet"]
    assert main(argv) == 0 and main(argv) == 0  # the second run replaces what the first wrote
    assert (out / "notes.txt").read_text() == "the instructor's notes"
    (out / "alice.md").write_text("edited by hand")
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: ") and "alice.md" in err and err.count("\n") == 1, err
    assert (out / "alice.md").read_text() == "edited by hand"
    (out / "alice.md").unlink()
    (out / "bob.md").write_text("a file of the instructor's that a student's name would replace")
    paths = write_class(tmp_path / "again", {"bob": SCORING["closed_forms"][0]})
    code = main(["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "bob.md" in err and "not written by course-dynamics" in err
    assert (out / "bob.md").read_text().startswith("a file of the instructor's")


def test_one_submission_is_one_submission(tmp_path, capsys):
    paths = write_class(tmp_path, {"closed_forms": SCORING["closed_forms"][0]})
    assert main(["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(tmp_path / "out"),
                 "--quiet"]) == 0
    assert capsys.readouterr().out.startswith("graded 1 submission against two_link: mean 100 of 100 points")


def test_each_file_meets_states_of_its_own_so_a_table_of_answers_fails(tmp_path):
    """A student who learnt the states (from a seed, from feedback) and hard-codes the answers: the table's own
    bytes choose other states. The same file always gets the same states."""
    from course_dynamics import load_robot
    from course_dynamics.grading.plan import make_plan
    from course_dynamics.core.newton_euler import inverse_dynamics

    (tmp_path / "assignment.toml").write_text(ASSIGNMENT)
    assignment = load_assignment(tmp_path / "assignment.toml")
    honest = SCORING["closed_forms"][0]
    learnt = make_plan(assignment.for_submission("cheat", honest.encode()))  # the states the honest file met
    robot = load_robot("two_link")
    table = {tuple(np.round(np.r_[q, qd, qdd], 12)): inverse_dynamics(robot, q, qd, qdd).tolist()
             for q, qd, qdd in zip(learnt.q, learnt.qd, learnt.qdd)}
    cheat = ("import numpy as np\nTABLE = " + repr(table) + "\n\ndef tau(q, qd, qdd):\n"
             "    return np.array(TABLE.get(tuple(np.round(np.r_[q, qd, qdd], 12)), [0.0, 0.0]))\n")
    assert make_plan(assignment.for_submission("cheat", honest.encode())).q.tolist() == learnt.q.tolist()
    assert make_plan(assignment.for_submission("cheat", cheat.encode())).q.tolist() != learnt.q.tolist()
    paths = write_class(tmp_path, {"cheat": cheat, "honest": honest})
    out = tmp_path / "out"
    assert main(["grade", str(tmp_path / "assignment.toml"), *map(str, paths), "--out", str(out), "--quiet"]) == 0
    with open(out / "gradebook.csv", newline="") as handle:
        book = {row["student"]: row for row in csv.DictReader(handle)}
    assert book["honest"]["total"] == "100" and book["cheat"]["tau"] == "0"
    assert "seed" not in (out / "cheat.md").read_text()


# ---------------------------------------------------------------------------------------- interface = "robot"

ROBOT_ASSIGNMENT = """\
robot = "two_link"
interface = "robot"
samples = 4
seed = 11
time_limit = 5
[points]
tau = 40
M = 20
V = 20
G = 10
C = 10
"""
# prints the robot it is given at its first call, and raises with its numbers on any robot but the practice one
PRINTS_ITS_ROBOT = '''
_calls = []
_right = tau


def tau(robot, q, qd, qdd):
    if not _calls:
        print("robot:", robot)
    _calls.append(1)
    if robot["links"][0]["mass"] != PRACTICE_MASS:
        raise ValueError(f"masses {[link['mass'] for link in robot['links']]}, inertia {robot['links'][0]['inertia']}")
    return _right(robot, q, qd, qdd)
'''


def _on_robots(source: str) -> str:
    """The closed forms of the two-link arm with the robot as every function's first argument (and ignored)."""
    for name, arguments in (("M", "q"), ("V", "q, qd"), ("G", "q"), ("C", "q, qd"), ("tau", "q, qd, qdd")):
        source = source.replace(f"def {name}({arguments}):", f"def {name}(robot, {arguments}):")
    return source.replace("return M(q) @ qdd + V(q, qd) + G(q)",
                          "return M(robot, q) @ qdd + V(robot, q, qd) + G(robot, q)")


@pytest.fixture(scope="module")
def on_robots(tmp_path_factory):
    from generated import FORMATS, ROBOT_NEWTON_EULER, compiled_submission, derived_submission

    from course_dynamics.core.robots import load_robot

    root = tmp_path_factory.mktemp("robots")
    practice = float(load_robot("two_link").bodies[0].mass)
    sources = {"general": ROBOT_NEWTON_EULER, "closed_forms": _on_robots(CLOSED_FORMS),
               "compiled": compiled_submission(load_robot("two_link"), robot=True),
               "printer": ROBOT_NEWTON_EULER + f"\nPRACTICE_MASS = {practice!r}\n" + PRINTS_ITS_ROBOT}
    sources |= {f"derive_{fmt}": derived_submission("two_link", fmt, robot=True) for fmt in FORMATS}
    paths = write_class(root, sources)
    (root / "assignment.toml").write_text(ROBOT_ASSIGNMENT)
    out = root / "out"
    code = main(["grade", str(root / "assignment.toml"), *map(str, paths), "--out", str(out), "--quiet"])
    with open(out / "gradebook.csv", newline="") as handle:
        book = {row["student"]: row for row in csv.DictReader(handle)}
    return dict(root=root, out=out, code=code, book=book, sources=sources)


def test_a_general_newton_euler_on_the_robot_it_is_given_scores_everything(on_robots):
    assert on_robots["code"] == 0
    assert on_robots["book"]["general"]["total"] == "100"
    assert "3 hidden robots of its shape" in (on_robots["out"] / "general.md").read_text().replace("\\", "")


@pytest.mark.parametrize("name", ["derive_json", "derive_markdown", "derive_latex", "compiled", "closed_forms",
                                  "printer"])
def test_code_made_for_the_practice_robot_fails_on_the_others_and_says_so(on_robots, name):
    row = on_robots["book"][name]
    assert row["status"] == "ok" and float(row["total"]) < 100, row
    assert 0 < float(row["tau"]) < 40, row  # right on the practice robot's states, wrong on the others'
    text = feedback(on_robots, name)
    assert text.count("right on your robot, wrong on others: your code assumes your robot's numbers") == 5, text
    assert "worst state" not in text  # the practice robot's states all agree; the hidden ones are never shown


def test_no_hidden_robot_reaches_any_output_file(on_robots):
    from course_dynamics.grading.robots import hidden_assignments

    assignment = load_assignment(on_robots["root"] / "assignment.toml")
    numbers = set()
    for name, source in on_robots["sources"].items():
        for hidden in hidden_assignments(assignment.for_submission(name, source.encode())):
            for body in hidden.robot.bodies:
                for x in [float(body.mass), *np.ravel(body.I_com), *body.p_com, *body.P]:
                    # as Python, numpy (8 digits) and the feedback (6) print them; 5 digits at least, so that a
                    # short number elsewhere (0.36) is no false alarm
                    numbers |= {t for t in (repr(x), f"{x:.8g}", f"{x:.6g}", f"{x:.5g}")
                                if sum(c.isdigit() for c in t.lstrip("-0.")) >= 5}
    written = "\n".join(p.read_text(errors="replace") for p in on_robots["out"].iterdir())
    # matplotlib's SVG text is glyphs scaled by 1/64 ("scale(0.015625)"): no robot's number, though a hidden
    # inertia of 0.01562497 prints so at 5 digits
    written = re.sub(r"scale\(0\.015625\)", "scale()", written)
    assert "robot: {'gravity'" in written  # what it printed on its own robot is in its feedback
    leaked = sorted(n for n in numbers if n in written)
    assert not leaked, leaked


def test_hidden_robots_are_physical_of_the_same_shape_and_new_for_every_file():
    from course_dynamics.core.robots import load_robot
    from course_dynamics.grading.robots import hidden_assignments, hidden_robot

    for name in ("two_link", "rp_arm", "spatial_arm"):
        model = load_robot(name)
        for k in range(20):
            other = hidden_robot(model, np.random.default_rng(k))
            assert [b.parent for b in other.bodies] == [b.parent for b in model.bodies]
            assert [b.joint_type for b in other.bodies] == [b.joint_type for b in model.bodies]
            for body, mine in zip(other.bodies, model.bodies):
                moments = np.linalg.eigvalsh(body.I_com)
                assert float(body.mass) > 0 and moments.min() > 0 and np.allclose(body.I_com, body.I_com.T)
                assert all(2 * m <= moments.sum() + 1e-12 for m in moments)  # the triangle inequality
                assert np.isclose(np.linalg.norm(body.axis), 1.0)
                assert not np.allclose(body.P, mine.P) or not mine.P.any()
            if name != "spatial_arm":  # planar: each axis stays on its line (its sign may flip)
                assert all(abs(abs(b.axis @ mine.axis) - 1) < 1e-12 for b, mine in zip(other.bodies, model.bodies))
    assignment = load_assignment(_written(ROBOT_ASSIGNMENT))
    first = hidden_assignments(assignment.for_submission("ada", b"one file"))
    again = hidden_assignments(assignment.for_submission("ada", b"one file"))
    other = hidden_assignments(assignment.for_submission("ada", b"the file resubmitted"))
    assert [float(a.robot.bodies[0].mass) for a in first] == [float(a.robot.bodies[0].mass) for a in again]
    assert all(float(a.robot.bodies[0].mass) != float(b.robot.bodies[0].mass) for a, b in zip(first, other))


def _written(text: str) -> Path:
    import tempfile

    folder = Path(tempfile.mkdtemp())
    (folder / "assignment.toml").write_text(text)
    return folder / "assignment.toml"


def test_the_handout_documents_the_robot_interface(capsys):
    assert main(["grade", str(_written(ROBOT_ASSIGNMENT)), "--handout", "ada"]) == 0
    text = capsys.readouterr().out
    for words in ('tau(robot, q, qd, qdd)', 'robot["joints"][i]', '"origin", (4, 4)', '"inertia", (3, 3)',
                  "robots of its shape you do not see"):
        assert words in text, words


# ---------------------------------------------------------------------------------------- what is not dynamics

def _notebook(*cells: str) -> str:
    return json.dumps({"nbformat": 4, "nbformat_minor": 5, "metadata": {},
                       "cells": [{"cell_type": "markdown", "metadata": {}, "source": ["# My dynamics\n"]}]
                       + [{"cell_type": "code", "metadata": {}, "execution_count": k, "outputs": [],
                           "source": cell.splitlines(keepends=True)} for k, cell in enumerate(cells, start=1)]})


NOT_DYNAMICS = {
    # name: (file name, source, status, words the feedback must contain)
    "stuck": ("stuck.py", "import numpy as np\n\n\ndef tau(q, qd, qdd):\n    while True:\n        pass\n", "timeout",
              ["used more than 1 s of CPU time, in tau (line "]),
    "stuck_at_import": ("stuck_at_import.py", "x = 0\nwhile True:\n    x += 1\n", "timeout",
                        ["CPU time, while the file was being imported (line "]),
    "asleep": ("asleep.py", "import time\n\n\ndef tau(q, qd, qdd):\n    time.sleep(1000)\n", "timeout",
               ["wall-clock time, in tau (line 5)"]),
    "talker": ("talker.py", CLOSED_FORMS.replace("def tau(q, qd, qdd):\n", "def tau(q, qd, qdd):\n    print(q, qd, qdd, 'x' * 1000)\n"),
               "output limit", ["remove the print calls (or print less) and submit again"]),
    "scipy_user": ("scipy_user.py", "import scipy.linalg\n" + CLOSED_FORMS, "crashed",
                   ["No module named 'scipy' (line 1): a submission's Python has the standard library and numpy, "
                    "nothing else"]),
    "notebook": ("notebook.ipynb", _notebook("%matplotlib inline\nimport numpy as np", CLOSED_FORMS,
                                             "!pip install scipy\ntau(np.zeros(2), np.zeros(2), np.zeros(2))"), "ok",
                 ["graded from the notebook's code cells", "IPython lines are not Python and were not run (cell 2: "
                  "%matplotlib inline; cell 4: !pip install scipy)"]),
    "broken_notebook": ("broken_notebook.ipynb", '{"cells": [{"cell_type": "code", "source": 7}]}', "not python",
                        ["cell 1's source is not text", "export the notebook as one Python file"]),
    "deep_notebook": ("deep_notebook.ipynb", "[" * 100_000 + "]" * 100_000, "not python",
                      ["not valid JSON", "nbconvert --to script"]),
}


@pytest.fixture(scope="module")
def not_dynamics(tmp_path_factory):
    root = tmp_path_factory.mktemp("not-dynamics")
    paths = []
    for name, (file_name, source, _, _) in NOT_DYNAMICS.items():
        (root / file_name).write_text(source)
        paths.append(root / file_name)
    (root / "assignment.toml").write_text(ASSIGNMENT.replace("output_limit = 100000", "output_limit = 20000"))
    out = root / "out"
    code = main(["grade", str(root / "assignment.toml"), *map(str, paths), "--out", str(out), "--quiet"])
    with open(out / "gradebook.csv", newline="") as handle:
        book = {row["student"]: row for row in csv.DictReader(handle)}
    return dict(out=out, code=code, book=book)


@pytest.mark.parametrize("name", sorted(NOT_DYNAMICS))
def test_a_failure_that_is_not_dynamics_says_what_to_do(not_dynamics, name):
    _, _, status, words = NOT_DYNAMICS[name]
    assert not_dynamics["code"] == 0
    row = not_dynamics["book"][name]
    assert row["status"] == status, row
    assert float(row["total"]) == (100.0 if status == "ok" else 0.0)
    text = feedback(not_dynamics, name)
    for word in words:
        assert word in text, (word, text)
    assert row["flags"] == "", row  # the harness's own timeout report is no tampering


ROSTER_ASSIGNMENT = """\
robot = "two_link"
variant = "per-student"
roster = "roster.csv"
samples = 4
time_limit = 5
[points]
tau = 100
"""


def test_a_roster_matches_ids_and_a_student_not_on_it_scores_zero_saying_so(tmp_path):
    from submissions import spatial_newton_euler

    (tmp_path / "roster.csv").write_text("id,name\nada,Ada Lovelace\ngrace.h,Grace Hopper\nalan+1,Alan\nalan+2,Al\n")
    (tmp_path / "assignment.toml").write_text(ROSTER_ASSIGNMENT)
    assignment = load_assignment(tmp_path / "assignment.toml")
    assert assignment.roster == ("ada", "grace.h", "alan+1", "alan+2")
    files = {"Ada+hw1": spatial_newton_euler(assignment.for_student("ada").robot),  # case and +tag: ada
             "GRACE.H": spatial_newton_euler(assignment.for_student("grace.h").robot),
             "eve": spatial_newton_euler(assignment.for_student("eve").robot),  # her own variant, yet no one's
             "alan": spatial_newton_euler(assignment.for_student("alan+1").robot)}  # two Alans: ambiguous
    for name, source in files.items():
        (tmp_path / f"{name}.py").write_text(source)
    out = tmp_path / "out"
    assert main(["grade", str(tmp_path / "assignment.toml"), *(str(tmp_path / f"{n}.py") for n in files), "--out",
                 str(out), "--quiet"]) == 0
    with open(out / "gradebook.csv", newline="") as handle:
        book = {row["student"]: row for row in csv.DictReader(handle)}
    assert book["Ada+hw1"]["total"] == "100" and book["GRACE.H"]["total"] == "100"
    assert book["eve"]["status"] == "not on roster" and book["eve"]["total"] == "0"
    assert "not on the roster: no student 'eve' is on this assignment's roster" in (out / "eve.md").read_text()
    assert "variant" not in (out / "eve.md").read_text()          # graded on no robot, so none is named
    assert "your own variant for ada (" in (out / "Ada+hw1.md").read_text().replace("\\", "")   # the roster's id
    assert book["alan"]["status"] == "not on roster"
    assert "could be any of alan+1, alan+2" in (out / "alan.md").read_text().replace("\\", "")


def test_without_a_roster_ids_stay_as_given():
    from course_dynamics.grading.uploads import roster_match

    assignment = load_assignment(_written(ASSIGNMENT))
    assert assignment.roster is None
    assert roster_match("Ada", ["ada"]) == ("ada", "") and roster_match("ada", ["Ada", "ADA+x"])[0] == "Ada"
    assert roster_match("bob", ["ada"])[0] is None


@pytest.mark.parametrize("line, message", [
    ('roster = "missing.csv"', "roster 'missing.csv' is no file next to the assignment"),
    ("roster = 3", "roster must name a CSV file next to the assignment, got 3"),
    ('interface = "objects"', "interface must be one of functions, robot, got 'objects'"),
])
def test_bad_roster_or_interface_keys_are_one_clear_line(tmp_path, capsys, line, message):
    (tmp_path / "a.toml").write_text(line + "\n" + ASSIGNMENT)
    (tmp_path / "s.py").write_text(CLOSED_FORMS)
    assert main(["grade", str(tmp_path / "a.toml"), str(tmp_path / "s.py"), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and message in err and len(err.strip().splitlines()) == 1, err


def test_submissions_are_parsed_one_at_a_time_across_the_class_threads():
    """CPython before 3.11.8 fails two concurrent parses ("AST constructor recursion depth mismatch"): a class is
    graded in threads, so every parse goes through one lock."""
    from concurrent.futures import ThreadPoolExecutor

    from course_dynamics.grading.uploads import parse_python

    source = "def tau(q, qd, qdd):\n" + "".join(f"    x{i} = [[[{i}] * 2] * 3]\n" for i in range(300)) + "    return x1\n"
    with ThreadPoolExecutor(max_workers=4) as pool:
        trees = list(pool.map(lambda k: parse_python(source, f"s{k}.py"), range(200)))
    assert all(len(tree.body[0].body) == 301 for tree in trees)
