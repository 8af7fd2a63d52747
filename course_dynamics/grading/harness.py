"""Runs one student's submission and evaluates its functions on a plan of calls.

This file and integrity.py beside it are the only code of ours that runs next to student code. In grading
it runs as a script, ``python -I -S harness.py RESULTS_FD FLAGS_FD``, in its own process
(inside the sandbox), on an interpreter that sees only the standard library and
the folders the plan's ``path`` names (numpy and the assignment's allowed
packages: :mod:`course_dynamics.grading.environment`): it reads the plan as
JSON from standard input, imports the submission, calls its functions, and
writes plain JSON (numbers, strings) to the file descriptor RESULTS_FD. It
imports nothing but the standard library and numpy, so it never loads the
grader or the library it checks against; the grader reads what comes back as
hostile (:mod:`course_dynamics.grading.results`), since the submission can write
to the same descriptor. The import guard below only names a forbidden import
in the feedback: what keeps a forbidden package out is that it is not there.
The notebooks' exercise checks call :func:`evaluate` in the student's own kernel.

Integrity flags: before the submission runs, the audit hook of
:mod:`integrity.py <course_dynamics.grading.integrity>` (beside this file, loaded by its path; a Python audit hook
cannot be removed once added) records what it tries that a dynamics answer never needs
(:data:`~course_dynamics.grading.integrity.FLAGS`), each line tagged and written at once on the channel FLAGS_FD,
before the attempt itself proceeds. The hook ends the channel
when the harness raises END_EVENT with the digest of the results it is about to write, and tells the harness, when
asked with IMPORTS_EVENT, the forbidden modules it saw loaded (an import the submission hid afterwards, its guard
taken out and its modules dropped from ``sys.modules``, still makes the status ``forbidden import``). After arming,
the harness opens no file but the submission's and writes the results with ``os.write``. Flags are leads for the
instructor, never a score: a submission can hide a flag by going below Python, and the sandbox, not the hook, is what
keeps it in.

Plan: ``{"module": path, "path": [folders], "forbidden": [names], "available": [names], "nonce": text,
"time_limit": s, "wall_seconds": s, "functions": {name: [[arg, …], …]}}``
where each argument is a list of floats (one state vector); with ``"robots": [robot, …]`` and
``"robot_of": {name: [index, …]}`` (the assignment's ``interface = "robot"``), each call's first argument is
``robots[index]`` as plain data (:func:`robot_data`). ``available`` names the packages a submission may import
(an import of another says so); ``time_limit`` and ``wall_seconds`` are the run's limits, at which the harness
itself reports a ``timeout`` naming the function and line of the submission that was running.

Results: ``{"status", "message", "defined", "forbidden_attempts",
"results": {name: [{"value": nested floats} or {"error": text}, …]}}``.
Statuses: ``ok``, ``syntax error``, ``forbidden import``, ``exited``,
``memory``, ``file access``, ``crashed``, ``timeout``.
"""
from __future__ import annotations

import errno
import hashlib
import importlib.abc
import importlib.util
import json
import os
import signal
import sys
import traceback

try:  # in grading, numpy is importable only once main() has put the plan's folders on the path
    import numpy as np
except ImportError:
    np = None

#: The functions a submission may define, in the order they are graded.
FUNCTIONS = ("tau", "M", "V", "G", "C")
#: The statuses the harness writes (``ok``, or what ended the submission's run).
STATUSES = ("ok", "syntax error", "forbidden import", "exited", "memory", "file access", "crashed", "timeout")
#: The most numbers one returned value may hold to be sent back (nor more than n × n for n joints).
MAX_VALUES = 10_000  # a returned array larger than this is reported, not sent back (nor one over n × n values)
#: The most dimensions one returned value may have to be sent back (M and C have two).
MAX_DIMENSIONS = 3   # nor one of more dimensions (M and C have two)
FILE_ERRORS = (errno.EROFS, errno.EACCES, errno.EPERM)
WALL_MARGIN = 2.0  # s: the harness reports a wall-clock timeout this long before the grader kills the run
AVAILABLE = {"packages": None}  # in grading, what a submission may import besides the standard library (the plan's)


def _integrity():
    """The integrity hook's module (integrity.py, beside this file), loaded by its path: nothing of ours is imported."""
    where = os.path.join(os.path.dirname(os.path.abspath(__file__)), "integrity.py")
    spec = importlib.util.spec_from_file_location("course_dynamics_integrity", where)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


integrity = _integrity()
FLAGS, MAX_FLAG_LINES, MAX_FLAG_DETAIL = integrity.FLAGS, integrity.MAX_FLAG_LINES, integrity.MAX_FLAG_DETAIL
END_EVENT, IMPORTS_EVENT = integrity.END_EVENT, integrity.IMPORTS_EVENT


class ForbiddenImport(ImportError):
    """A submission imported a module the assignment forbids (its status becomes ``forbidden import``)."""


class ImportGuard(importlib.abc.MetaPathFinder):
    """Refuses the forbidden top-level modules and remembers every attempt.

    Parameters
    ----------
    forbidden : iterable of str
        The forbidden top-level module names.
    """

    def __init__(self, forbidden):
        self.forbidden = set(forbidden)
        self.attempts: list[str] = []

    def find_spec(self, fullname, path=None, target=None):
        """Refuse ``fullname`` when its top-level module is forbidden, recording the attempt; else leave it to others.

        Parameters
        ----------
        fullname : str
            The module imported.
        path : list of str or None
            The parent package's path (unused).
        target : module or None
            The module being reloaded (unused).

        Returns
        -------
        None
            For a module that is not forbidden, which the next finders then look for.

        Raises
        ------
        ForbiddenImport
            If the module is forbidden.
        """
        if fullname.split(".")[0] in self.forbidden:
            if fullname not in self.attempts:
                self.attempts.append(fullname)
            raise ForbiddenImport(f"import of '{fullname}' is not allowed in this assignment")
        return None


def _where(exc: BaseException, path: str) -> str:
    """``Type: message (line N)``, N the last line of the submission in the traceback."""
    line = ""
    for frame, number in traceback.walk_tb(exc.__traceback__):  # line numbers only: no file read after arming
        if frame.f_code.co_filename == path:
            line = f" (line {number})"
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    found = f"{type(exc).__name__}{': ' + text[:300] if text else ''}{line}"
    if isinstance(exc, ModuleNotFoundError) and AVAILABLE["packages"] is not None:  # not in a notebook's kernel
        found += (f": a submission's Python has the standard library and {', '.join(AVAILABLE['packages'])}, "
                  "nothing else")
    return found


def _place(frame, path: str) -> str:
    """Where the submission was when time ran out: "in tau (line 12)", from the innermost frame of its file."""
    while frame is not None and frame.f_code.co_filename != path:
        frame = frame.f_back
    if frame is None:
        return ""
    name = frame.f_code.co_name
    return f", {'while the file was being imported' if name == '<module>' else f'in {name}'} (line {frame.f_lineno})"


def _value(result, limit: int = MAX_VALUES):
    """A returned value as nested floats, or an error record that says why it cannot be one.

    ``limit`` is what the grader takes back of one call (results.results_cap: n × n values for n joints): a longer
    answer is that call's error, never a document too large to read."""
    try:
        if np.iscomplexobj(np.asarray(result)):
            return {"error": "returned complex numbers; every term is real (a square root of a negative number?)"}
        array = np.asarray(result, dtype=float)
    except (TypeError, ValueError):
        kind = type(result).__name__
        return {"error": f"returned {kind if result is not None else 'None'}, expected numbers"}
    if array.size > min(limit, MAX_VALUES):
        return {"error": f"returned {array.size} values, more than the {min(limit, MAX_VALUES)} a term can have here"}
    if array.ndim > MAX_DIMENSIONS:
        return {"error": f"returned an array of {array.ndim} dimensions"}
    return {"value": array.tolist(), "shape": list(array.shape)}


def robot_data(robot: dict) -> dict:
    """A robot as a submission of ``interface = "robot"`` receives it: plain data, numpy arrays and numbers.

    ``{"gravity": (3,), "joints": [...], "links": [...]}``, joint i of ``joints`` moving link i of ``links``:

    ===========  ==================================================================================
    joint key    value
    ===========  ==================================================================================
    ``name``     the joint's name
    ``parent``   the index of the link it hangs from, -1 for the fixed base
    ``type``     ``"revolute"`` or ``"prismatic"``
    ``axis``     (3,): its unit axis Ẑ in its own frame i
    ``xyz``      (3,): the origin of frame i in its parent's frame at θ = 0, m
    ``rpy``      (3,): the rotation of frame i in its parent's (URDF roll, pitch, yaw: R = Rz Ry Rx), rad
    ``origin``   (4, 4): the same placement as one homogeneous transform
    ===========  ==================================================================================

    A link has ``name``, ``mass`` (kg), ``com`` ((3,), the centre of mass in frame i, m) and ``inertia``
    ((3, 3), about the centre of mass, axes of frame i, kg·m²). ``gravity`` is g in the base frame, m/s².
    Every call gets its own copy, so a function that changes it changes nothing for the next.

    Parameters
    ----------
    robot : dict
        The robot as the plan sends it (lists of floats).

    Returns
    -------
    dict
        The same with numpy arrays for every vector and matrix.
    """
    def array(value):
        return np.array(value, dtype=float)

    return {"gravity": array(robot["gravity"]),
            "joints": [{"name": str(j["name"]), "parent": int(j["parent"]), "type": str(j["type"]),
                        "axis": array(j["axis"]), "xyz": array(j["xyz"]), "rpy": array(j["rpy"]),
                        "origin": array(j["origin"])} for j in robot["joints"]],
            "links": [{"name": str(link["name"]), "mass": float(link["mass"]), "com": array(link["com"]),
                       "inertia": array(link["inertia"])} for link in robot["links"]]}


def evaluate(namespace, functions: dict, path: str = "", robots=None, robot_of=None) -> dict:
    """Call each function of ``namespace`` named in ``functions`` on its argument lists.

    ``namespace`` is a module or a dict (a notebook's globals). Returns
    ``{"defined": [...], "results": {name: [record, ...]}}`` as in the module docstring.

    Parameters
    ----------
    namespace : module or dict
        Where the student's functions are.
    functions : dict of str to list
        Per function name, its argument lists (each argument a list of floats).
    path : str
        The submission's file, whose line an error names.
    robots : list of dict or None
        With ``interface = "robot"``, the robots as the plan sends them; each call's first argument is one of
        them as :func:`robot_data` makes it.
    robot_of : dict of str to list of int or None
        Per function name, the index in ``robots`` of each call's robot.

    Returns
    -------
    dict
        ``defined`` (the functions of :data:`FUNCTIONS` it defines) and ``results`` (per function called, one
        record per call: ``value`` and ``shape``, or ``error`` when the call failed or returned no usable array).

    Raises
    ------
    SystemExit, MemoryError, KeyboardInterrupt
        Whatever of these a student's function raises, passed on.
    """
    get = namespace.get if isinstance(namespace, dict) else (lambda name: getattr(namespace, name, None))
    defined = [name for name in FUNCTIONS if callable(get(name))]
    results = {}
    for name, calls in functions.items():
        function = get(name)
        if not callable(function):
            continue
        records = []
        which = (robot_of or {}).get(name, ())
        for index, arguments in enumerate(calls):
            limit = len(arguments[0]) ** 2 if arguments else 1  # as results.results_cap counts
            given = [robot_data(robots[which[index]])] if robots is not None else []
            try:
                records.append(_value(function(*given, *(np.array(a, dtype=float) for a in arguments)), limit))
            except (SystemExit, MemoryError, KeyboardInterrupt):
                raise
            except Exception as exc:  # the student's function failed on this call: a finding, not our failure
                records.append({"error": _where(exc, path)})
        results[name] = records
    return {"defined": defined, "results": results}


def run(plan: dict) -> dict:
    """Import the submission and evaluate it; every outcome becomes a status, never an exception.

    Parameters
    ----------
    plan : dict
        The plan (module docstring): ``module``, ``forbidden`` and ``functions``.

    Returns
    -------
    dict
        The results document (module docstring), its ``status`` one of :data:`STATUSES`.
    """
    path = plan["module"]
    AVAILABLE["packages"] = tuple(str(name) for name in plan.get("available", ("numpy",)))
    guard = ImportGuard(plan.get("forbidden", ()))
    outcome = {"status": "ok", "message": "", "defined": [], "results": {}, "forbidden_attempts": guard.attempts}
    try:
        with open(path, encoding="utf-8") as handle:
            source = handle.read()
        code = compile(source, path, "exec")
    except SyntaxError as exc:
        return dict(outcome, status="syntax error", message=f"{exc.msg} (line {exc.lineno})")
    except (UnicodeDecodeError, ValueError) as exc:
        return dict(outcome, status="syntax error", message=f"the file is not readable Python source: {exc}")
    sys.meta_path.insert(0, guard)
    spec = importlib.util.spec_from_loader("submission", loader=None, origin=path)
    module = importlib.util.module_from_spec(spec)
    module.__file__ = path
    sys.modules["submission"] = module
    try:
        exec(code, module.__dict__)
        outcome.update(evaluate(module, plan["functions"], path, plan.get("robots"), plan.get("robot_of")))
    except ForbiddenImport as exc:
        outcome.update(status="forbidden import", message=str(exc))
    except SystemExit as exc:
        outcome.update(status="exited", message=f"the submission called exit({exc.code!r})")
    except MemoryError:
        outcome.update(status="memory", message="the submission ran out of memory")
    except RecursionError as exc:
        outcome.update(status="crashed", message=_where(exc, path))
    except OSError as exc:
        status = "file access" if exc.errno in FILE_ERRORS else "crashed"
        outcome.update(status=status, message=_where(exc, path))
    except BaseException as exc:  # anything else the submission raised, KeyboardInterrupt included
        outcome.update(status="crashed", message=_where(exc, path))
    loaded = sorted({m.split(".")[0] for m in sys.modules} & set(plan.get("forbidden", ())))
    if (guard.attempts or loaded) and outcome["status"] == "ok":
        outcome.update(status="forbidden import", message=f"tried to import {', '.join(guard.attempts or loaded)}",
                       forbidden_attempts=list(dict.fromkeys([*outcome["forbidden_attempts"], *loaded])))
    return outcome


def main() -> None:
    """The script: read the plan on standard input, arm the integrity hook, run, write the results to RESULTS_FD.

    Started as ``python -I -S harness.py RESULTS_FD FLAGS_FD``; it ends the process itself (``os._exit``), so no
    handler the submission registered runs after the results are written.
    """
    global np
    results_fd, flags_fd = int(sys.argv[1]), int(sys.argv[2])
    write, close, digest, audit = os.write, os.close, hashlib.sha256, sys.audit  # whatever the submission rebinds
    setitimer, dumps, finishing = signal.setitimer, json.dumps, []
    plan = json.loads(sys.stdin.read())
    sys.stdin.close()
    sys.path[:0] = plan.get("path", [])
    sys.dont_write_bytecode = True  # a cache write into Python's folders would be the harness's, not a flag
    import numpy as np

    def finish(outcome: dict) -> None:  # the results, bound to the channel's closing line, then the end
        if finishing:  # a second signal while the results are written
            return
        finishing.append(True)
        setitimer(signal.ITIMER_REAL, 0)
        data = dumps(outcome).encode()
        audit(END_EVENT, digest(data).hexdigest())  # the closing line, bound to these very results
        while data:  # os.write, as it was before the submission ran: no file opened after arming
            data = data[write(results_fd, data):]
        close(results_fd)
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(0)  # no student atexit handler runs after the results are written

    def out_of_time(signum, frame):  # CPU (SIGXCPU) or wall clock (our alarm): say where the submission was
        limit = (f"used more than {plan.get('time_limit', 0):g} s of CPU time" if signum == signal.SIGXCPU else
                 f"still running after {plan.get('wall_seconds', 0):g} s of wall-clock time")
        finish({"status": "timeout", "message": limit + _place(frame, plan["module"]), "defined": [], "results": {},
                "forbidden_attempts": []})

    signal.signal(signal.SIGXCPU, out_of_time)  # before arming: the hook knows them as the harness's
    if float(plan.get("wall_seconds", 0)) > 2 * WALL_MARGIN:
        signal.signal(signal.SIGALRM, out_of_time)
        setitimer(signal.ITIMER_REAL, float(plan["wall_seconds"]) - WALL_MARGIN)
    writable = [os.getcwd()]  # not /tmp, even the sandbox's private one: a probe writes there first
    own = [os.path.dirname(os.path.abspath(plan["module"])), os.getcwd()]
    sys.addaudithook(integrity.integrity_hook(flags_fd, own, _library(plan), writable, plan.pop("nonce", ""),
                                              plan.get("forbidden", ()), [__file__], main.__code__, finish.__code__))
    # Only the interpreter holds the hook now, and only the hook the key: the nonce is gone from the plan.
    outcome = run(plan)
    imported = []
    audit(IMPORTS_EVENT, imported)  # the forbidden imports the hook saw, whatever sys.modules says now
    if imported and outcome["status"] == "ok":
        outcome.update(status="forbidden import", message=f"tried to import {', '.join(imported)}",
                       forbidden_attempts=list(dict.fromkeys([*outcome["forbidden_attempts"], *imported])))
    finish(outcome)


def _library(plan: dict) -> list[str]:
    """The standard library and the allowed packages (links followed)."""
    folders = [os.path.dirname(os.__file__)]
    for site in plan.get("path", []):
        folders.append(site)
        try:
            folders += [os.path.realpath(os.path.join(site, name)) for name in os.listdir(site)]
        except OSError:
            pass
    return folders



__all__ = ["FUNCTIONS", "MAX_DIMENSIONS", "MAX_VALUES", "STATUSES", "ForbiddenImport", "ImportGuard", "evaluate",
           "main", "robot_data", "run"]


if __name__ == "__main__":
    main()
