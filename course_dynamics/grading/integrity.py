"""The integrity hook: a Python audit hook in the submission's own interpreter that records what it tries.

Like :mod:`~course_dynamics.grading.harness`, this file runs beside student code and imports nothing but the
standard library; the harness loads it by its path (the sandbox binds it next to the harness), and the grader
imports it for the channel's keys (:func:`first_key`, :func:`next_key`, :func:`tag`).

The channel: every line the hook writes is ``code<TAB>detail<TAB>tag``, the tag an HMAC of ``code<TAB>detail``
under a key that moves on after every line (``next_key``, a hash: the hook holds only the current key, never the
nonce, so a key read from the hook's memory forges no earlier line). The grader, who has the nonce, checks each tag;
a line that fails is the submission's (``channel-closed``). The last line, ``end<TAB>digest<TAB>tag``, binds the
SHA-256 of the results document the harness is about to write: a closing line forged before the harness's end would
have to know that document, and a line after it is refused. The hook withholds the closing line once it has seen
tampering, and ``tampered`` is never capped.
"""
from __future__ import annotations

import hashlib
import hmac
import os
import sys

#: The integrity flags, code -> what the submission tried (the instructor's summary prints these words).
FLAGS = {
    "file-read": "opened a file outside its own folder, its working folder and Python's installation",
    "file-write": "wrote, made, moved or removed a file outside its working folder",
    "list-folder": "listed a folder outside its own folder, its working folder and Python's installation",
    "process": "started, replaced or signalled a process (os.system, subprocess, fork, exec, kill)",
    "socket": "opened a network socket or looked up a host",
    "ctypes": "loaded or called native code through ctypes",
    "introspection": "read the interpreter's frames, object lists or addresses (sys._getframe, a traceback's frames, "
                     "gc, id), where the harness's state is",
    "tampered": "reached for the integrity hook: replaced a function's code, made a function of Python's code, "
                "added an audit hook, a trace function, a signal handler or a gc callback, ran code inside the hook "
                "or raised its closing event",
    "import-outside": "imported a module from a folder outside the interpreter's path as the harness set it up",
    "channel-closed": "the integrity channel was closed, redirected or written to by the submission",
    "generated-code": "holds the code course-dynamics itself writes for the student's robot (derive's closed forms, "
                      "a compiled model's module), found by the grader's similarity check, not by the hook",
}
#: The most lines the hook writes per flag code, ``tampered`` excepted (each distinct attempt once).
MAX_FLAG_LINES = 50  # lines the hook writes at most per code but tampered (each distinct attempt once)
#: The most characters of a flag's detail (a path, a command).
MAX_FLAG_DETAIL = 200  # characters of a flag's detail (a path, a command)
TAG_CHARS = 32  # hex characters of a line's tag
WRITE_BITS = os.O_WRONLY | os.O_RDWR | os.O_APPEND | os.O_CREAT | os.O_TRUNC
FILE_CHANGES = ("os.remove", "os.rename", "os.mkdir", "os.rmdir", "os.chmod", "os.chown", "os.link", "os.symlink",
                "os.truncate", "os.utime", "shutil.rmtree", "shutil.copyfile", "shutil.move")
PROCESS_EVENTS = ("os.system", "os.exec", "os.posix_spawn", "os.spawn", "os.fork", "os.forkpty", "subprocess.Popen",
                  "pty.spawn", "os.kill", "os.killpg", "os.startfile")
LISTINGS = ("os.listdir", "os.scandir", "glob.glob")
INTROSPECTION = ("sys._getframe", "sys._current_frames", "gc.get_objects", "gc.get_referrers", "gc.get_referents")
FRAME_ATTRIBUTES = ("tb_frame", "gi_frame", "cr_frame", "ag_frame", "f_back")
#: The audit event the harness raises with the results' digest, the channel's last line.
END_EVENT = "course_dynamics.harness.end"  # the harness raises it with the results' digest: the channel's last line
#: The audit event the harness raises with a list the hook fills with the forbidden modules it saw loaded.
IMPORTS_EVENT = "course_dynamics.harness.imports"  # the harness raises it with a list the hook fills


def first_key(nonce: str) -> bytes:
    """The channel's first key, from the run's nonce (the grader's secret, in the plan only).

    Parameters
    ----------
    nonce : str
        The run's nonce.

    Returns
    -------
    bytes
        The key, 32 bytes.
    """
    return hashlib.sha256(b"course-dynamics integrity\0" + nonce.encode()).digest()


def next_key(key: bytes) -> bytes:
    """The key after ``key``: one line, one key.

    Parameters
    ----------
    key : bytes
        A key of the channel.

    Returns
    -------
    bytes
        The next key, 32 bytes.
    """
    return hashlib.sha256(b"next\0" + key).digest()


def tag(key: bytes, body: bytes) -> bytes:
    """A line's tag: the HMAC of its ``code<TAB>detail`` under its key, in hex.

    Parameters
    ----------
    key : bytes
        The line's key.
    body : bytes
        The line's ``code<TAB>detail``.

    Returns
    -------
    bytes
        The tag, 32 hexadecimal characters.
    """
    return hmac.digest(key, body, "sha256").hex()[:TAG_CHARS].encode()


def integrity_hook(fd: int, own, library, writable, nonce: str, forbidden=(), harness=(), closer=None,
                   interrupter=None):
    """The audit hook behind the integrity flags (module docstring); the harness ends its channel with END_EVENT.

    Each attempt is one tagged line on ``fd``, written before the attempt proceeds, once per distinct attempt and at
    most MAX_FLAG_LINES per code (``tampered`` always). The submission's business are the files and listings of
    ``own`` (its folder, its working folder) and ``library`` (Python's standard library, the allowed packages);
    ``writable`` is its working folder; ``forbidden`` the top-level modules it may not import (one loaded is recorded
    then, from the import's own frames, whatever sys.modules says later: IMPORTS_EVENT); ``harness`` the files
    of the harness (its code, whose frames are the harness's); ``closer`` the code that alone may raise END_EVENT and
    IMPORTS_EVENT. The hook runs on copies made here, before any submission exists, of these globals, the builtins,
    ``os``, ``sys`` and ``os.path``: rewriting a module's names changes nothing it calls.

    Parameters
    ----------
    fd : int
        The channel's file descriptor.
    own : iterable of str
        The submission's folder and its working folder.
    library : iterable of str
        Python's standard library and the allowed packages.
    writable : iterable of str
        Where the submission may write (its working folder).
    nonce : str
        The run's nonce, which the channel's first key comes from.
    forbidden : iterable of str
        The top-level modules the submission may not import.
    harness : iterable of str
        The harness's files.
    closer : code or None
        The code that alone may raise :data:`END_EVENT` and :data:`IMPORTS_EVENT`.
    interrupter : code or None
        The harness's code that may also raise :data:`END_EVENT` with the submission's frames below it: the
        time-out handler, whose signal lands wherever the submission is (it reports a timeout, and nothing else).

    Returns
    -------
    callable
        The hook, ``hook(event, args)``, for ``sys.addaudithook``.
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
    private["_STATE"] = {"key": [first_key(nonce)], "counts": {}, "written": set(), "seen": [], "imports": set()}
    return types.FunctionType(_integrity_hook.__code__, private)(fd, own, library, writable, forbidden, harness, closer,
                                                                 interrupter)


def _integrity_hook(fd, own, library, writable, forbidden, harness_files, closer, interrupter):
    """integrity_hook's body, run with its private globals; its state (the key, the counts) is their ``_STATE``.

    The submission's code is every code object the interpreter did not hold when the hook was made (``known``: every
    function's then, the frames on the stack), except a module's code that is what its file in Python's installation
    compiles to, or a frozen module's own, whoever runs it: names (a code object's file name) are never evidence. An
    event whose stack reaches importlib's entry (``_find_and_load``) before any code of the submission's is an import's
    work, and a frame lookup counts when the submission's code makes it directly or when it returns a frame of the
    harness's to a stack that holds the submission's code (warnings, inspect and namedtuple look up frames too).
    After arming, the harness itself starts no process, opens no socket, loads no ctypes and touches no file but the
    submission's (in its own folder): those events are flags whatever the stack shows (a finalizer made of C callables
    runs under the harness's frames alone). The hook calls nothing of the submission's (an argument is read only when
    it is exactly a str, bytes, int or a list of them), runs with the collector off, and every event raised while it
    runs that its own code did not raise (a finalizer, a callback, a signal handler) is ``tampered``.
    """
    import _imp
    import _signal
    import _thread
    import gc
    import importlib._bootstrap as bootstrap
    import types

    code_type, frame_type, function_type, getframe, ident = types.CodeType, types.FrameType, types.FunctionType, \
        sys._getframe, _thread.get_ident
    realpath, join, write_fd, getsignal = os.path.realpath, os.path.join, os.write, _signal.getsignal
    gc_enabled, gc_disable, gc_enable, gc_callbacks = gc.isenabled, gc.disable, gc.enable, gc.callbacks
    known, own_code, busy, checking, lock = set(), set(), set(), set(), _thread.RLock()
    signals = tuple(s for s in _signal.valid_signals() if s not in (_signal.SIGKILL, _signal.SIGSTOP))
    handlers, callbacks = tuple(getsignal(s) for s in signals), tuple(gc_callbacks)
    forbidden = frozenset(n for n in forbidden if type(n) is str)
    try:  # the channel's keys through C functions alone: no code of theirs to swap
        from _hashlib import hmac_digest as mac
    except ImportError:
        mac = hmac.digest
    sha256 = hashlib.sha256

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
    harness = {c for c in known if c.co_filename in harness_files or c.co_filename == __file__}
    entry, removed = bootstrap._find_and_load.__code__, bootstrap._call_with_frames_removed.__code__
    main_thread = ident()

    def roots(folders) -> tuple:
        return tuple(join(realpath(r), "") for r in folders if type(r) is str and r)

    library, writable = roots(library) + roots([__file__, *harness_files]), roots(writable)  # a traceback quotes these
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
            found = next(filter(None, (path_flag(p, "file-write") for p in args[:2]
                                       if p is not None and type(p) is not int)),
                         None)
        elif event in PROCESS_EVENTS:
            return "process", f"{event} {text(first)}", "always"  # the harness starts none
        elif event.startswith(("socket.", "ctypes.")):
            return event.split(".")[0], f"{event} {text(second if event.startswith('socket.') else first)}", "always"
        elif event.startswith("gc."):
            return "introspection", event, "always"
        elif event in ("sys.settrace", "sys.setprofile", "sys.addaudithook"):
            found = "tampered", event
        elif type(first) is frame_type and first.f_code in harness and event in ("sys._getframe", "object.__getattr__"):
            found = "introspection", "a frame of the harness's"
        elif event in INTROSPECTION:
            return "introspection", event, "direct"
        elif event == "builtins.id":
            return "introspection", "id() of an object: its address in memory", "direct"
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

    def importing(frame) -> str:
        """The module importlib is loading at ``frame`` (its ``_find_and_load``'s name), or ""."""
        while frame is not None and frame.f_code is not entry:
            frame = frame.f_back
        name = frame.f_locals.get("name") if frame is not None else None
        return name if type(name) is str else ""

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

    def send(body: bytes) -> None:
        """One tagged line, under the next key; the key moves on only once the line is written."""
        with lock:
            keys = _STATE["key"]
            key = keys[-1]
            line_tag = mac(key, body, "sha256").hex()[:TAG_CHARS].encode()
            write_fd(fd, b"\n" + body + b"\t" + line_tag + b"\n")  # a line of its own, whatever came before
            keys[:] = [sha256(b"next\0" + key).digest()]

    def write(code, detail):
        detail = "".join(c if c.isprintable() else f"\\x{ord(c):02x}"
                         for c in " ".join(detail.split()))[:MAX_FLAG_DETAIL]
        state = _STATE
        if code == "tampered":
            state["seen"].append(detail)  # the closing line is withheld: no counter silences this
        elif state["counts"].get(code, 0) >= MAX_FLAG_LINES:
            return
        if (code, detail) in state["written"]:
            return
        state["written"].add((code, detail))
        state["counts"][code] = state["counts"].get(code, 0) + 1
        send(f"{code}\t{detail}".encode("utf-8", "replace"))

    def guards() -> None:
        """What reaches into the hook without an event: a Python signal handler, a gc callback."""
        for number, handler in zip(signals, handlers):
            now = getsignal(number)
            if now is not handler and not (type(now) is int and now == handler):
                write("tampered", f"a Python handler for signal {number}: it runs inside the hook, on its frame")
        if len(gc_callbacks) != len(callbacks) or any(a is not b for a, b in zip(gc_callbacks, callbacks)):
            write("tampered", "a gc callback: it runs inside the hook when the collector does")

    def hook(event, args):
        collecting = gc_enabled()
        if collecting:
            gc_disable()  # no collection (no callback, no finalizer) while the hook runs
        me = ident()
        try:
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
                guards()
                raiser = getframe(1)  # 0 is the hook, 1 the frame that raised the event
                if event in (END_EVENT, IMPORTS_EVENT):
                    interrupted = event == END_EVENT and interrupter is not None and raiser.f_code is interrupter
                    if not interrupted and (raiser.f_code is not closer or whose(raiser) != ""):
                        write("tampered", f"raised the harness's event {event}")
                    elif event == IMPORTS_EVENT and type(args[0]) is list:
                        args[0].extend(sorted(_STATE["imports"]))
                    elif event == END_EVENT and _STATE["seen"]:
                        write("tampered", "the hook saw tampering: it withholds the channel's closing line")
                    elif event == END_EVENT and type(args[0]) is str:
                        send(f"end\t{args[0]}".encode())
                    return
                if event == "exec" and type(args[0]) is code_type and args[0] not in known:
                    if trusted(args[0]):
                        learn(args[0], known)
                    name = args[0].co_filename
                    if raiser.f_code is removed:  # a module importlib loads: a forbidden one is recorded as loaded
                        module = importing(raiser).split(".")[0]
                        if module in forbidden:
                            _STATE["imports"].add(module)
                        if name.startswith("/") and not join(realpath(name), "").startswith(importable):
                            write("import-outside", name)
                found = flag(event, args)
                if found is None:
                    return
                code, detail, rule = found
                who = whose(raiser) if rule == "stack" else ""
                if code == "list-folder" and who == "import" and not join(realpath(detail), "").startswith(importable):
                    write("import-outside", f"searched {detail}")
                if (rule == "always" or (rule == "direct" and raiser.f_code not in known)
                        or who in ("theirs", "thread")
                        or (who == "" and code in ("file-read", "file-write", "list-folder"))):
                    write(code, detail)  # under the harness's frames alone: not the harness's (docstring), so a flag
            finally:
                busy.discard(me)
        except RecursionError:  # a recursion limit set to starve the hook: that itself is the flag
            _STATE["seen"].append("recursion")
            try:
                send(b"tampered\tthe recursion limit was set too low for the integrity hook to run")
            except Exception:
                pass
        except Exception:  # the hook never disturbs the submission, whatever its arguments are
            pass
        finally:
            if collecting:
                gc_enable()

    return hook


__all__ = ["END_EVENT", "FLAGS", "IMPORTS_EVENT", "MAX_FLAG_DETAIL", "MAX_FLAG_LINES", "first_key", "integrity_hook",
           "next_key", "tag"]
