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
channel FLAGS_FD, before the attempt itself proceeds. The hook ends the channel
itself, when the harness raises END_EVENT, with a line holding the run's nonce
(given in the plan, held by the hook alone); a channel without it was closed or
redirected by the submission, or the hook was switched off: itself a flag.
Flags are leads for the instructor, never a score: a submission can hide a flag
by going below Python (a C call through ctypes, itself flagged when loaded from
Python), and the sandbox, not the hook, is what keeps it in.

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
    "tampered": "reached for the integrity hook: replaced a function's code, made a function of Python's code, added an "
                "audit hook or a trace function, ran code inside the hook or raised its closing event",
    "import-outside": "imported a module from a folder outside the interpreter's path as the harness set it up",
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
END_EVENT = "course_dynamics.harness.end"  # main() raises it once the submission has run: the channel's last line


def integrity_hook(fd: int, own, library, writable, nonce: str):
    """The audit hook behind the integrity flags (module docstring); :func:`main` ends its channel with END_EVENT.

    Each attempt is one line ``code<TAB>detail`` on ``fd``, written before the attempt proceeds, once per distinct
    attempt and at most MAX_FLAG_LINES per code. The submission's business are the files and listings of ``own`` (its
    folder, its working folder) and ``library`` (Python's standard library, the allowed packages); ``writable`` is its
    working folder. The hook runs on copies made here, before any submission exists, of the harness's globals, the
    builtins, ``os``, ``sys`` and ``os.path`` (its functions with globals of their own): rewriting a module's names or
    a function's code changes nothing it calls. No frame the submission can climb to holds any of its state, and the
    hook itself writes the channel's closing line when the harness (no code of the submission's) raises END_EVENT: a
    hook switched off by any means leaves the channel unclosed, the flag ``channel-closed``.
    """
    import builtins
    import posixpath
    import stat
    import types

    space = types.SimpleNamespace
    path = dict(vars(posixpath), os=space(**vars(os)), stat=space(**vars(stat)))
    for name, value in list(path.items()):
        if type(value) is types.FunctionType:
            path[name] = types.FunctionType(value.__code__, path, name, value.__defaults__, value.__closure__)
            path[name].__kwdefaults__ = value.__kwdefaults__
    private = dict(globals(), __builtins__=dict(vars(builtins)), sys=space(**vars(sys)),
                   os=space(**dict(vars(os), path=space(**path))))
    return types.FunctionType(_integrity_hook.__code__, private)(fd, own, library, writable, nonce)


def _integrity_hook(fd, own, library, writable, nonce):
    """integrity_hook's body, run with its private globals.

    The submission's code is every code object the interpreter did not hold when the hook was made (``known``: every
    function's then, the frames on the stack), except a module's code that is what its file in Python's installation
    compiles to, or a frozen module's own, whoever runs it: names (a code object's file name) are never evidence. An
    event whose stack reaches importlib's entry (``_find_and_load``) before any code of the submission's is an import's
    work, and a frame lookup counts when the submission's code makes it directly or when it returns a frame of the
    harness's to a stack that holds the submission's code (warnings, inspect and namedtuple look up frames too). The
    hook calls nothing of the submission's (an argument is read only when it is exactly a str, bytes, int or a list
    of them); an event raised while it runs that its own code did not raise (a finalizer, a callback) is ``tampered``.
    """
    import _imp
    import _thread
    import gc
    import importlib._bootstrap as bootstrap
    import types

    code_type, frame_type, function_type, getframe, ident = types.CodeType, types.FrameType, types.FunctionType, \
        sys._getframe, _thread.get_ident
    realpath, join, write_fd = os.path.realpath, os.path.join, os.write
    known, own_code, written, counts, busy, checking = set(), set(), set(), {}, set(), set()

    def learn(code, into) -> None:
        pending = [code]
        while pending:
            code = pending.pop()
            if code not in into:
                into.add(code)
                pending += [c for c in code.co_consts if type(c) is code_type]

    learn(getframe().f_code, own_code)
    for code in [t.__code__ for t in gc.get_objects() if type(t) is function_type]:
        learn(code, known)
    frame = getframe()
    while frame is not None:
        learn(frame.f_code, known)
        frame = frame.f_back
    harness = {c for c in known if c.co_filename == __file__}
    entry, removed, closer = bootstrap._find_and_load.__code__, bootstrap._call_with_frames_removed.__code__, main.__code__
    main_thread = ident()

    def roots(folders) -> tuple:
        return tuple(join(realpath(r), "") for r in folders if type(r) is str and r)

    library, writable = roots(library) + roots([__file__]), roots(writable)  # a traceback quotes this file
    readable = roots(own) + library
    importable = readable + roots(sys.path)  # the path as it stands now, before the submission runs
    anyone = {"/dev/null/", "/dev/urandom/"}

    def text(value) -> str:
        """An argument as text, with nothing of the submission's called (no __str__, __fspath__ or __eq__)."""
        kind = type(value)
        if kind is str or kind is int or kind is float or kind is bytes:
            return value.decode("utf-8", "replace") if kind is bytes else str(value)
        if kind is list or kind is tuple:
            return " ".join(text(v) for v in value[:8])
        return f"(an object of type {kind.__qualname__ if type(kind) is type else 'unknown'})"

    def path_flag(path, code):
        if type(path) is int:
            return code, f"file descriptor {path}"
        if type(path) is bytes:
            path = path.decode("utf-8", "surrogateescape")
        if type(path) is not str:
            return code, f"a path given as {text(path)}, not converted (its conversion would be the submission's code)"
        if not path.startswith("/") and ".." in path.replace("\\", "/").split("/"):
            return code, path  # relative to what (a dir_fd is not in the event)? climbing out is a lead anyway
        where = join(realpath(path), "")
        if where.startswith(writable if code == "file-write" else readable) or where in anyone:
            return None
        return code, path

    def flag(event, args):
        """(code, detail, rule) for an event that is a flag when the submission did it; rule says how to tell."""
        first, second = (*args[:2], None, None)[:2]
        if event == "open":
            writing = bool(args[2] & WRITE_BITS) if type(args[2]) is int else any(c in text(args[1]) for c in "wax+")
            found = path_flag(first, "file-write" if writing else "file-read")
        elif event in LISTINGS:
            found = path_flag("." if first is None else first, "list-folder")
        elif event in FILE_CHANGES:
            found = next(filter(None, (path_flag(p, "file-write") for p in args[:2] if p is not None and type(p) is not int)),
                         None)
        elif event in PROCESS_EVENTS:
            found = "process", f"{event} {text(first)}"
        elif event.startswith(("socket.", "ctypes.")):
            found = event.split(".")[0], f"{event} {text(second if event.startswith('socket.') else first)}"
        elif event.startswith("gc."):
            return "introspection", event, "always"
        elif event in ("sys.settrace", "sys.setprofile", "sys.addaudithook"):
            found = "tampered", event
        elif type(first) is frame_type and first.f_code in harness and event in ("sys._getframe", "object.__getattr__"):
            found = "introspection", "a frame of the harness's"
        elif event in INTROSPECTION:
            return "introspection", event, "direct"
        elif event == "object.__getattr__" and type(second) is str and second in FRAME_ATTRIBUTES:
            return "introspection", f"the attribute {second}", "direct"
        elif event == "object.__setattr__" and type(second) is str and second == "__code__":
            found = "tampered", "replaced a function's code"
        elif event == "function.__new__" and type(first) is code_type and first in known:
            return "tampered", "made a function of the harness's or Python's code", "direct"
        elif event in ("compile", "code.__new__") and type(second) is str and second.startswith("/") \
                and join(realpath(second), "").startswith(library):
            return "introspection", f"made code under the name of {second}, a file of Python's or the harness's", \
                "direct"
        else:
            return None
        return found and (*found, "stack")

    def whose(frame) -> str:
        """"theirs" (code of the submission's before importlib's entry), "import" (a library loading itself),
        "thread" (the bottom of a thread it started: the harness starts none) or "" (the harness's own work)."""
        while frame is not None and frame.f_code is not entry and frame.f_code in known:
            frame = frame.f_back
        if frame is not None:
            return "import" if frame.f_code is entry else "theirs"
        return "thread" if ident() != main_thread else ""

    def trusted(code) -> bool:
        """Whether a module's code is what its file in Python's installation compiles to, or a frozen module's."""
        name = code.co_filename
        try:
            if name.startswith("<frozen ") and name.endswith(">"):
                return code == _imp.get_frozen_object(name[8:-1])
            if not name.startswith("/") or not join(realpath(name), "").startswith(library):
                return False
            with open(name, "rb") as handle:
                return code == compile(handle.read(), name, "exec", dont_inherit=True)
        except (ImportError, OSError, SyntaxError, ValueError):
            return False

    def write(code, detail):
        detail = "".join(c if c.isprintable() else f"\\x{ord(c):02x}" for c in " ".join(detail.split()))[:MAX_FLAG_DETAIL]
        if (code, detail) in written or counts.get(code, 0) >= MAX_FLAG_LINES:
            return
        written.add((code, detail))
        counts[code] = counts.get(code, 0) + 1
        write_fd(fd, f"\n{code}\t{detail}\n".encode("utf-8", "replace"))  # a line of its own, whatever came before

    def hook(event, args):
        me = ident()
        if me in busy:  # raised while the hook runs: by its own code (a frame lookup), or by someone else's
            if me not in checking:
                checking.add(me)
                try:
                    if getframe(1).f_code not in own_code:
                        write("tampered", f"{event}, raised by other code while the integrity hook ran")
                finally:
                    checking.discard(me)
            return
        busy.add(me)
        try:
            raiser = getframe(1)  # 0 is the hook, 1 the frame that raised the event
            if event == END_EVENT:
                if raiser.f_code is closer and whose(raiser) == "":
                    write_fd(fd, f"\nend\t{nonce}\n".encode())
                else:
                    write("tampered", "raised the harness's closing event")
                return
            if event == "exec" and type(args[0]) is code_type and args[0] not in known:
                if trusted(args[0]):
                    learn(args[0], known)
                name = args[0].co_filename
                if raiser.f_code is removed and name.startswith("/") \
                        and not join(realpath(name), "").startswith(importable):
                    write("import-outside", name)
            found = flag(event, args)
            if found is None:
                return
            code, detail, rule = found
            who = whose(raiser) if rule == "stack" else ""
            if code == "list-folder" and who == "import" and not join(realpath(detail), "").startswith(importable):
                write("import-outside", f"searched {detail}")
            if rule == "always" or (rule == "direct" and raiser.f_code not in known) or who in ("theirs", "thread") \
                    or (who == "import" and code in ("process", "socket", "ctypes")):
                write(code, detail)
        except RecursionError:  # a recursion limit set to starve the hook: that itself is the flag
            try:
                write_fd(fd, b"\ntampered\tthe recursion limit was set too low for the integrity hook to run\n")
            except OSError:
                pass
        except Exception:  # the hook never disturbs the submission, whatever its arguments are
            pass
        finally:
            busy.discard(me)

    return hook


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
    hook = integrity_hook(flags_fd, own, _library(plan), writable, plan.pop("nonce", ""))  # the nonce is the hook's
    sys.addaudithook(hook)
    del hook  # only the interpreter holds the hook now: no frame the submission can climb to leads to it
    outcome = run(plan)
    sys.audit(END_EVENT)  # the hook writes the channel's closing line, if it is still the hook the harness added
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
