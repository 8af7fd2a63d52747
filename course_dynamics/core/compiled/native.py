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
import subprocess
import sysconfig
import tempfile
from pathlib import Path

from .tracing import Program

NATIVE_OFF = "off"  # COURSE_DYNAMICS_NATIVE=off
BUILD_SECONDS = 300  # a build taking longer is abandoned (the Python programs run)
OPERATIONS = {"add": "{} + {}", "sub": "{} - {}", "mul": "{} * {}", "div": "{} / {}", "neg": "-{}", "cos": "cos({})",
              "sin": "sin({})"}


def enabled() -> bool:
    """Whether native code may be built and loaded (``COURSE_DYNAMICS_NATIVE`` is not ``off``).

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


def _argument(a, nodes, inputs: dict[str, str]) -> str:
    kind, value = a
    if kind == "t":
        op, *arguments = nodes[value]
        return inputs[arguments[0]] if op == "input" else f"t{value}"
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"a constant {value} has no C literal")
    return repr(value) if value >= 0 else f"({value!r})"


def _function(program: Program, n: int) -> str:
    """``static void <name>_one(const double *q, …, double *out)``: one line per operation."""
    inputs = {f"{name}{j}": f"{name}[{j}]" for name in program.inputs for j in range(n)}
    parameters = ", ".join(f"const double *restrict {name}" for name in program.inputs)
    lines = [f"static void {program.name}_one({parameters}, double *restrict out)", "{"]
    for i, (op, *arguments) in enumerate(program.nodes):
        if op != "input":
            lines.append(f"    const double t{i} = {OPERATIONS[op].format(*(_argument(a, program.nodes, inputs) for a in arguments))};")
    if program.name == "mass_matrix":  # the packed upper triangle, written out as the whole symmetric matrix
        places = [(i, j) for i in range(n) for j in range(i, n)]
        for (i, j), output in zip(places, program.outputs):
            value = _argument(output, program.nodes, inputs)
            lines += [f"    out[{i * n + j}] = {value};"] + ([f"    out[{j * n + i}] = {value};"] if i != j else [])
    else:
        for k, output in enumerate(program.outputs):
            lines.append(f"    out[{k}] = {_argument(output, program.nodes, inputs)};")
    return "\n".join(lines + ["}"])


@functools.cache
def width(name: str, n: int) -> int:
    """Entries a native program writes per state (M whole, n × n, where the Python programs give its upper
    triangle).

    >>> width("mass_matrix", 6), width("tau", 6), width("forward_dynamics", 6)   # Θ̈ and the n pivots
    (36, 6, 12)
    """
    return {"tau": n, "mass_matrix": n * n, "bias": n, "coriolis": n * n, "forward_dynamics": 2 * n}[name]


WRAPPER = """
static PyObject *{name}(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{{
    Py_buffer views[{count}];
    Py_ssize_t got = 0, states = 0;
    PyObject *result = NULL;
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
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t k = 0; k < states; k++)
        {name}_one({pointers}, (double *)views[{inputs}].buf + k * {width});
    Py_END_ALLOW_THREADS
    Py_INCREF(Py_None);
    result = Py_None;
done:
    for (Py_ssize_t i = 0; i < got; i++)
        PyBuffer_Release(&views[i]);
    return result;
}}
"""


def c_source(programs: dict[str, Program], n: int, key: str, robot: str) -> str:
    """The extension module's C source: every program as a C function and its batch wrapper.

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.compiled.tracing import trace_programs
    >>> pendulum = load_robot("pendulum")
    >>> source = c_source(trace_programs(pendulum), 1, "k1", pendulum.name)
    >>> [line for line in source.splitlines() if line.startswith("static void")][:2]
    ['static void tau_one(const double *restrict q, const double *restrict qd, const double *restrict qdd, double *restrict out)', 'static void mass_matrix_one(const double *restrict q, double *restrict out)']
    """
    # The robot's name appears only inside a comment, with anything that could end it taken out.
    safe = "".join(c if c.isalnum() or c in " _-." else "?" for c in robot)[:80]
    parts = [f"/* course-dynamics compiled model {key}, robot {safe}, {n} joints: generated C, one line per",
             "   operation of the library's recursions (course_dynamics.core.compiled.native). */",
             "#define PY_SSIZE_T_CLEAN", "#include <Python.h>", "#include <math.h>", "#include <string.h>", ""]
    methods = []
    for program in programs.values():
        parts.append(_function(program, n))
        pointers = ", ".join(f"(const double *)views[{i}].buf + k * {n}" for i in range(len(program.inputs)))
        parts.append(WRAPPER.format(name=program.name, count=len(program.inputs) + 1, inputs=len(program.inputs),
                                    width=width(program.name, n), n=n, pointers=pointers))
        methods.append(f'    {{"{program.name}", (PyCFunction)(void (*)(void)){program.name}, METH_FASTCALL, NULL}},')
    name = module_name(key)
    parts += ["static PyMethodDef methods[] = {", *methods, "    {NULL, NULL, 0, NULL}", "};", "",
              f'static struct PyModuleDef module = {{PyModuleDef_HEAD_INIT, "{name}", NULL, -1, methods}};', "",
              f"PyMODINIT_FUNC PyInit_{name}(void) {{ return PyModule_Create(&module); }}", ""]
    return "\n".join(parts)


def compiler() -> str | None:
    """A C compiler with Python's headers beside it, or None.

    >>> compiler() is None or Path(compiler()).is_file()
    True
    """
    include = Path(sysconfig.get_paths()["include"]) / "Python.h"
    chosen = (sysconfig.get_config_var("CC") or "cc").split()[0]
    found = shutil.which(chosen) or shutil.which("cc") or shutil.which("gcc")
    return found if found and include.is_file() else None


def build(source: str, key: str) -> bytes | None:
    """The shared library built from ``source`` (its bytes), or None when it cannot be built here.

    >>> build("this is not C", "k3") is None          # a failed build is None, never an exception
    True
    """
    cc = compiler()
    if cc is None:
        return None
    with tempfile.TemporaryDirectory(prefix="course-dynamics-native-") as folder:
        c_file, library = Path(folder) / f"{module_name(key)}.c", Path(folder) / f"{module_name(key)}.so"
        c_file.write_text(source)
        command = [cc, "-O1", "-fPIC", "-shared", "-fno-math-errno", "-ffp-contract=off", "-I", sysconfig.get_paths()["include"],
                   str(c_file), "-o", str(library), "-lm"]
        try:
            done = subprocess.run(command, capture_output=True, timeout=BUILD_SECONDS)
        except (OSError, subprocess.TimeoutExpired):
            return None
        if done.returncode != 0 or not library.is_file():
            return None
        return library.read_bytes()


def load(data: bytes, key: str) -> dict | None:
    """The extension's functions from checked library bytes, written to a new private file to be loaded.

    >>> import numpy as np
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.compiled.tracing import trace_programs
    >>> pendulum = load_robot("pendulum")
    >>> data = build(c_source(trace_programs(pendulum), 1, "k2", pendulum.name), "k2")   # None without a compiler
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
