"""Runs one student's submission and evaluates its functions on a plan of calls.

This file is the only code of ours that runs next to student code. In grading
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

Integrity flags: before the submission runs, :class:`IntegrityHook` (a Python
audit hook, which cannot be removed once added) records what it tries that a
dynamics answer never needs (:data:`FLAGS`), each line written at once on the
channel FLAGS_FD, before the attempt itself proceeds. The harness ends the
channel with a line holding the run's nonce (given in the plan, kept out of the
submission's namespace); a channel without it was closed or redirected by the
submission, itself a flag. Flags are leads for the instructor, never a score:
a submission can hide a flag by going below Python (a C call through ctypes,
itself flagged when loaded from Python), and the sandbox, not the hook, is what
keeps it in.

Plan: ``{"module": path, "path": [folders], "forbidden": [names], "nonce": text,
"functions": {name: [[arg, …], …]}}``
where each argument is a list of floats (one state vector).

Results: ``{"status", "message", "defined", "forbidden_attempts",
"results": {name: [{"value": nested floats} or {"error": text}, …]}}``.
Statuses: ``ok``, ``syntax error``, ``forbidden import``, ``exited``,
``memory``, ``file access``, ``crashed``.
"""
from __future__ import annotations

import errno
import importlib.abc
import importlib.util
import json
import os
import sys
import traceback

try:  # in grading, numpy is importable only once main() has put the plan's folders on the path
    import numpy as np
except ImportError:
    np = None

FUNCTIONS = ("tau", "M", "V", "G", "C")
STATUSES = ("ok", "syntax error", "forbidden import", "exited", "memory", "file access", "crashed")
MAX_VALUES = 10_000  # a returned array larger than this is reported, not sent back
MAX_DIMENSIONS = 3   # nor one of more dimensions (M and C have two)
FILE_ERRORS = (errno.EROFS, errno.EACCES, errno.EPERM)

# Integrity flags: code -> what the submission tried (the instructor's summary prints these words).
FLAGS = {
    "file-read": "opened a file outside its own folder, its working folder and Python's installation",
    "file-write": "wrote, made, moved or removed a file outside its working folder",
    "list-folder": "listed a folder outside its own folder, its working folder and Python's installation",
    "process": "started, replaced or signalled a process (os.system, subprocess, fork, exec, kill)",
    "socket": "opened a network socket or looked up a host",
    "ctypes": "loaded or called native code through ctypes",
    "introspection": "read the interpreter's frames or object lists (sys._getframe, gc), where the harness's state is",
    "channel-closed": "the integrity channel was closed or redirected before the run ended",
}
MAX_FLAG_LINES = 50  # lines the hook writes at most per code (each distinct attempt once): a flood hides no other
MAX_FLAG_DETAIL = 200  # characters of a flag's detail (a path, a command)
WRITE_BITS = os.O_WRONLY | os.O_RDWR | os.O_APPEND | os.O_CREAT | os.O_TRUNC
FILE_CHANGES = ("os.remove", "os.rename", "os.mkdir", "os.rmdir", "os.chmod", "os.chown", "os.link", "os.symlink",
                "os.truncate", "os.utime", "shutil.rmtree", "shutil.copyfile", "shutil.move")
PROCESS_EVENTS = ("os.system", "os.exec", "os.posix_spawn", "os.spawn", "os.fork", "os.forkpty", "subprocess.Popen",
                  "pty.spawn", "os.kill", "os.killpg", "os.startfile")
LISTINGS = ("os.listdir", "os.scandir", "glob.glob")
INTROSPECTION = ("sys._getframe", "sys._current_frames", "gc.get_objects", "gc.get_referrers", "gc.get_referents")


class IntegrityHook:
    """The audit hook behind the integrity flags (module docstring): one line ``code<TAB>detail`` per attempt.

    ``readable`` are the folders whose files and listings are the submission's
    business (its own folder, its working folder, Python's standard library and
    its allowed packages), ``writable`` its working folder. Events during an
    import (a frame of importlib on the stack) are the importer's work: a
    library loading itself is no flag, whoever imported it.
    """

    def __init__(self, fd: int, submission: str, readable, writable):
        self.fd, self.submission, self.armed, self.busy, self.written, self.counts = fd, submission, False, False, set(), {}
        self.readable = tuple(os.path.join(os.path.realpath(r), "") for r in readable)
        self.writable = tuple(os.path.join(os.path.realpath(w), "") for w in writable)
        # Files anyone may open: the null devices, and this file (a traceback of the student's error quotes it).
        self.files = {"/dev/null/", "/dev/urandom/", os.path.join(os.path.realpath(__file__), "")}

    def __call__(self, event, args):
        if not self.armed or self.busy:  # busy: an event raised by the hook itself (its own sys._getframe)
            return
        self.busy = True
        try:
            found = self._flag(event, args)
            if found is not None and self._attributed(found[0]):
                self._write(*found)
        except Exception:  # the hook never disturbs the submission, whatever its arguments are
            pass
        finally:
            self.busy = False

    def _flag(self, event, args):
        if event == "open":
            path, mode, flags = args
            writing = bool(flags & WRITE_BITS) if isinstance(flags, int) else any(c in str(mode) for c in "wax+")
            if isinstance(path, int):
                return ("file-write" if writing else "file-read"), f"file descriptor {path}"
            return self._path_flag(path, "file-write" if writing else "file-read")
        if event in LISTINGS:
            return self._path_flag(args[0] if args and args[0] is not None else ".", "list-folder")
        if event in FILE_CHANGES:
            for path in args[:2]:
                if isinstance(path, (str, bytes, os.PathLike)):
                    found = self._path_flag(path, "file-write")
                    if found is not None:
                        return found
            return None
        if event in PROCESS_EVENTS:
            return "process", f"{event} {args[0] if args else ''}"
        if event.startswith("socket."):
            return "socket", f"{event} {args[1] if len(args) > 1 else ''}"
        if event.startswith("ctypes."):
            return "ctypes", f"{event} {args[0] if args else ''}"
        if event in INTROSPECTION:
            return "introspection", event
        return None

    def _path_flag(self, path, code):
        if isinstance(path, bytes):
            path = os.fsdecode(path)
        where = os.path.join(os.path.realpath(os.fspath(path)), "")
        allowed = self.writable if code == "file-write" else self.readable
        if where.startswith(allowed) or where in self.files:
            return None
        return code, os.fspath(path)

    def _attributed(self, code: str) -> bool:
        """Whether the event is the submission's doing: not an import's; a frame lookup only from its own code (or
        one call away: ``inspect.currentframe``), since the standard library's warnings look up frames too."""
        frame = sys._getframe(2)  # 0 here, 1 __call__, 2 the frame that raised the event
        if code == "introspection" and frame is not None:
            near = [frame.f_code.co_filename, frame.f_back.f_code.co_filename if frame.f_back else ""]
            if self.submission not in near:
                return False
        while frame is not None:
            if frame.f_code.co_filename.startswith("<frozen importlib"):
                return False
            frame = frame.f_back
        return True

    def _write(self, code, detail):
        detail = " ".join(str(detail).split())[:MAX_FLAG_DETAIL]
        if (code, detail) in self.written or self.counts.get(code, 0) >= MAX_FLAG_LINES:
            return
        self.written.add((code, detail))
        self.counts[code] = self.counts.get(code, 0) + 1
        os.write(self.fd, f"{code}\t{detail}\n".encode("utf-8", "replace"))

    def end(self, nonce: str) -> None:
        """The channel's last line; written only by the harness, after the submission has run."""
        self.armed = False
        try:
            os.write(self.fd, f"end\t{nonce}\n".encode())
            os.close(self.fd)
        except OSError:
            pass


class ForbiddenImport(ImportError):
    """A submission imported a module the assignment forbids."""


class ImportGuard(importlib.abc.MetaPathFinder):
    """Refuses the forbidden top-level modules and remembers every attempt."""

    def __init__(self, forbidden):
        self.forbidden = set(forbidden)
        self.attempts: list[str] = []

    def find_spec(self, fullname, path=None, target=None):
        if fullname.split(".")[0] in self.forbidden:
            if fullname not in self.attempts:
                self.attempts.append(fullname)
            raise ForbiddenImport(f"import of '{fullname}' is not allowed in this assignment")
        return None


def _where(exc: BaseException, path: str) -> str:
    """``Type: message (line N)``, N the last line of the submission in the traceback."""
    line = ""
    for frame in traceback.extract_tb(exc.__traceback__):
        if frame.filename == path:
            line = f" (line {frame.lineno})"
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    return f"{type(exc).__name__}{': ' + text[:300] if text else ''}{line}"


def _value(result):
    """A returned value as nested floats, or an error record that says why it cannot be one."""
    try:
        if np.iscomplexobj(np.asarray(result)):
            return {"error": "returned complex numbers; every term is real (a square root of a negative number?)"}
        array = np.asarray(result, dtype=float)
    except (TypeError, ValueError):
        kind = type(result).__name__
        return {"error": f"returned {kind if result is not None else 'None'}, expected numbers"}
    if array.size > MAX_VALUES:
        return {"error": f"returned {array.size} values"}
    if array.ndim > MAX_DIMENSIONS:
        return {"error": f"returned an array of {array.ndim} dimensions"}
    return {"value": array.tolist(), "shape": list(array.shape)}


def evaluate(namespace, functions: dict, path: str = "") -> dict:
    """Call each function of ``namespace`` named in ``functions`` on its argument lists.

    ``namespace`` is a module or a dict (a notebook's globals). Returns
    ``{"defined": [...], "results": {name: [record, ...]}}`` as in the module docstring.
    """
    get = namespace.get if isinstance(namespace, dict) else (lambda name: getattr(namespace, name, None))
    defined = [name for name in FUNCTIONS if callable(get(name))]
    results = {}
    for name, calls in functions.items():
        function = get(name)
        if not callable(function):
            continue
        records = []
        for arguments in calls:
            try:
                records.append(_value(function(*(np.array(a, dtype=float) for a in arguments))))
            except (SystemExit, MemoryError, KeyboardInterrupt):
                raise
            except Exception as exc:  # the student's function failed on this call: a finding, not our failure
                records.append({"error": _where(exc, path)})
        results[name] = records
    return {"defined": defined, "results": results}


def run(plan: dict) -> dict:
    """Import the submission and evaluate it; every outcome becomes a status, never an exception."""
    path = plan["module"]
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
        outcome.update(evaluate(module, plan["functions"], path))
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
        outcome.update(status="forbidden import", message=f"imported {', '.join(guard.attempts or loaded)}")
    return outcome


def main() -> None:
    global np
    results_fd, flags_fd = int(sys.argv[1]), int(sys.argv[2])
    plan = json.loads(sys.stdin.read())
    sys.stdin.close()
    nonce = plan.pop("nonce", "")
    sys.path[:0] = plan.get("path", [])
    sys.dont_write_bytecode = True  # a cache write into Python's folders would be the harness's, not a flag
    import numpy as np
    hook = IntegrityHook(flags_fd, plan["module"], readable=_readable(plan), writable=[os.getcwd()])
    sys.addaudithook(hook)
    hook.armed = True
    outcome = run(plan)
    hook.end(nonce)
    data = json.dumps(outcome).encode()
    with os.fdopen(results_fd, "wb") as channel:
        channel.write(data)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)  # no student atexit handler runs after the results are written


def _readable(plan: dict) -> list[str]:
    """The submission's folder, its working folder, the standard library, the allowed packages (links followed)."""
    folders = [os.path.dirname(os.path.abspath(plan["module"])), os.getcwd(), os.path.dirname(os.__file__)]
    for site in plan.get("path", []):
        folders.append(site)
        try:
            folders += [os.path.realpath(os.path.join(site, name)) for name in os.listdir(site)]
        except OSError:
            pass
    return folders


if __name__ == "__main__":
    main()
