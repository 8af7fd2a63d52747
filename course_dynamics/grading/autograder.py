"""Gradescope's autograder: the bundle ``grade ASSIGNMENT --gradescope autograder.zip`` writes, and what runs in it.

Gradescope builds an image from the zip once (running ``setup.sh`` as root)
and then runs ``run_autograder`` for each submission, with the student's files
in ``/autograder/submission`` and ``/autograder/submission_metadata.json``
beside them; the results go to ``/autograder/results/results.json``.

===========================  ===================================================
in the zip                   what it is
===========================  ===================================================
``setup.sh``                 chooses a Python >= 3.11 that an unprivileged user
                             can run (``COURSE_DYNAMICS_PYTHON``, else
                             ``/usr/bin/python3``, ``/usr/local/bin/python3``, …,
                             then the ``python3`` on PATH), stopping with one line
                             before it installs anything when there is none
                             (``setup.sh --check-python`` only prints it);
                             makes the grader's environment
                             ``/autograder/grader-env`` with the
                             bundled wheel and its dependencies, then runs
                             :func:`prepare`
``run_autograder``           runs :func:`run` in the grader's environment
``assignment/``              the assignment file, and its robot's URDF when the
                             robot is a file
``course_dynamics-*.whl``    this installation of course-dynamics as a wheel
``bundle.json``              the version, the assignment's file name
===========================  ===================================================

:func:`prepare` copies numpy and the assignment's allowed packages into
``/autograder/submission-site``, the only packages a submission's Python sees
(so Pinocchio and course-dynamics stay out of its reach), and closes the
grader's environment and the bundle to everyone but root. :func:`run` grades
the one Python file of the submission as one student: the student id is the
local part of the first user's e-mail in ``submission_metadata.json``, or the
user field the assignment names (``gradescope_student``), which is what a
per-student assignment gives each student their own robot by. It uses the
bubblewrap sandbox where it starts; inside Gradescope's container it usually
cannot (no namespaces), and the submission then runs in a separate process
with the limits, a throw-away working folder and, the grader being root, an
unprivileged user of its own (:data:`SUBMISSION_UID`). The results say which.

``AUTOGRADER`` (default ``/autograder``) moves the whole layout, and
``COURSE_DYNAMICS_ISOLATION=process`` asks for the fallback even where
bubblewrap starts (both for trying the bundle outside Gradescope).
"""
from __future__ import annotations

import base64
import hashlib
import importlib.metadata
import importlib.util
import io as text_io
import json
import os
import stat
import sys
import time
import tomllib
import traceback
import zipfile
from pathlib import Path

from ..base.errors import CourseDynamicsError, InputError
from ..core.robots import robot_names
from ..output import io, render
from ..tools.variants import check_student_id
from .assignment import Assignment, load_assignment
from .environment import copy_packages, submission_environment
from .feedback import results_json
from .grade import grade_class
from .sandbox import SandboxError, check_sandbox

#: The autograder's folder in Gradescope's image, unless ``AUTOGRADER`` names another.
ROOT = "/autograder"
PACKAGES = ("course_dynamics", "course_dynamics_reference", "course_dynamics_notebooks", "course_dynamics_robots")
#: The unprivileged user and group id a submission runs as where bubblewrap cannot start and the grader is root.
SUBMISSION_UID = 61_000  # the unprivileged user (and group) a submission runs as without the sandbox
MAX_METADATA_BYTES = 10 * 2**20
ISOLATION_WORDS = {
    "bubblewrap": "the bubblewrap sandbox (no network, only its own files, limits)",
    "unprivileged-user": "a separate process with limits and a throw-away working folder, as an unprivileged user, "
                         "without bubblewrap",
    "none": "a separate process with limits and a throw-away working folder, as the grader's own user (not root, so "
            "it cannot give the submission another), without bubblewrap",
}

SETUP = r"""#!/usr/bin/env bash
# course-dynamics autograder: Gradescope runs this once, as root, when it builds the autograder's image.
# `setup.sh --check-python` only prints the Python it would use (or why there is none) and installs nothing.
set -euo pipefail
AUTOGRADER="${AUTOGRADER:-/autograder}"
SOURCE="$AUTOGRADER/source"
recent() { "$1" -c 'import sys, venv, ensurepip; sys.exit(sys.version_info < (3, 11))' 2>/dev/null; }
# As root, a submission may run as an unprivileged user (where bubblewrap cannot start): the Python and its standard
# library must be readable by others, and every folder above them searchable (a Python under root's home is not).
closed_folder() {
    [ "$(id -u)" = 0 ] || return 1
    local target part where
    for target in "$(readlink -f -- "$1")" \
        "$(readlink -f -- "$("$1" -c 'import sysconfig; print(sysconfig.get_paths()["stdlib"])')")"; do
        where=""
        IFS=/ read -ra parts <<< "${target#/}"
        for part in "${parts[@]}"; do
            where="$where/$part"
            local mode; mode="$(stat -L -c %A -- "$where")"
            if [ "$where" = "$target" ] && [ -f "$where" ]; then
                [ "${mode:7:1}" = r ] && [ "${mode:9:1}" = x ] || { echo "$where"; return 0; }
            elif [ "${mode:9:1}" != x ] && [ "${mode:9:1}" != t ]; then
                echo "$where"; return 0
            fi
        done
    done
    return 1
}
candidates() {
    if [ -n "${COURSE_DYNAMICS_PYTHON:-}" ]; then echo "$COURSE_DYNAMICS_PYTHON"; return; fi
    echo /usr/bin/python3; echo /usr/local/bin/python3
    for minor in 14 13 12 11; do echo "/usr/bin/python3.$minor"; echo "/usr/local/bin/python3.$minor"; done
    command -v python3 || true
}
choose() {  # the first recent Python others can run; else the reason, on standard error, and status 1
    local python closed="" first=""
    while read -r python; do
        [ -n "$python" ] && command -v "$python" >/dev/null || continue
        first="${first:-$python}"
        recent "$python" || continue
        if folder="$(closed_folder "$python")"; then closed="${closed:-$python:$folder}"; continue; fi
        echo "$python"; return 0
    done < <(candidates)
    if [ -n "$closed" ]; then
        echo "error: ${closed%%:*} is under ${closed#*:}, which other users cannot read, so a submission run as an" \
            "unprivileged user could not start it; set COURSE_DYNAMICS_PYTHON to a Python 3.11 or newer outside" \
            "root's home (such as /usr/bin/python3)" >&2
    else
        echo "error: course-dynamics needs Python 3.11 or newer with venv;" \
            "this image has $("${first:-python3}" --version 2>&1 || echo no python3):" \
            "choose the Ubuntu 24.04 base image in the autograder's settings" >&2
    fi
    return 1
}
if [ "${1:-}" = --check-python ]; then
    choose || exit 2
    exit 0
fi
if ! PYTHON="$(choose 2>/dev/null)" && [ -z "${COURSE_DYNAMICS_PYTHON:-}" ] && [ -z "${COURSE_DYNAMICS_OFFLINE:-}" ] \
        && command -v apt-get >/dev/null; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3 python3-venv >/dev/null
fi
PYTHON="$(choose)" || exit 2  # before anything is installed
"$PYTHON" -m venv "$AUTOGRADER/grader-env"
GRADER="$AUTOGRADER/grader-env/bin/python"
if [ -n "${COURSE_DYNAMICS_DEPENDENCIES:-}" ]; then
    # An offline build: the dependencies come from a folder that already holds them.
    purelib="$("$GRADER" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
    echo "import site; site.addsitedir('$COURSE_DYNAMICS_DEPENDENCIES')" \
        > "$purelib/zz-course-dynamics-dependencies.pth"
    "$GRADER" -m pip install -q --no-deps --no-index "$SOURCE"/course_dynamics-*.whl
else
    "$GRADER" -m pip install -q "$SOURCE"/course_dynamics-*.whl
fi
"$GRADER" -I -m course_dynamics.grading.autograder prepare
"""

RUN = r"""#!/usr/bin/env bash
# course-dynamics autograder: Gradescope runs this for every submission.
exec "${AUTOGRADER:-/autograder}/grader-env/bin/python" -I -m course_dynamics.grading.autograder run
"""


# ---------------------------------------------------------------------------------------- the bundle


def _record_hash(data: bytes) -> str:
    return "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()


def wheel() -> tuple[str, bytes]:
    """This installation of course-dynamics as a wheel (file name, bytes): its packages' files and its metadata.

    Made from what is installed (an editable install too), so the bundle grades with exactly the code that
    wrote it.

    Returns
    -------
    tuple of (str, bytes)
        The wheel's file name and its bytes.
    """
    distribution = importlib.metadata.distribution("course-dynamics")
    version = distribution.version
    info = f"course_dynamics-{version}.dist-info"
    files: dict[str, bytes] = {}
    for package in PACKAGES:
        spec = importlib.util.find_spec(package)
        folder = Path(list(spec.submodule_search_locations)[0])
        for path in sorted(folder.rglob("*")):
            relative = path.relative_to(folder)
            if path.is_file() and "__pycache__" not in relative.parts and not relative.name.startswith("."):
                files[f"{package}/{relative.as_posix()}"] = path.read_bytes()
    metadata = distribution.read_text("METADATA") or distribution.read_text("PKG-INFO") or ""
    files[f"{info}/METADATA"] = metadata.encode()
    files[f"{info}/WHEEL"] = (b"Wheel-Version: 1.0\nGenerator: course-dynamics\nRoot-Is-Purelib: true\n"
                              b"Tag: py3-none-any\n")
    files[f"{info}/entry_points.txt"] = (distribution.read_text("entry_points.txt") or "").encode()
    record = "".join(f"{name},{_record_hash(data)},{len(data)}\n" for name, data in files.items())
    files[f"{info}/RECORD"] = (record + f"{info}/RECORD,,\n").encode()
    buffer = text_io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in files.items():
            archive.writestr(_entry(name), data)
    return f"course_dynamics-{version}-py3-none-any.whl", buffer.getvalue()


def _entry(name: str, executable: bool = False) -> zipfile.ZipInfo:
    """A zip entry with a fixed date (the same input makes the same zip) and a regular file's mode."""
    info = zipfile.ZipInfo(name, date_time=(2020, 1, 1, 0, 0, 0))
    info.external_attr = (0o100755 if executable else 0o100644) << 16  # Gradescope runs both scripts
    info.compress_type = zipfile.ZIP_DEFLATED
    return info


def write_bundle(assignment: Assignment, target) -> Path:
    """The autograder zip for ``assignment`` at ``target`` (module docstring); InputError if something is there.

    Parameters
    ----------
    assignment : Assignment
        The assignment, bundled with its robot's URDF when the robot is a file.
    target : str or os.PathLike
        The zip file to write; never overwritten.

    Returns
    -------
    pathlib.Path
        The zip written.

    Raises
    ------
    InputError
        If ``target`` exists, or the robot's URDF is outside the assignment's folder.
    """
    target = Path(target)
    files = {f"assignment/{assignment.source.name}": assignment.source.read_bytes()}
    robot_file = assignment.source.parent / assignment.robot_argument
    if robot_file.is_file() and assignment.robot_argument not in robot_names():
        if Path(assignment.robot_argument).is_absolute() or ".." in Path(assignment.robot_argument).parts:
            raise InputError(f"{assignment.source}: robot '{assignment.robot_argument}' is outside the assignment's "
                             "folder; put the URDF beside the assignment (or below it) to bundle it")
        files[f"assignment/{Path(assignment.robot_argument).as_posix()}"] = robot_file.read_bytes()
    roster = tomllib.loads(assignment.source.read_text(encoding="utf-8")).get("roster")
    if roster is not None:  # load_assignment read it: a file next to the assignment
        if Path(roster).is_absolute() or ".." in Path(roster).parts:
            raise InputError(f"{assignment.source}: roster '{roster}' is outside the assignment's folder; put it "
                             "beside the assignment (or below it) to bundle it")
        files[f"assignment/{Path(roster).as_posix()}"] = (assignment.source.parent / roster).read_bytes()
    wheel_name, wheel_data = wheel()
    files[wheel_name] = wheel_data
    files["bundle.json"] = json.dumps({"course_dynamics": importlib.metadata.version("course-dynamics"),
                                       "assignment": assignment.source.name}, indent=2).encode()
    buffer = text_io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr(_entry("setup.sh", executable=True), SETUP)
        archive.writestr(_entry("run_autograder", executable=True), RUN)
        for name, data in files.items():
            archive.writestr(_entry(name), data)
    if not io.write_new(target, buffer.getvalue()):
        raise InputError(f"{target}: exists; kept as it is (remove it, or name another file, to write the bundle)")
    return target


# ---------------------------------------------------------------------------------------- inside Gradescope


def root() -> Path:
    """The autograder's folder: ``$AUTOGRADER``, else :data:`ROOT`.

    Returns
    -------
    pathlib.Path
        The folder.
    """
    return Path(os.environ.get("AUTOGRADER", ROOT))


def prepare(where: Path | None = None) -> list[str]:
    """After ``setup.sh`` installed the wheel: the submissions' packages, and the grader's files closed to others.

    Parameters
    ----------
    where : pathlib.Path or None
        The autograder's folder; ``$AUTOGRADER`` (default ``/autograder``) when None.

    Returns
    -------
    list of str
        The packages copied for the submissions (numpy and the assignment's allowed ones).

    Raises
    ------
    InputError
        If the bundled assignment is not valid, or (as root) a file a submission's Python needs is not readable by
        other users.
    """
    where = where or root()
    assignment = _assignment(where)
    site = where / "submission-site"
    site.mkdir(exist_ok=True)
    copied = copy_packages(assignment.allowed_imports, site)
    for private in (where / "grader-env", where / "source"):
        private.chmod(0o700)
    if os.geteuid() == 0:
        environment = submission_environment(assignment.allowed_imports, site=site)
        closed = _closed_to_others([environment.interpreter, environment.stdlib, *environment.libraries, site, where])
        if closed:
            raise InputError(f"{closed}: not readable by other users, so a submission run as an unprivileged user "
                             "(where bubblewrap cannot start) could not start Python; make it and the folders above "
                             "it readable and searchable by all (chmod o+rx)")
    print(f"course-dynamics autograder: {assignment.source.name} on {assignment.robot.name}; submissions see "
          f"{', '.join(copied)} beside the standard library; grading runs in {_isolation()[2]}")
    return copied


def _closed_to_others(paths) -> Path | None:
    """The first of ``paths`` (or a folder above one) that a user other than its owner cannot reach, or None."""
    for path in map(Path, paths):
        path = path.resolve()
        for folder in [*reversed(path.parents), path]:
            mode = folder.stat().st_mode
            # a folder on the way must be searchable; the end read (a folder listed too, a program run too)
            needed = stat.S_IXOTH if folder != path else stat.S_IROTH | (stat.S_IXOTH if folder.is_dir() else 0)
            if mode & needed != needed:
                return folder
    return None


def _assignment(where: Path) -> Assignment:
    bundle = json.loads((where / "source" / "bundle.json").read_text())
    return load_assignment(where / "source" / "assignment" / bundle["assignment"])


def _isolation() -> tuple[bool, tuple[int, int] | None, str]:
    """(sandbox, user, words): bubblewrap where it starts (unless the environment asks for the fallback), else a
    separate process as SUBMISSION_UID when the grader is root."""
    reason = "asked for with COURSE_DYNAMICS_ISOLATION=process"
    if os.environ.get("COURSE_DYNAMICS_ISOLATION") != "process":
        try:
            check_sandbox()
            return True, None, ISOLATION_WORDS["bubblewrap"]
        except SandboxError as exc:
            reason = str(exc).split("; pass --no-sandbox")[0]
    if os.geteuid() == 0:
        return False, (SUBMISSION_UID, SUBMISSION_UID), f"{ISOLATION_WORDS['unprivileged-user']}: {reason}"
    return False, None, f"{ISOLATION_WORDS['none']}: {reason}"


def student_id(metadata_path: Path, field: str) -> str:
    """The student from Gradescope's ``submission_metadata.json``: the first user's ``field`` (``email``: its local
    part), checked as an id; InputError naming the file and the field otherwise.

    Parameters
    ----------
    metadata_path : pathlib.Path
        Gradescope's ``submission_metadata.json``.
    field : str
        The user field that names the student (the assignment's ``gradescope_student``).

    Returns
    -------
    str
        The student id.

    Raises
    ------
    InputError
        If the file is missing or not JSON, the field is missing, or its value is not a valid id.
    """
    where = f"{metadata_path.name}: users[0].{field}"
    try:
        with open(metadata_path, "rb") as handle:
            data = handle.read(MAX_METADATA_BYTES + 1)
        metadata = json.loads(data) if len(data) <= MAX_METADATA_BYTES else None
    except FileNotFoundError:
        raise InputError(f"{metadata_path}: no submission metadata "
                         "(Gradescope writes it beside the submission)") from None
    except (OSError, ValueError, RecursionError) as exc:
        raise InputError(f"{metadata_path}: not readable JSON ({type(exc).__name__})") from None
    users = metadata.get("users") if isinstance(metadata, dict) else None
    if not isinstance(users, list) or not users or not isinstance(users[0], dict) or field not in users[0]:
        raise InputError(f"{where}: missing; the assignment's gradescope_student names the user field that "
                         "identifies a student")
    value = users[0][field]
    if field == "email" and isinstance(value, str):
        value = value.split("@", 1)[0]
    if isinstance(value, int) and not isinstance(value, bool):
        value = str(value)
    if not isinstance(value, str) or len(value) > 64:  # no id; and the message quotes only its start
        raise InputError(f"{where} {repr(value)[:40]}…: not an id of at most 64 characters")
    return check_student_id(value, where)


def submission_file(folder: Path) -> Path:
    """The one Python file or notebook of the submission (at its top, or alone anywhere below it); InputError
    otherwise.

    Parameters
    ----------
    folder : pathlib.Path
        The submission's folder; links in it are never followed.

    Returns
    -------
    pathlib.Path
        The file.

    Raises
    ------
    InputError
        If there is no such file or more than one.
    """
    def usable(path: Path) -> bool:  # a regular file inside the folder: a link is never followed, as root
        return not path.is_symlink() and path.is_file() and not any(p.is_symlink() for p in path.parents
                                                                     if p.is_relative_to(folder))

    def files(pattern: str) -> list[Path]:
        return sorted(p for suffix in (".py", ".ipynb") for p in folder.glob(pattern + suffix) if usable(p)
                      and "__MACOSX" not in p.parts and ".ipynb_checkpoints" not in p.parts)

    found = files("*") or files("**/*")
    if len(found) != 1:
        names = ", ".join(p.relative_to(folder).as_posix() for p in found[:5])
        raise InputError("submit exactly one Python file (or one notebook) defining tau, M, V, G or C; "
                         + (f"found {len(found)} ({names})" if found else "found none"))
    return found[0]


def grade_here(where: Path) -> dict:
    """Grade the submission in ``where`` (the /autograder layout) and return Gradescope's results document.

    Parameters
    ----------
    where : pathlib.Path
        The autograder's folder.

    Returns
    -------
    dict
        Gradescope's ``results.json`` document (:func:`~course_dynamics.grading.feedback.results_json`), the
        student named in its output and the isolation in its hidden test.

    Raises
    ------
    InputError
        If the student id or the submission file cannot be found (:func:`student_id`, :func:`submission_file`).
    """
    assignment = _assignment(where)
    student = student_id(where / "submission_metadata.json", assignment.gradescope_student)
    path = submission_file(where / "submission")
    sandbox, user, words = _isolation()
    environment = submission_environment(assignment.allowed_imports, site=where / "submission-site")
    grade, = grade_class(assignment, [path], sandbox=sandbox, students=[student], user=user, environment=environment,
                         jobs=1)
    document = results_json(grade, assignment)
    document["output"] = f"student {student}\n{document['output']}"[:20_000]
    hidden = document["tests"][-1]  # the instructors' test: which isolation ran is for them
    hidden["output"] = f"graded in {words}\n{hidden['output']}"
    return document


def run(where: Path | None = None) -> dict:
    """Grade and write ``results/results.json`` whatever happens: a problem becomes a score of 0 with its reason.

    Parameters
    ----------
    where : pathlib.Path or None
        The autograder's folder; ``$AUTOGRADER`` (default ``/autograder``) when None.

    Returns
    -------
    dict
        The results document written, with its ``execution_time``, s.
    """
    where = where or root()
    started = time.monotonic()
    metadata = where / "submission_metadata.json"
    if metadata.exists():
        metadata.chmod(0o600)  # other students' names and earlier results: not for the submission to read
    (where / "results").mkdir(exist_ok=True)
    (where / "results").chmod(0o755)
    try:
        document = grade_here(where)
    except CourseDynamicsError as exc:
        document = {"score": 0.0, "output": f"error: {exc}", "tests": []}
    except Exception:  # our own failure: the instructor sees the traceback in the autograder's stdout
        traceback.print_exc()
        document = {"score": 0.0, "output": "the autograder failed (a fault of course-dynamics, not of the "
                    "submission); your instructor can see its log", "tests": []}
    document["execution_time"] = round(time.monotonic() - started, 1)
    io.write_text(where / "results" / "results.json", render.json_text(document) + "\n")
    print(f"course-dynamics autograder: score {document['score']:g}; {document['output'].splitlines()[0]}"
          + (f"; {document['tests'][-1]['output'].splitlines()[0]}" if document["tests"] else ""))
    return document


def main(argv=None) -> int:
    """``python -m course_dynamics.grading.autograder prepare`` or ``run``, as the bundle's scripts call it.

    Parameters
    ----------
    argv : list of str or None
        The arguments, ``["prepare"]`` or ``["run"]``; ``sys.argv[1:]`` when None.

    Returns
    -------
    int
        The exit status: 0, or 2 (with a usage line) for other arguments.
    """
    argv = sys.argv[1:] if argv is None else argv
    if argv == ["prepare"]:
        prepare()
        return 0
    if argv == ["run"]:
        run()
        return 0
    print("usage: python -m course_dynamics.grading.autograder {prepare|run} (run by the Gradescope bundle's "
          "setup.sh and run_autograder)", file=sys.stderr)
    return 2



__all__ = ["ROOT", "SUBMISSION_UID", "grade_here", "main", "prepare", "root", "run", "student_id", "submission_file",
           "wheel", "write_bundle"]


if __name__ == "__main__":
    sys.exit(main())
