"""course_dynamics/grading/autograder: the Gradescope bundle, unpacked into a simulated /autograder and run.

The bundle is written through the CLI, unpacked as Gradescope unpacks it, and
set up by its own ``setup.sh`` without network: the bundled wheel is installed
with ``--no-deps`` into a fresh environment that finds the dependencies in this
one. ``run_autograder`` then grades a correct, a wrong and a hostile
submission, in the sandbox and in the fallback Gradescope's containers need,
and every ``results.json`` is checked against Gradescope's documented schema.
"""
from __future__ import annotations

import json
import os
import shutil
import stat
import subprocess
import sys
import sysconfig
import tempfile
import zipfile
from pathlib import Path

import pytest
from submissions import CLOSED_FORMS, closed_forms, spatial_newton_euler

from course_dynamics.cli import main
from course_dynamics.grading import load_assignment
from course_dynamics.grading.autograder import SUBMISSION_UID

ASSIGNMENT = 'robot = "two_link"\nsamples = 6\nseed = 5\ntime_limit = 10\n[points]\ntau = 40\nM = 30\nG = 30\n'
PER_STUDENT = 'robot = "spatial_arm"\nvariant = "per-student"\nsamples = 6\ntime_limit = 10\n{field}[points]\ntau = 100\n'

# Gradescope's results.json (gradescope-autograders.readthedocs.io, "Autograder Specifications").
TOP_LEVEL = {"score", "execution_time", "output", "output_format", "test_output_format", "test_name_format",
             "visibility", "stdout_visibility", "extra_data", "tests", "leaderboard"}
TEST_KEYS = {"score", "max_score", "status", "name", "name_format", "number", "output", "output_format", "tags",
             "visibility", "extra_data"}
VISIBILITIES = {"hidden", "after_due_date", "after_published", "visible"}

# Tries the grader's files, the results, the other users' metadata and our package; reports what it could through G's
# error message (in its feedback), so that tau and M still score and G scores nothing.
HOSTILE = '''
import os, sys
ROOT = "AUTOGRADER_ROOT"
report = []
for name, attempt in (("bundle", lambda: open(ROOT + "/source/bundle.json").read()),
                      ("grader", lambda: os.listdir(ROOT + "/grader-env")),
                      ("results", lambda: open(ROOT + "/results/results.json", "w").write('{"score": 1000}')),
                      ("metadata", lambda: open(ROOT + "/submission_metadata.json").read())):
    try:
        attempt()
        report.append(name + ":ALLOWED")
    except OSError:
        report.append(name + ":refused")
for top in (ROOT, "/usr/lib", "/usr/local/lib"):
    sys.path += [os.path.join(r, d) for r, dirs, _ in os.walk(top) for d in dirs if d.endswith("-packages")]
sys.meta_path[:] = [f for f in sys.meta_path if type(f).__name__ != "ImportGuard"]
try:
    __import__("course_" + "dynamics")
    report.append("import:ALLOWED")
except ImportError:
    report.append("import:refused")
os.system("true")
report.append("uid:" + str(os.getuid()))
''' + CLOSED_FORMS + '''
G_RIGHT = G


def tau(q, qd, qdd):
    return M(q) @ qdd + V(q, qd) + G_RIGHT(q)


def G(q):
    raise RuntimeError(" ".join(report))
'''


def interpreter() -> str:
    """A Python of this version for the bundle's environment; as root, one an unprivileged user can run too."""
    base = os.path.realpath(getattr(sys, "_base_executable", sys.executable))
    version = f"python{sys.version_info.major}.{sys.version_info.minor}"

    def others_can_run(path: str) -> bool:
        return all(os.stat(p).st_mode & stat.S_IXOTH for p in [*Path(path).parents][:-1]) and \
            bool(os.stat(path).st_mode & stat.S_IROTH)

    if os.geteuid() == 0 and not others_can_run(base) and shutil.which(version, path="/usr/bin"):
        return f"/usr/bin/{version}"
    return base


def unpack(bundle: Path) -> Path:
    """A fresh /autograder as Gradescope makes it: the zip in source/, readable by everyone down to it."""
    root = Path(tempfile.mkdtemp(prefix="autograder-", dir="/tmp"))
    root.chmod(0o755)
    with zipfile.ZipFile(bundle) as archive:
        archive.extractall(root / "source")
        for info in archive.infolist():  # zipfile does not restore modes; Gradescope's unzip does
            (root / "source" / info.filename).chmod((info.external_attr >> 16) & 0o777)
    (root / "submission").mkdir()
    return root


def setup(root: Path, python: str) -> subprocess.CompletedProcess:
    dependencies = sysconfig.get_paths()["purelib"]
    env = dict(os.environ, AUTOGRADER=str(root), COURSE_DYNAMICS_OFFLINE="1", COURSE_DYNAMICS_PYTHON=python,
               COURSE_DYNAMICS_DEPENDENCIES=dependencies)
    return subprocess.run(["bash", str(root / "source" / "setup.sh")], env=env, capture_output=True, text=True,
                          timeout=600)


def submit(root: Path, files: dict[str, str], email: str = "ada.lovelace@uni.example", isolation: str = "",
           user: dict | None = None) -> dict:
    """One Gradescope run: the submission's files and metadata in place, run_autograder, its results.json."""
    shutil.rmtree(root / "submission")
    (root / "submission").mkdir()
    for name, text in files.items():
        (root / "submission" / name).write_text(text)
    metadata = {"users": [user or {"email": email, "id": 1234, "name": "Student User"}],
                "assignment": {"title": "Dynamics", "total_points": "100.0"}, "previous_submissions": []}
    (root / "submission_metadata.json").write_text(json.dumps(metadata))
    (root / "results").mkdir(exist_ok=True)
    env = dict(os.environ, AUTOGRADER=str(root), FAKE_ROOT=str(root))
    env.pop("COURSE_DYNAMICS_ISOLATION", None)
    if isolation:
        env["COURSE_DYNAMICS_ISOLATION"] = isolation
    run = subprocess.run([str(root / "source" / "run_autograder")], env=env, capture_output=True, text=True,
                         cwd=root, timeout=300)
    assert run.returncode == 0, run.stderr
    results = json.loads((root / "results" / "results.json").read_text())
    check_schema(results)
    return results


def check_schema(results: dict) -> None:
    assert set(results) <= TOP_LEVEL, set(results) - TOP_LEVEL
    assert isinstance(results["score"], float) and isinstance(results["output"], str)
    assert results.get("visibility", "visible") in VISIBILITIES
    for test in results["tests"]:
        assert set(test) <= TEST_KEYS and {"name", "score", "max_score"} <= set(test), test
        assert isinstance(test["name"], str) and isinstance(test["output"], str)
        assert 0 <= test["score"] <= test["max_score"] or test["max_score"] == 0 == test["score"]
        assert test["visibility"] in VISIBILITIES
    if results["tests"]:
        assert results["score"] == pytest.approx(sum(t["score"] for t in results["tests"]))


@pytest.fixture(scope="module")
def bundle(tmp_path_factory):
    folder = tmp_path_factory.mktemp("course")
    (folder / "hw.toml").write_text(ASSIGNMENT)
    assert main(["grade", str(folder / "hw.toml"), "--gradescope", str(folder / "autograder.zip")]) == 0
    root = unpack(folder / "autograder.zip")
    done = setup(root, interpreter())
    assert done.returncode == 0, done.stdout + done.stderr
    yield dict(folder=folder, zip=folder / "autograder.zip", root=root, setup=done)
    shutil.rmtree(root, ignore_errors=True)


def test_the_zip_is_what_gradescope_asks_for(bundle):
    with zipfile.ZipFile(bundle["zip"]) as archive:
        names = archive.namelist()
        modes = {i.filename: (i.external_attr >> 16) & 0o777 for i in archive.infolist()}
        assert archive.read("setup.sh").startswith(b"#!/usr/bin/env bash")
    assert {"setup.sh", "run_autograder", "assignment/hw.toml", "bundle.json"} <= set(names)
    assert modes["setup.sh"] == modes["run_autograder"] == 0o755 and modes["bundle.json"] == 0o644
    assert [n for n in names if n.endswith(".whl")] == ["course_dynamics-0.1.0-py3-none-any.whl"]
    assert all("/" not in n or n.startswith("assignment/") for n in names)  # the scripts at the zip's root


def test_setup_installs_the_bundled_wheel_and_closes_the_grader(bundle):
    root = bundle["root"]
    grader = root / "grader-env" / "bin" / "python"
    where = subprocess.run([str(grader), "-I", "-c", "import course_dynamics; print(course_dynamics.__file__)"],
                           capture_output=True, text=True).stdout
    assert where.startswith(str(root / "grader-env")), where  # the wheel's code, not this checkout's
    assert stat.S_IMODE((root / "grader-env").stat().st_mode) == 0o700
    assert stat.S_IMODE((root / "source").stat().st_mode) == 0o700
    site = sorted(p.name for p in (root / "submission-site").iterdir())
    assert "numpy" in site and not any(n.startswith(("pinocchio", "course_dynamics", "cmeel")) for n in site)
    assert "submissions see numpy" in bundle["setup"].stdout


@pytest.mark.parametrize("isolation", ["", "process"])
def test_a_correct_and_a_wrong_submission(bundle, isolation):
    right = submit(bundle["root"], {"dynamics.py": CLOSED_FORMS}, isolation=isolation)
    assert right["score"] == 100.0
    assert right["output"].startswith("student ada.lovelace\n") and "graded in" not in right["output"]
    words = "bubblewrap sandbox" if not isolation else ("as an unprivileged user" if os.geteuid() == 0 else
                                                        "as the grader's own user")
    assert [t["name"] for t in right["tests"]] == ["tau", "M", "G", "integrity flags (instructors only)"]
    hidden = right["tests"][-1]  # which isolation ran is for the instructors, beside the flags
    assert hidden["visibility"] == "hidden" and hidden["score"] == hidden["max_score"] == 0.0
    assert hidden["output"].startswith("graded in ") and words in hidden["output"].splitlines()[0]
    assert hidden["output"].splitlines()[1] == "none"
    wrong = submit(bundle["root"], {"dynamics.py": closed_forms("\ndef G(q):\n    return -np.array("
                                                                 "[m2 * l2 * g * np.cos(q[0] + q[1]) + (m1 + m2) * l1 * g"
                                                                 " * np.cos(q[0]), m2 * l2 * g * np.cos(q[0] + q[1])])\n",
                                                                 remove=("tau",)) +
                                    "\ndef tau(q, qd, qdd):\n    return M(q) @ qdd + V(q, qd) + G(q)\n"},
                   isolation=isolation)
    g = next(t for t in wrong["tests"] if t["name"] == "G")
    assert g["score"] == 0 and "opposite sign" in g["output"] and wrong["score"] == 30.0


@pytest.mark.parametrize("isolation", ["", "process"])
def test_a_hostile_submission_is_contained_and_flagged(bundle, isolation):
    root = bundle["root"]
    results = submit(root, {"dynamics.py": HOSTILE.replace("AUTOGRADER_ROOT", str(root))}, isolation=isolation)
    assert results["score"] == 70.0  # tau and M are right; G carries the report
    report = next(t for t in results["tests"] if t["name"] == "G")["output"]
    flags = results["tests"][-1]
    assert flags["visibility"] == "hidden" and "[process]" in flags["output"] and "[list-folder]" in flags["output"]
    assert "integrity" not in results["output"]
    assert json.loads((root / "results" / "results.json").read_text())["score"] == 70.0  # ours, not 1000
    if isolation == "process" and os.geteuid() != 0:
        return  # as the grader's own user, only the sandbox keeps the grader's files out of reach
    for attempt in ("bundle", "grader", "results", "metadata", "import"):
        assert f"{attempt}:refused" in report, report
    if isolation == "process":
        assert f"uid:{SUBMISSION_UID}" in report, report


@pytest.mark.parametrize("field, user, student", [
    ("", {"email": "ada.lovelace@uni.example", "id": 1}, "ada.lovelace"),
    ('gradescope_student = "sid"\n', {"email": "x@uni.example", "sid": "s1234567"}, "s1234567"),
])
def test_each_student_is_graded_on_their_own_robot(tmp_path, field, user, student):
    (tmp_path / "own.toml").write_text(PER_STUDENT.format(field=field))
    assert main(["grade", str(tmp_path / "own.toml"), "--gradescope", str(tmp_path / "own.zip")]) == 0
    root = unpack(tmp_path / "own.zip")
    try:
        assert setup(root, interpreter()).returncode == 0
        theirs = spatial_newton_euler(load_assignment(tmp_path / "own.toml").for_student(student).robot)
        assert submit(root, {"arm.py": theirs}, user=user)["score"] == 100.0
        other = spatial_newton_euler(load_assignment(tmp_path / "own.toml").for_student("grace.h").robot)
        results = submit(root, {"arm.py": other}, user=user)
        assert results["score"] < 100.0 and results["output"].startswith(f"student {student}\n")
    finally:
        shutil.rmtree(root, ignore_errors=True)


def test_a_gradescope_email_is_matched_to_the_bundled_roster(tmp_path):
    (tmp_path / "roster.csv").write_text("id\nada\ngrace.h\n")
    (tmp_path / "own.toml").write_text(PER_STUDENT.format(field='roster = "roster.csv"\n'))
    assert main(["grade", str(tmp_path / "own.toml"), "--gradescope", str(tmp_path / "own.zip")]) == 0
    with zipfile.ZipFile(tmp_path / "own.zip") as archive:
        assert "assignment/roster.csv" in archive.namelist()
    root = unpack(tmp_path / "own.zip")
    try:
        assert setup(root, interpreter()).returncode == 0
        ada = spatial_newton_euler(load_assignment(tmp_path / "own.toml").for_student("ada").robot)
        assert submit(root, {"arm.py": ada}, email="Ada+hw1@uni.example")["score"] == 100.0
        results = submit(root, {"arm.py": ada}, email="eve@uni.example")
        assert results["score"] == 0.0 and "not on the roster: no student 'eve'" in results["output"], results
    finally:
        shutil.rmtree(root, ignore_errors=True)


@pytest.mark.parametrize("files, user, message", [
    ({"a.py": CLOSED_FORMS, "b.py": CLOSED_FORMS}, None, "exactly one Python file (or one notebook) defining tau, M, V, G or C; found 2 (a.py, b.py)"),
    ({"notes.txt": "hello"}, None, "C; found none"),
    ({"a.py": CLOSED_FORMS}, {"name": "No Email"}, "users[0].email: missing"),
    ({"a.py": CLOSED_FORMS}, {"email": "../../etc@x.example"}, "users[0].email '../../etc'"),
    ({"a.py": CLOSED_FORMS}, {"email": "x" * 9_000_000},
     "users[0].email '" + "x" * 39 + "…: not an id of at most 64 characters"),
])
def test_what_cannot_be_graded_is_a_zero_that_says_why(bundle, files, user, message):
    results = submit(bundle["root"], files, user=user)
    assert results["score"] == 0.0 and results["tests"] == [] and results["output"].startswith("error: ")
    assert message in results["output"], results["output"]
    assert len(results["output"]) < 1000


def test_a_link_in_the_submission_is_never_followed(bundle):
    """The grader reads the submission as root: a link to the assignment (closed to the submission) is no file."""
    root = bundle["root"]
    submit(root, {})
    (root / "submission" / "peek.py").symlink_to(root / "source" / "assignment" / "hw.toml")
    env = dict(os.environ, AUTOGRADER=str(root))
    subprocess.run([str(root / "source" / "run_autograder")], env=env, capture_output=True, cwd=root, check=True)
    results = json.loads((root / "results" / "results.json").read_text())
    assert results["score"] == 0.0 and "found none" in results["output"] and "points" not in results["output"]


def test_a_submission_in_a_folder_is_found(bundle):
    root = bundle["root"]
    results = submit(root, {}, isolation="")
    assert results["score"] == 0.0
    (root / "submission" / "hw1").mkdir()
    (root / "submission" / "hw1" / "dynamics.py").write_text(CLOSED_FORMS)
    env = dict(os.environ, AUTOGRADER=str(root))
    subprocess.run([str(root / "source" / "run_autograder")], env=env, capture_output=True, cwd=root, check=True)
    assert json.loads((root / "results" / "results.json").read_text())["score"] == 100.0


def test_setup_stops_on_an_old_python_with_one_line(bundle, tmp_path):
    old = tmp_path / "python3"
    old.write_text("#!/bin/sh\n[ \"$1\" = --version ] && echo 'Python 3.8.10' && exit 0\nexit 1\n")
    old.chmod(0o755)
    root = unpack(bundle["zip"])
    try:
        done = setup(root, str(old))
    finally:
        shutil.rmtree(root, ignore_errors=True)
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        "error: course-dynamics needs Python 3.11 or newer with venv; this image has Python 3.8.10: choose the "
        "Ubuntu 24.04 base image in the autograder's settings"]


def _closed_python(tmp_path: Path) -> Path:
    """A working Python 3.11+ in a folder only its owner can enter, as pyenv's under root's home."""
    home = tmp_path / "home"
    (home / "bin").mkdir(parents=True)
    home.chmod(0o700)
    python = home / "bin" / "python3"
    python.write_text(f"#!/bin/sh\nexec {interpreter()} \"$@\"\n")
    python.chmod(0o755)
    return python


def test_setup_chooses_a_python_others_can_run_over_the_one_on_path(bundle, tmp_path):
    closed = _closed_python(tmp_path)
    env = {k: v for k, v in os.environ.items() if k != "COURSE_DYNAMICS_PYTHON"}
    env["PATH"] = f"{closed.parent}:{env['PATH']}"
    done = subprocess.run(["bash", str(bundle["root"] / "source" / "setup.sh"), "--check-python"], env=env,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    chosen = done.stdout.strip()
    assert chosen != str(closed) and chosen.startswith(("/usr/bin/", "/usr/local/bin/"))
    assert subprocess.run([chosen, "-c", "import sys; assert sys.version_info >= (3, 11)"]).returncode == 0


def test_setup_stops_before_installing_on_a_python_others_cannot_run(bundle, tmp_path):
    closed = _closed_python(tmp_path)
    root = unpack(bundle["zip"])
    try:
        done = setup(root, str(closed))
        made = (root / "grader-env").exists()
    finally:
        shutil.rmtree(root, ignore_errors=True)
    lines = done.stderr.strip().splitlines()
    if os.geteuid() == 0:  # only root's submissions run as another user, who must be able to start the Python
        assert done.returncode == 2 and not made
        assert len(lines) == 1 and lines[0].startswith(f"error: {closed} is under /") and \
            "set COURSE_DYNAMICS_PYTHON to a Python 3.11 or newer outside root's home" in lines[0], lines
    else:
        assert done.returncode == 0 and made, done.stderr


def test_the_bundle_is_never_written_over(bundle, capsys):
    before = bundle["zip"].read_bytes()
    assert main(["grade", str(bundle["folder"] / "hw.toml"), "--gradescope", str(bundle["zip"])]) == 2
    assert "exists; kept as it is" in capsys.readouterr().err and bundle["zip"].read_bytes() == before
