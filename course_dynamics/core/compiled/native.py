"""Native code: the same traced programs written as C and built into a Python extension where a compiler exists.

The straight-line Python of :mod:`~course_dynamics.core.compiled` spends a
microsecond or more per operation on the interpreter; written as C, one line
per operation as before, the arithmetic itself is what is left. Each program
becomes a C function on plain ``double`` arrays, and one extension function per
program loops it over a batch, taking C-contiguous float64 buffers (numpy
arrays) and filling an output buffer the caller made, with the GIL released
(so threads can share a batch). It refuses (TypeError, ValueError,
BufferError) anything but float64 buffers of whole, finite states, so a caller
can try it first and give anything else to the checked path, which then names
the problem.

=====================  ==========================================================
name                   what
=====================  ==========================================================
:func:`c_source`       the extension's C source (readable: one line per operation)
:func:`build`          the shared library's bytes from the source, or None where
                       no C compiler or no Python headers exist
:func:`load`           the extension from checked bytes: its functions by name
=====================  ==========================================================

Built libraries are cached beside the Python programs, behind the same keyed
hash (:mod:`~course_dynamics.core.compiled.cache`); what is loaded is written
first to a new private file, from the very bytes that were checked.
``COURSE_DYNAMICS_NATIVE=off`` never builds or loads one (the pure-Python
programs then run, as wherever no compiler exists).
"""
from __future__ import annotations

import functools
import importlib.machinery
import importlib.util
import math
import os
import shutil
import signal
import stat
import subprocess
import sys
import sysconfig
import tempfile
import time
from pathlib import Path

import numpy as np

from ..state import batch_shape
from . import rollout
from .tracing import Program

#: The programs a library's capsule (``terms``, :data:`~course_dynamics.core.compiled.rollout.TERMS`) holds, in
#: its order, with the regressor where it is within its bound; a library without all of them has no capsule.
CAPSULE_PROGRAMS = ("tau", "mass_matrix", "bias", "forward_dynamics")
#: The value of ``COURSE_DYNAMICS_NATIVE`` that turns native code off.
NATIVE_OFF = "off"  # COURSE_DYNAMICS_NATIVE=off
#: The most wall and CPU time a build may take, s; a build taking longer is stopped and remembered.
BUILD_SECONDS = 60            # a build taking longer is stopped (the Python programs run), and remembered
#: The compiler's address space, bytes.
BUILD_MEMORY = 2**30          # address space of the compiler (the 20-joint chain's build peaks at 0.3 GB)
#: The largest file the compiler may write, bytes (the library included).
BUILD_FILE_BYTES = 256 * 2**20  # any file the compiler writes (the 20-joint chain's library is 0.8 MB)
#: The most operations in one C function; a longer program is cut into parts of this size.
PART_OPERATIONS = 1000  # operations in one C function at most: gcc then takes time linear in the program (below)
#: The line before each translation unit of a large library's C (after the prelude they share); the units
#: compile at once, each on a core of its own, and are linked after.
UNIT_MARK = "/* ---- translation unit ---- */"
#: A library's programs of more operations than this are cut into :data:`UNITS` translation units.
SPLIT_OPERATIONS = 3000
#: The translation units of a large library (the cores a build may use at once).
UNITS = 2
C_FLAGS = ("-O1", "-fPIC", "-fno-math-errno", "-ffp-contract=off", "-I", sysconfig.get_paths()["include"])
OPERATIONS = {"add": "{} + {}", "sub": "{} - {}", "mul": "{} * {}", "div": "{} / {}", "neg": "-{}", "cos": "cos({})",
              "sin": "sin({})"}


#: A native batch is shared by at most this many threads ...
THREADS = max(1, min(4, os.cpu_count() or 1))
#: ... when each gets at least this many states.
THREAD_STATES = 2000


def run_batch(function, arrays, width: int, first: tuple = ()) -> np.ndarray:
    """``function(*first, *states, out)`` on checked float64 arrays of any batch shape, into a new output of
    ``width`` entries a state; a batch of :data:`THREAD_STATES` states a thread or more is shared over
    :data:`THREADS` threads (the native functions release the GIL).

    Parameters
    ----------
    function : callable
        A native function that fills its last argument.
    arrays : sequence of numpy.ndarray, shape (..., n)
        The states, already checked (float64, finite).
    width : int
        The output's entries per state.
    first : tuple, optional
        Arguments before the states (the native loop's model array).

    Returns
    -------
    numpy.ndarray, shape (..., width)
        The output.

    Examples
    --------
    >>> def doubled(x, out):              # a stand-in for a native function: fills its output
    ...     out[...] = 2 * x
    >>> run_batch(doubled, [np.ones((3, 2))], 2).tolist()
    [[2.0, 2.0], [2.0, 2.0], [2.0, 2.0]]
    """
    batch = batch_shape(*arrays)
    # contiguous and aligned (an array read from a packed buffer at an odd offset is contiguous, not aligned)
    columns = [np.require(np.broadcast_to(a, batch + a.shape[-1:]), np.float64, ["C", "A"]) for a in arrays]
    out = np.empty(batch + (width,))
    states = int(np.prod(batch))
    parts = min(THREADS, states // THREAD_STATES)
    if parts < 2:
        function(*first, *columns, out)
        return out
    flat = [c.reshape(states, -1) for c in columns] + [out.reshape(states, width)]
    bounds = np.linspace(0, states, parts + 1).astype(int)
    list(pool().map(lambda k: function(*first, *(a[bounds[k]:bounds[k + 1]] for a in flat)), range(parts)))
    return out


@functools.cache
def pool():
    """The threads native work is shared over (:data:`THREADS` of them), made on first use.

    Returns
    -------
    concurrent.futures.ThreadPoolExecutor
        The one pool of the process.

    Examples
    --------
    >>> pool() is pool()
    True
    """
    from concurrent.futures import ThreadPoolExecutor

    return ThreadPoolExecutor(max_workers=THREADS, thread_name_prefix="course-dynamics-native")


def enabled() -> bool:
    """Whether native code may be built and loaded (``COURSE_DYNAMICS_NATIVE`` is not ``off``).

    Returns
    -------
    bool
        False when ``COURSE_DYNAMICS_NATIVE`` is ``off`` (in any case), else True.

    Examples
    --------
    >>> import os
    >>> from unittest import mock
    >>> with mock.patch.dict(os.environ, {"COURSE_DYNAMICS_NATIVE": "off"}):
    ...     enabled()
    False
    """
    return os.environ.get("COURSE_DYNAMICS_NATIVE", "").lower() != NATIVE_OFF


def module_name(key: str) -> str:
    """The extension module's name for a model key.

    >>> module_name("0123456789abcdef" * 4)
    'course_dynamics_native_0123456789abcdef'
    """
    return f"course_dynamics_native_{key[:16]}"


def c_argument(a, nodes, inputs: dict[str, str]) -> str:
    """An operation's argument as C: an input's element, a value ``t<i>`` or a literal.

    Parameters
    ----------
    a : list
        The argument, ``["t", index]`` or ``["c", value]``.
    nodes : list
        The program's nodes (an input node's argument is its name).
    inputs : dict of str to str
        Each input's name (``q0``) and its C (``q[0]``).

    Returns
    -------
    str
        The C expression.

    Raises
    ------
    ValueError
        If a constant is not finite (it has no C literal).

    Examples
    --------
    >>> nodes = [["input", "q0"], ["mul", ["c", 2.0], ["t", 0]]]
    >>> c_argument(["t", 0], nodes, {"q0": "q[0]"}), c_argument(["t", 1], nodes, {}), c_argument(["c", -0.5], nodes, {})
    ('q[0]', 't1', '(-0.5)')
    """
    kind, value = a
    if kind == "t":
        op, *arguments = nodes[value]
        return inputs[arguments[0]] if op == "input" else f"t{value}"
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"a constant {value} has no C literal")
    return repr(value) if value >= 0 else f"({value!r})"


def _parts(program: Program) -> tuple[list[list[int]], dict[int, int]]:
    """The program's operations cut into parts of at most :data:`PART_OPERATIONS` (one C function each), and
    the values a later part uses (an output counts as used by the last part), each with its slot in the
    scratch array that carries them from part to part."""
    nodes = program.nodes
    steps = [i for i, (op, *_) in enumerate(nodes) if op != "input"]
    parts = [steps[k:k + PART_OPERATIONS] for k in range(0, len(steps), PART_OPERATIONS)] or [[]]
    part_of = {i: p for p, part in enumerate(parts) for i in part}
    carried: dict[int, int] = {}
    uses = [(part_of[i], a) for i in steps for a in nodes[i][1:]]
    for p, (kind, value) in uses + [(len(parts) - 1, o) for o in program.outputs]:
        if kind == "t" and value in part_of and part_of[value] < p:
            carried.setdefault(value, len(carried))
    return parts, carried


def _function(program: Program, n: int) -> tuple[str, int]:
    """``HIDDEN void <name>_one(const double *q, …, double *scratch, double *out)``: one line per operation, in
    parts of bounded size (gcc's time grows faster than the size of a function); and the scratch size."""
    inputs = {f"{name}{j}": f"{name}[{j}]" for name in program.inputs for j in range(n)}
    parameters = ", ".join(f"const double *restrict {name}" for name in program.inputs)
    arguments = ", ".join(program.inputs)
    parts, carried = _parts(program)
    text = []
    for p, part in enumerate(parts):
        own = set(part)

        def value(a):
            if a[0] == "t" and a[1] not in own and a[1] in carried:
                return f"scratch[{carried[a[1]]}]"
            return c_argument(a, program.nodes, inputs)

        name = f"static PART void {program.name}_part{p}" if len(parts) > 1 else f"HIDDEN void {program.name}_one"
        lines = [f"{name}({parameters}, double *restrict scratch, double *restrict out)", "{"]
        for i in part:
            op, *operands = program.nodes[i]
            lines.append(f"    const double t{i} = {OPERATIONS[op].format(*(value(a) for a in operands))};")
            if i in carried:
                lines.append(f"    scratch[{carried[i]}] = t{i};")
        if p == len(parts) - 1:
            lines += _outputs(program, n, value)
        text.append("\n".join(lines + ["}"]))
    if len(parts) == 1:
        return text[0], len(carried)
    calls = [f"    {program.name}_part{p}({arguments}, scratch, out);" for p in range(len(parts))]
    text.append("\n".join([f"HIDDEN void {program.name}_one({parameters}, double *restrict scratch, "
                            "double *restrict out)", "{", *calls, "}"]))
    return "\n\n".join(text), len(carried)


def _outputs(program: Program, n: int, value) -> list[str]:
    if program.name != "mass_matrix":
        return [f"    out[{k}] = {value(output)};" for k, output in enumerate(program.outputs)]
    lines = []  # the packed upper triangle, written out as the whole symmetric matrix
    places = [(i, j) for i in range(n) for j in range(i, n)]
    for (i, j), output in zip(places, program.outputs):
        lines.append(f"    out[{i * n + j}] = {value(output)};")
        if i != j:
            lines.append(f"    out[{j * n + i}] = {value(output)};")
    return lines


def _units(programs: dict[str, Program]) -> list:
    """The programs in translation units of about equal operations ([None]: one unit, no mark), largest first."""
    sizes = {name: len(program.nodes) for name, program in programs.items()}
    if sum(sizes.values()) <= SPLIT_OPERATIONS:
        return [None]
    units = [[] for _ in range(UNITS)]
    for name in sorted(sizes, key=lambda name: -sizes[name]):
        min(units, key=lambda unit: sum(sizes[p.name] for p in unit)).append(programs[name])
    return [unit for unit in units if unit]


@functools.cache
def width(name: str, n: int, bodies: int | None = None) -> int:
    """Entries a native program writes per state (M whole, n × n, where the Python programs give its upper
    triangle; Y n × 10 ``bodies``, the moving bodies, n by default).

    >>> width("mass_matrix", 6), width("tau", 6), width("forward_dynamics", 6)   # Θ̈ and the n pivots
    (36, 6, 12)
    >>> width("regressor", 6)
    360
    """
    return {"tau": n, "mass_matrix": n * n, "bias": n, "coriolis": n * n, "forward_dynamics": 2 * n,
            "regressor": 10 * n * (n if bodies is None else bodies)}[name]


WRAPPER = """
HIDDEN PyObject *{name}(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{{
    Py_buffer views[{count}];
    Py_ssize_t got = 0, states = 0;
    PyObject *result = NULL;
    double *scratch = NULL;
    if (nargs != {count}) {{
        PyErr_SetString(PyExc_TypeError, "{name} takes {inputs} input arrays and one output array");
        return NULL;
    }}
    for (; got < {count}; got++) {{
        int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (got == {inputs} ? PyBUF_WRITABLE : 0);
        if (PyObject_GetBuffer(args[got], &views[got], flags) != 0)
            goto done;
        if (views[got].itemsize != 8 || strcmp(views[got].format, "d") != 0) {{
            PyErr_SetString(PyExc_TypeError, "{name} takes C-contiguous float64 arrays");
            got++;
            goto done;
        }}
    }}
    states = views[{inputs}].len / (8 * {width});
    if (views[{inputs}].len != states * 8 * {width}) {{
        PyErr_SetString(PyExc_ValueError, "{name}: the output holds no whole number of states");
        goto done;
    }}
    for (Py_ssize_t i = 0; i < {inputs}; i++) {{
        if (views[i].len != states * 8 * {n}) {{
            PyErr_SetString(PyExc_ValueError, "{name}: an input holds another number of states than the output");
            goto done;
        }}
        for (Py_ssize_t j = 0; j < states * {n}; j++) {{
            if (!isfinite(((const double *)views[i].buf)[j])) {{
                PyErr_SetString(PyExc_ValueError, "{name}: an input is not finite");
                goto done;
            }}
        }}
    }}
    if ({carried} > 0 && (scratch = malloc(sizeof(double) * {carried})) == NULL) {{
        PyErr_NoMemory();
        goto done;
    }}
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t k = 0; k < states; k++)
        {name}_one({pointers}, scratch, (double *)views[{inputs}].buf + k * {width});
    Py_END_ALLOW_THREADS
    Py_INCREF(Py_None);
    result = Py_None;
done:
    free(scratch);
    for (Py_ssize_t i = 0; i < got; i++)
        PyBuffer_Release(&views[i]);
    return result;
}}
"""


def c_source(programs: dict[str, Program], n: int, key: str, robot: str) -> str:
    """The extension module's C source: every program as a C function and its batch wrapper.

    Parameters
    ----------
    programs : dict of str to Program
        The traced programs, by name (:func:`~course_dynamics.core.compiled.tracing.trace_programs`).
    n : int
        The robot's number of joints.
    key : str
        The model's key (:func:`~course_dynamics.core.compiled.model_key`): it names the module.
    robot : str
        The robot's name, for the first comment (anything that could end the comment is replaced by ``?``).

    Returns
    -------
    str
        The C source of the extension: one line per operation, in functions of at most
        :data:`PART_OPERATIONS` operations.

    Raises
    ------
    ValueError
        If a program holds a constant that is not finite (it has no C literal).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.compiled.tracing import trace_programs
    >>> pendulum = load_robot("pendulum")
    >>> source = c_source(trace_programs(pendulum), 1, "k1", pendulum.name)
    >>> import textwrap
    >>> for line in [line for line in source.splitlines() if line.startswith("HIDDEN void") and line[-1] == ")"][:2]:
    ...     print(textwrap.fill(line, 104, subsequent_indent="    "))
    HIDDEN void tau_one(const double *restrict q, const double *restrict qd, const double *restrict qdd,
        double *restrict scratch, double *restrict out)
    HIDDEN void mass_matrix_one(const double *restrict q, double *restrict scratch, double *restrict out)
    """
    # The robot's name appears only inside a comment, with anything that could end it taken out.
    safe = "".join(c if c.isalnum() or c in " _-." else "?" for c in robot)[:80]
    parts = [f"/* course-dynamics compiled model {key}, robot {safe}, {n} joints: generated C, one line per",
             "   operation of the library's recursions (course_dynamics.core.compiled.native). */",
             "#define PY_SSIZE_T_CLEAN", "#include <Python.h>", "#include <math.h>", "#include <stdlib.h>",
             "#include <string.h>", "",
             "#if defined(__GNUC__)  /* a part stays its own function, so no function gcc sees grows past a part */",
             "#define PART __attribute__((noinline))", "#define HIDDEN __attribute__((visibility(\"hidden\")))",
             "#else", "#define PART", "#define HIDDEN", "#endif", ""]
    parts += [f"HIDDEN PyObject *{name}(PyObject *self, PyObject *const *args, Py_ssize_t nargs);"
              for name in programs] + [""]
    # the capsule the native run and the one-state entry compute with (the regressor may be over its bound)
    terms = all(name in programs for name in CAPSULE_PROGRAMS)
    if terms:
        for program in programs.values():
            if program.name in CAPSULE_PROGRAMS + ("regressor",):
                parameters = ", ".join(f"const double *restrict {name}" for name in program.inputs)
                parts.append(f"HIDDEN void {program.name}_one({parameters}, double *restrict scratch, "
                             "double *restrict out);")
        parts.append(rollout.TERMS)
    methods, scratch = [], {}
    for unit in _units(programs):
        if unit is not None:
            parts.append(UNIT_MARK)
        for program in unit or programs.values():
            function, carried = _function(program, n)
            parts.append(function)
            scratch[program.name] = carried
            pointers = ", ".join(f"(const double *)views[{i}].buf + k * {n}" for i in range(len(program.inputs)))
            bodies = len(program.outputs) // (10 * n) if program.name == "regressor" else None  # Y: n × 10 bodies
            parts.append(WRAPPER.format(name=program.name, count=len(program.inputs) + 1, inputs=len(program.inputs),
                                        width=width(program.name, n, bodies), n=n, pointers=pointers,
                                        carried=carried))
    for program in programs.values():
        methods.append(f'    {{"{program.name}", (PyCFunction)(void (*)(void)){program.name}, METH_FASTCALL, NULL}},')
    name = module_name(key)
    parts += ["static PyMethodDef methods[] = {", *methods, "    {NULL, NULL, 0, NULL}", "};", "",
              f'static struct PyModuleDef module = {{PyModuleDef_HEAD_INIT, "{name}", NULL, -1, methods}};', ""]
    if not terms:
        return "\n".join(parts + [f"PyMODINIT_FUNC PyInit_{name}(void) {{ return PyModule_Create(&module); }}", ""])
    bodies = len(programs["regressor"].outputs) // (10 * n) if "regressor" in programs else 0  # Y's, if any
    functions = ", ".join(f"{program}_one" for program in CAPSULE_PROGRAMS)
    regressor = "regressor_one" if "regressor" in programs else "NULL"
    parts += [f"static course_dynamics_terms terms = {{2, {n}, {bodies}, {functions}, {regressor}, "
              f"{max(scratch.values())}}};", "",
              f"PyMODINIT_FUNC PyInit_{name}(void)", "{",
              "    PyObject *m = PyModule_Create(&module), *capsule = NULL;", "    if (m == NULL)",
              "        return NULL;",
              f'    if ((capsule = PyCapsule_New(&terms, "{rollout.CAPSULE}", NULL)) == NULL',
              '        || PyModule_AddObject(m, "terms", capsule) != 0) {',
              "        Py_XDECREF(capsule);", "        Py_DECREF(m);", "        return NULL;", "    }", "    return m;",
              "}", ""]
    return "\n".join(parts)


def compiler() -> str | None:
    """A C compiler with Python's headers beside it, or None.

    Returns
    -------
    str or None
        The compiler's path (Python's own ``CC``, else ``cc``, else ``gcc``), or None where there is none or
        ``Python.h`` is missing.

    Examples
    --------
    >>> compiler() is None or Path(compiler()).is_file()
    True
    """
    include = Path(sysconfig.get_paths()["include"]) / "Python.h"
    chosen = (sysconfig.get_config_var("CC") or "cc").split()[0]
    found = shutil.which(chosen) or shutil.which("cc") or shutil.which("gcc")
    return found if found and include.is_file() else None


# Run before the compiler, in a Python of its own (-I -S: nothing of the user's imported): the limits below, then
# exec of the compiler, whose own children (cc1, as, ld) inherit them.
LIMITED = """import os, resource, sys
seconds, memory, size = map(int, sys.argv[1:4])
for limit, value in ((resource.RLIMIT_CPU, seconds), (resource.RLIMIT_AS, memory), (resource.RLIMIT_FSIZE, size),
                     (resource.RLIMIT_CORE, 0)):
    hard = resource.getrlimit(limit)[1]
    value = value if hard == resource.RLIM_INFINITY else min(value, hard)
    resource.setrlimit(limit, (value, value))
os.execv(sys.argv[4], sys.argv[4:])
"""


def compile_library(folder: str, name: str, cc: str, seconds: float, memory: int, size: int) -> str | None:
    """Build ``<name>.so`` from ``<name>.c`` in the private ``folder``; None when built, else why not.

    The compiler runs in a session of its own, with at most ``seconds`` of wall and CPU time (then its whole
    process group is killed), ``memory`` bytes of address space and files of ``size`` bytes, its temporary
    files in ``folder`` (TMPDIR) and what it prints in ``folder``/compiler.log. A source cut into translation
    units (:data:`UNIT_MARK`) has each unit compiled at once, each by its own compiler under the same limits
    (``compiler<k>.log``), and the objects linked; ``seconds`` bounds the whole build.

    Parameters
    ----------
    folder : str
        A private folder (mode 0700) holding ``<name>.c``.
    name : str
        The module's name, ``course_dynamics_native_`` and the key's first 16 characters.
    cc : str
        The C compiler's path (:func:`compiler`).
    seconds : float
        The most wall and CPU time the compiler may take, s.
    memory : int
        The compiler's address space, bytes.
    size : int
        The largest file the compiler may write, bytes.

    Returns
    -------
    str or None
        None when ``<name>.so`` was built; otherwise why not (could not start, stopped after ``seconds``, stopped
        by a limit, or the compiler's exit code and the last line it printed).

    Examples
    --------
    >>> import shutil, tempfile
    >>> folder = tempfile.mkdtemp()
    >>> with open(os.path.join(folder, "tiny.c"), "w") as c:
    ...     _ = c.write("int one(void) { return 1; }")
    >>> cc = compiler()
    >>> cc is None or compile_library(folder, "tiny", cc, 30, BUILD_MEMORY, 2**20) is None   # None: built
    True
    >>> cc is None or compile_library(folder, "tiny", cc, 0.001, BUILD_MEMORY, 2**20)
    'the C compiler took longer than 0.001 s and was stopped'
    >>> shutil.rmtree(folder)
    """
    try:
        with open(os.path.join(folder, f"{name}.c"), encoding="utf-8") as handle:
            units = handle.read().split(UNIT_MARK)
    except (OSError, UnicodeDecodeError) as exc:
        return f"the C source could not be read ({exc})"
    deadline = time.monotonic() + seconds
    if len(units) == 1:  # one translation unit: compiled and linked by one command
        return _limited(folder, [[cc, *C_FLAGS, "-shared", f"{name}.c", "-o", f"{name}.so", "-lm"]], seconds, memory,
                        size, deadline)
    objects, commands = [], []
    for k, unit in enumerate(units[1:]):  # each after the shared prelude, compiled at once on its own core
        source = f"{name}.u{k}.c"
        try:
            fd = os.open(os.path.join(folder, source), os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_NOFOLLOW, 0o600)
            with os.fdopen(fd, "w", encoding="utf-8") as handle:
                handle.write(units[0] + unit)
        except OSError as exc:
            return f"the C source could not be written ({exc.strerror})"
        objects.append(f"{name}.u{k}.o")
        commands.append([cc, *C_FLAGS, "-c", source, "-o", objects[-1]])
    reason = _limited(folder, commands, seconds, memory, size, deadline)
    if reason:
        return reason
    return _limited(folder, [[cc, "-shared", *objects, "-o", f"{name}.so", "-lm"]], seconds, memory, size, deadline)


def _start_limited(folder: str, argv: list[str], seconds: float, memory: int, size: int, log_name: str):
    """The process running ``argv`` under the limits (LIMITED), in a session of its own, printing to ``log_name``."""
    command = [sys.executable, "-I", "-S", "-c", LIMITED, str(math.ceil(seconds)), str(memory), str(size), *argv]
    environment = dict(os.environ, TMPDIR=folder, LC_ALL="C")
    log = os.open(os.path.join(folder, log_name), os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_NOFOLLOW, 0o600)
    try:
        return subprocess.Popen(command, cwd=folder, env=environment, stdin=subprocess.DEVNULL, stdout=log,
                                stderr=log, start_new_session=True)
    finally:
        os.close(log)


def _limited(folder: str, commands: list, seconds: float, memory: int, size: int, deadline: float) -> str | None:
    """The commands run at once under the limits (their address space shared among them), all waited for until
    ``deadline``: None when every one ended well, else why not (the first that did not, and which of several);
    the first to end badly, or the deadline, stops every one. One command prints to compiler.log, several to
    compiler<k>.log."""
    logs = ["compiler.log"] if len(commands) == 1 else [f"compiler{k}.log" for k in range(len(commands))]
    processes = []
    try:
        for argv, log in zip(commands, logs):
            try:
                processes.append(_start_limited(folder, argv, seconds, memory // len(commands), size, log))
            except OSError as exc:
                return f"the C compiler could not be started ({exc.strerror})"
        running = dict(enumerate(processes))
        while running:
            for k, process in list(running.items()):
                if process.poll() is not None:
                    del running[k]
                    reason = _outcome(process.returncode, os.path.join(folder, logs[k]))
                    if reason:
                        return reason if len(commands) == 1 else f"{reason} (translation unit {k})"
            if running:
                if time.monotonic() > deadline:
                    return f"the C compiler took longer than {seconds:g} s and was stopped"
                time.sleep(0.01)
        return None
    finally:
        for process in processes:
            _stop(process)


def _outcome(code: int, log: str) -> str | None:
    """Why a limited process that ended with exit status ``code`` did not end well (None when it did)."""
    if code < 0:
        return f"the C compiler was stopped by signal {-code} (over its CPU time, memory or file-size limit)"
    if code != 0:
        return f"the C compiler failed (exit {code}): {_last_line(log)}"
    return None


def _stop(process) -> None:
    """A process still running (too long, or interrupted) stopped: its whole group, cc1, as and ld included."""
    if process.returncode is None and process.poll() is None:
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except OSError:
            pass
        process.wait()


def _last_line(path: str) -> str:
    """The compiler's last error line (gcc ends with the source line and a caret under it), else its last line."""
    try:
        with open(path, "rb") as handle:
            handle.seek(max(0, os.fstat(handle.fileno()).st_size - 4000))
            lines = handle.read().decode("utf-8", "replace").strip().splitlines()
    except OSError:
        return ""
    errors = [line for line in lines if "error" in line.lower()]
    return (errors or lines or ["no message"])[-1].strip()[-200:]


def read_library(folder: str, name: str, limit: int) -> bytes | None:
    """The bytes of the built ``<name>.so`` in the private ``folder``: a regular file of ours, no link, ≤ limit.

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     os.symlink("/etc/passwd", os.path.join(folder, "planted.so"))
    ...     print(read_library(folder, "planted", 2**20))
    None
    """
    try:
        fd = os.open(os.path.join(folder, f"{name}.so"), os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
    except OSError:
        return None
    with os.fdopen(fd, "rb") as handle:
        st = os.fstat(handle.fileno())
        if not stat.S_ISREG(st.st_mode) or st.st_uid != os.getuid() or st.st_size > limit:
            return None
        return handle.read(limit + 1)


def build(source: str, key: str) -> tuple[bytes | None, str]:
    """The shared library built from ``source`` here and now, in a new private folder: (its bytes, "") or
    (None, why not), never an exception.

    The build runs under :data:`BUILD_SECONDS`, :data:`BUILD_MEMORY` and :data:`BUILD_FILE_BYTES`
    (:func:`compile_library`); the folder is removed afterwards.

    Parameters
    ----------
    source : str
        The extension's C source (:func:`c_source`).
    key : str
        The model's key, which names the module.

    Returns
    -------
    tuple of (bytes or None, str)
        The library's bytes and ``""``, or None and why there is none (no compiler, the compiler's error, a
        limit).

    Examples
    --------
    >>> build("this is not C", "k3")[0] is None
    True
    """
    cc = compiler()
    if cc is None:
        return None, "no C compiler with Python's headers here"
    folder = tempfile.mkdtemp(prefix="course-dynamics-build-")  # 0700, a name no one can guess
    try:
        name = module_name(key)
        fd = os.open(os.path.join(folder, f"{name}.c"), os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(source)
        reason = compile_library(folder, name, cc, BUILD_SECONDS, BUILD_MEMORY, BUILD_FILE_BYTES)
        if reason:
            return None, reason
        data = read_library(folder, name, BUILD_FILE_BYTES)
        return (data, "") if data else (None, "the C compiler wrote no library")
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def load(data: bytes, key: str) -> dict | None:
    """The extension's functions from checked library bytes, written to a new private file to be loaded.

    Each function takes the program's input arrays and an output array, all C-contiguous float64 of whole
    states, and fills the output; it raises TypeError, ValueError or BufferError for anything else (a
    non-finite input among them).

    Parameters
    ----------
    data : bytes
        The shared library (:func:`build`), already checked: nothing else should be given.
    key : str
        The model's key it was built for, which names the module.

    Returns
    -------
    dict of str to callable or None
        The extension's functions by program name (``tau``, ``mass_matrix``, …), or None if it does not load.

    Examples
    --------
    >>> import numpy as np
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.compiled.tracing import trace_programs
    >>> pendulum = load_robot("pendulum")
    >>> data, _ = build(c_source(trace_programs(pendulum), 1, "k2", pendulum.name), "k2")   # None without a compiler
    >>> functions = load(data, "k2") if data else None
    >>> out = np.empty(1)
    >>> functions is None or functions["tau"](np.array([0.3]), np.zeros(1), np.zeros(1), out) is None
    True
    """
    folder = tempfile.mkdtemp(prefix="course-dynamics-native-")  # 0700: only this user
    path = os.path.join(folder, f"{module_name(key)}.so")
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o700)
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
        loader = importlib.machinery.ExtensionFileLoader(module_name(key), path)
        spec = importlib.util.spec_from_file_location(module_name(key), path, loader=loader)
        module = importlib.util.module_from_spec(spec)
        loader.exec_module(module)
    except (OSError, ImportError):
        return None
    finally:
        shutil.rmtree(folder, ignore_errors=True)  # the mapping stays; the file is not needed once loaded
    return {name: getattr(module, name) for name in dir(module) if not name.startswith("_")}


__all__ = ["BUILD_FILE_BYTES", "BUILD_MEMORY", "BUILD_SECONDS", "CAPSULE_PROGRAMS", "NATIVE_OFF", "PART_OPERATIONS",
           "SPLIT_OPERATIONS", "THREADS", "THREAD_STATES", "UNITS", "UNIT_MARK", "build", "c_argument", "c_source",
           "compile_library", "compiler", "enabled", "load", "pool", "run_batch"]
