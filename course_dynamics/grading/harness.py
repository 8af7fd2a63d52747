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

Integrity flags: before the submission runs, :func:`integrity_hook` (a Python
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
    "introspection": "read the interpreter's frames or object lists (sys._getframe, a traceback's frames, gc), where "
                     "the harness's state is",
    "channel-closed": "the integrity channel was closed, redirected or written to by the submission",
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
FRAME_ATTRIBUTES = ("tb_frame", "gi_frame", "cr_frame", "ag_frame", "f_back")


def integrity_hook(fd: int, own, library, writable, nonce: str):
    """The audit hook behind the integrity flags (module docstring), and the function that ends its channel.

    Each attempt is one line ``code<TAB>detail`` on ``fd``, written before the attempt proceeds, once per
    distinct attempt and at most MAX_FLAG_LINES per code. The folders whose files and listings are the
    submission's business are ``own`` (its folder, its working folder) and ``library`` (Python's standard
    library and the allowed packages); ``writable`` is its working folder.

    Which code is the submission's: every frame whose code is not Python's or the harness's (the submission,
    a module it wrote and imported, code it compiled, whatever name it gave it). An event whose stack reaches
    importlib's entry (``_find_and_load``) before any such frame is an import's work (a library loading
    itself), and a frame lookup counts only when the submission's code makes it directly (the standard
    library's warnings and namedtuple look up frames too).

    Everything the hook uses lives in this closure, not in module globals or a class a submission could patch
    without an audit event; replacing the hook's code is itself an event, and flagged.
    """
    import _thread
    import importlib._bootstrap as bootstrap
    import importlib._bootstrap_external as external

    def codes(modules) -> set:
        found = set()
        for module in modules:
            for value in list(vars(module).values()):
                for function in [value, *(list(vars(value).values()) if isinstance(value, type) else ())]:
                    function = getattr(function, "__func__", function)
                    if hasattr(function, "__code__"):
                        found.add(function.__code__)
        return found

    main_thread = _thread.get_ident()
    importer = codes((bootstrap, external))
    entry = bootstrap._find_and_load.__code__  # where every import statement enters importlib
    # Frozen modules (os, posixpath, codecs, importlib's) have no file: their code objects are known instead,
    # so that a submission's code compiled under a name like "<frozen os>" is still its own.
    frozen = codes([m for m in list(sys.modules.values())
                    if getattr(getattr(m, "__spec__", None), "origin", None) == "frozen"]) | importer
    library = tuple(os.path.join(os.path.realpath(r), "") for r in library)
    this_file = os.path.realpath(__file__)
    readable = tuple(os.path.join(os.path.realpath(r), "") for r in own) + library
    writable = tuple(os.path.join(os.path.realpath(w), "") for w in writable)
    anyone = {"/dev/null/", "/dev/urandom/", os.path.join(this_file, "")}  # a traceback quotes this file
    state = {"armed": False, "busy": False, "counts": {}}
    written = set()
    theirs = set()  # code objects the submission ran through exec, whatever file name they were given

    def ours(code) -> bool:
        """Whether this code object is the submission's (see above)."""
        if code in theirs:
            return True
        if code in frozen:
            return False
        if not code.co_filename.startswith("/"):
            return True  # compiled from a string, or a frozen module's name borrowed
        path = os.path.realpath(code.co_filename)
        return not (path == this_file or path.startswith(library))

    def path_flag(path, code):
        if isinstance(path, int):
            return code, f"file descriptor {path}"
        if isinstance(path, bytes):
            path = os.fsdecode(path)
        path = os.fspath(path)
        if not os.path.isabs(path) and ".." in path.replace("\\", "/").split("/"):
            return code, path  # relative to what (a dir_fd is not in the event)? climbing out is a lead anyway
        where = os.path.join(os.path.realpath(path), "")
        allowed = writable if code == "file-write" else readable
        if where.startswith(allowed) or where in anyone:
            return None
        return code, path

    def flag(event, args):
        if event == "open":
            path, mode, flags = args
            writing = bool(flags & WRITE_BITS) if isinstance(flags, int) else any(c in str(mode) for c in "wax+")
            return path_flag(path, "file-write" if writing else "file-read")
        if event in LISTINGS:
            return path_flag(args[0] if args and args[0] is not None else ".", "list-folder")
        if event in FILE_CHANGES:
            for path in args[:2]:
                if isinstance(path, (str, bytes, os.PathLike)):
                    found = path_flag(path, "file-write")
                    if found is not None:
                        return found
            return None
        if event in PROCESS_EVENTS:
            return "process", f"{event} {args[0] if args else ''}"
        if event.startswith("socket."):
            return "socket", f"{event} {args[1] if len(args) > 1 else ''}"
        if event.startswith("ctypes."):
            return "ctypes", f"{event} {args[0] if args else ''}"
        if event in INTROSPECTION or (event == "object.__getattr__" and len(args) > 1 and args[1] in FRAME_ATTRIBUTES):
            return "introspection", event if event != "object.__getattr__" else f"the attribute {args[1]}"
        if event in ("object.__setattr__", "object.__delattr__") and args and args[0] is hook:
            return "introspection", f"{event} {args[1] if len(args) > 1 else ''} of the integrity hook itself"
        if event == "compile" and len(args) > 1 and isinstance(args[1], str) and args[1].startswith("/"):
            where = os.path.join(os.path.realpath(args[1]), "")
            if where.startswith(library) or where == os.path.join(this_file, ""):
                return "introspection", f"compiled code under the name of {args[1]}, a file of Python's or the harness's"
        return None

    def remember(code) -> None:
        """A code object the submission runs, and every function defined in it, as the submission's own."""
        pending = [code]
        while pending:
            code = pending.pop()
            if code not in theirs:
                theirs.add(code)
                pending += [c for c in code.co_consts if hasattr(c, "co_consts")]

    def attributed(code: str) -> bool:
        """Whether the event is the submission's doing. An import's work is not, unless it starts processes,
        sockets or native code (an import with side effects of that kind is itself a lead); the bottom of a
        stack without the submission's code is a thread or a finalizer it started, and is its doing."""
        frame = sys._getframe(2)  # 0 here, 1 the hook, 2 the frame that raised the event
        if code == "introspection":
            return frame is not None and ours(frame.f_code)
        while frame is not None:
            if frame.f_code is entry:  # an import, with no code of the submission's on the way
                return code in ("process", "socket", "ctypes")
            if ours(frame.f_code):
                return True
            frame = frame.f_back
        # The bottom of the stack: in the main thread the harness's own work; in another, a thread the submission
        # started (the harness starts none).
        return _thread.get_ident() != main_thread

    def write(code, detail):
        detail = "".join(c if c.isprintable() else f"\\x{ord(c):02x}" for c in " ".join(str(detail).split()))
        detail = detail[:MAX_FLAG_DETAIL]
        counts = state["counts"]
        if (code, detail) in written or counts.get(code, 0) >= MAX_FLAG_LINES:
            return
        written.add((code, detail))
        counts[code] = counts.get(code, 0) + 1
        os.write(fd, f"\n{code}\t{detail}\n".encode("utf-8", "replace"))  # a line of its own, whatever came before

    def hook(event, args):
        if not state["armed"] or state["busy"]:  # busy: an event raised by the hook itself (its own sys._getframe)
            return
        state["busy"] = True
        try:
            if event == "exec" and args and hasattr(args[0], "co_consts") and attributed("exec"):
                remember(args[0])
            found = flag(event, args)
            if found is not None and (event.startswith("gc.") or attributed(found[0])):
                write(*found)
        except RecursionError:  # a recursion limit set to starve the hook: that itself is the flag
            try:
                os.write(fd, b"\nintrospection\tthe recursion limit was set too low for the integrity hook to run\n")
            except OSError:
                pass
        except Exception:  # the hook never disturbs the submission, whatever its arguments are
            pass
        finally:
            state["busy"] = False

    def arm():
        state["armed"] = True

    def end():
        """The channel's last line; written only by the harness, after the submission has run."""
        state["armed"] = False
        try:
            os.write(fd, f"\nend\t{nonce}\n".encode())
            os.close(fd)
        except OSError:
            pass

    return hook, arm, end


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
        outcome.update(status="forbidden import", message=f"tried to import {', '.join(guard.attempts or loaded)}")
    return outcome


def main() -> None:
    global np
    results_fd, flags_fd = int(sys.argv[1]), int(sys.argv[2])
    plan = json.loads(sys.stdin.read())
    sys.stdin.close()
    sys.path[:0] = plan.get("path", [])
    sys.dont_write_bytecode = True  # a cache write into Python's folders would be the harness's, not a flag
    import numpy as np
    writable = [os.getcwd()]  # not /tmp, even the sandbox's private one: a probe writes there first
    own = [os.path.dirname(os.path.abspath(plan["module"])), os.getcwd()]
    hook, arm, end = integrity_hook(flags_fd, own, _library(plan), writable, plan.pop("nonce", ""))
    sys.addaudithook(hook)
    arm()
    del hook, arm  # nothing of the hook stays within the submission's reach but its channel
    outcome = run(plan)
    end()
    data = json.dumps(outcome).encode()
    with os.fdopen(results_fd, "wb") as channel:
        channel.write(data)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)  # no student atexit handler runs after the results are written


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


if __name__ == "__main__":
    main()
