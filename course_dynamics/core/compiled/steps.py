"""The native loop's steps: one body's step of each recursion traced once, with the body's numbers as inputs,
and written as C with the loops over the bodies (``looped.c``, generated here and shipped).

The compiled models of :mod:`~course_dynamics.core.compiled` are unrolled for one robot: fastest for a small
one, but a program per robot, built by a compiler, and too large above about 20 joints. The native loop runs
the same recursions natively the other way: each body's *step* is traced once, with the body's numbers as
inputs (not as constants), into one C function per step and joint kind; C written by hand then loops over
the bodies, reading them from an array made from the model (:func:`model_array`). So one library serves every
robot, from its first call, whatever its size. It is built with the package where a C compiler exists (an
optional extension, ``course_dynamics.core.compiled._looped``, from the generated ``looped.c`` beside this
module) and run by :mod:`~course_dynamics.core.compiled.looped`.

=======================  ==================================================================================
step (C function)        traced from
=======================  ==================================================================================
``outward_<kind>``       ``kind.transform`` (the joint transform), then ``newton_euler.outward_link``
                         (6.45)–(6.50) and ``link_wrench``, the link's own part of (6.51)–(6.52)
``carry``                ``newton_euler.carried_wrench``: a child's f and n into its parent's (6.51)–(6.52)
``torque_<kind>``        ``newton_euler.joint_torque`` (6.53) / (6.44)
``place_<kind>``         ``kind.transform``, ``kinematics.placement_link``, ``spatial.motion_axis`` and
                         ``spatial.body_inertia``: a body's placement, unit motion and spatial inertia
``composite``            ``spatial.Inertia.__add__``: a composite body's inertia into its parent's
``force``                ``spatial.Inertia.times``: Fᵢ = Iᶜᵢ sᵢ
``power``                ``spatial.power``: Mₖᵢ = sₖᵀ Fᵢ
=======================  ==================================================================================

The loops themselves (``rnea`` and ``crba`` in the C, :data:`DRIVERS`) are the iterations of
:func:`~course_dynamics.core.newton_euler.outward_iteration`,
:func:`~course_dynamics.core.newton_euler.inward_iteration`
and ``crba.mass_matrix_entries`` (:func:`~course_dynamics.core.crba.mass_matrix`), with the mimic coupling
θ_bodies = S Θ + b at their entry and Sᵀ at their exit (:meth:`~course_dynamics.core.model.Model.body_entries`;
M's entry of bodies k and i goes to coordinates jₖ and jᵢ, scaled by both multipliers); a child's force, moment
and composite inertia are added into its parent's as the child is reached, tips to base, so that a tree's
children add in the reverse order (a difference in the last bits; a chain's are the same bits).

The C refuses (TypeError, ValueError) anything but C-contiguous float64 buffers of whole, finite states and a
model array it can trust (every parent before its child, a joint kind it has, a coordinate in range), so a
caller can try it first; it copies the model array before checking it, and computes from the copy (another
thread writing the array meanwhile, or an output over it, changes nothing), and its work memory is O(bodies).

To regenerate ``looped.c`` after the recursions changed (a test holds it to what they generate), then reinstall
the package::

    python -c "from course_dynamics.core.compiled import steps; steps.SOURCE.write_text(steps.c_source())"
"""
from __future__ import annotations

import hashlib
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..algebra import Mat3, Vec3
from ..joints import kind_of
from ..kinematics import JointTransforms, placement_link
from ..model import Model
from ..newton_euler import OutwardPass, carried_wrench, joint_torque, link_wrench, outward_link
from ..operations import EXACT
from ..spatial import Inertia, body_inertia, motion_axis, power
from . import entry, impulses, native, rollout, stopping
from .tracing import Program, Tape, recorded_program

#: The generated C of the native loop, shipped with the package and built with it.
SOURCE = Path(__file__).with_name("looped.c")
#: The doubles of one body's record in the model array.
BODY = 64
#: The doubles before the first body's record (the counts, then the base's block for each loop).
HEADER = 64
#: A body's block in the Newton–Euler loop (ω, ω̇, v̇, ᵖᵢR, ᵖPᵢ, f, n).
RNEA_BLOCK = 27
#: A body's block in the composite-rigid-body loop (⁰ᵢR, ⁰Pᵢ, s, and its composite inertia m, h, Ī).
CRBA_BLOCK = 31
KIND_CODES = {"revolute": 0, "continuous": 0, "prismatic": 1}  # the C's joint kinds: one step function each
#: Where each number of a body sits in its record.
SLOTS = {"parent": 0, "kind": 1, "leader": 2, "multiplier": 3, "offset": 4, "rotation_parts": 5, "R0": 32, "P": 41,
         "axis": 44, "R0_axis": 47, "p_com": 50, "mass": 53, "I_com": 54}


class _Body:
    """A body whose numbers are traced inputs ``b<slot>``: what one step is traced on."""

    def __init__(self, tape: Tape, joint_type: str):
        S = SLOTS
        vec, mat = (lambda k: _vec(tape, "b", S[k])), (lambda k: _mat(tape, "b", S[k]))  # noqa: E731
        self.joint_type, self.parent = joint_type, 0
        self.rotation_parts = tuple(_mat(tape, "b", S["rotation_parts"] + 9 * part).rows for part in range(3))
        self.R0_m, self.P_v, self.axis_v = mat("R0"), vec("P"), vec("axis")
        self.R0_axis_v, self.p_com_v, self.I_com_m = vec("R0_axis"), vec("p_com"), mat("I_com")
        self.mass_s = tape.input(f"b{S['mass']}")

    @property
    def is_prismatic(self) -> bool:
        return self.joint_type == "prismatic"


@dataclass(frozen=True)
class _One:
    """A robot of the one traced body, as the steps' operations ask for it (``model.bodies[0]``)."""

    bodies: tuple


def _vec(tape: Tape, name: str, start: int) -> Vec3:
    return Vec3(*(tape.input(f"{name}{start + k}") for k in range(3)))


def _mat(tape: Tape, name: str, start: int) -> Mat3:
    return Mat3(tuple(tuple(tape.input(f"{name}{start + 3 * r + c}") for c in range(3)) for r in range(3)))


def _flat(*values) -> list:
    out = []
    for v in values:
        out += [x for row in v.rows for x in row] if isinstance(v, Mat3) else list(v)
    return out


def _inertia(tape: Tape, name: str, start: int) -> Inertia:
    return Inertia(tape.input(f"{name}{start}"), _vec(tape, name, start + 1), _mat(tape, name, start + 4))


def trace_steps() -> dict[str, Program]:
    """Every step of the module docstring's table, traced on a body whose numbers are inputs.

    Returns
    -------
    dict of str to Program
        The steps by name; their inputs are vectors ``b`` (the body's record), ``s`` (θ, θ̇, θ̈ of the body),
        ``p`` and ``c`` (a parent's and a child's block), ``f`` (a force).

    Examples
    --------
    >>> steps = trace_steps()
    >>> sorted(steps)[:4], steps["carry"].inputs
    (['carry', 'composite', 'force', 'outward_prismatic'], ['c', 'p'])
    """
    steps = {}
    for kind in ("revolute", "prismatic"):
        t = Tape()
        body = _Body(t, kind)
        model = _One((body,))
        theta, theta_dot, theta_ddot = (t.input(f"s{k}") for k in range(3))
        R, P = kind_of(body).transform(body, theta)
        X = JointTransforms([R], [R.T], [P])
        parent = (_vec(t, "p", 0), _vec(t, "p", 3), _vec(t, "p", 6))
        w, w_dot, v, v_c, F, N = outward_link(model, X, 0, parent, theta_dot, theta_ddot, Vec3(0, 0, 0), EXACT)
        f, n = link_wrench(model, 0, OutwardPass([w], [w_dot], [v], [v_c], [F], [N]))
        steps[f"outward_{kind}"] = recorded_program(f"outward_{kind}", t, ["b", "s", "p"],
                                                    _flat(w, w_dot, v, R, P, f, n))

        t = Tape()
        body = _Body(t, kind)
        c = [_vec(t, "c", 21), _vec(t, "c", 24)]
        steps[f"torque_{kind}"] = recorded_program(f"torque_{kind}", t, ["b", "c"],
                                           [joint_torque(_One((body,)), 0, [c[0]], [c[1]], None)])

        t = Tape()
        body = _Body(t, kind)
        R_joint, P_joint = kind_of(body).transform(body, t.input("s0"))
        R, P, P_com = placement_link(body, R_joint, P_joint, (_mat(t, "p", 0), _vec(t, "p", 9)))
        inertia = body_inertia(body, R, P_com)
        steps[f"place_{kind}"] = recorded_program(f"place_{kind}", t, ["b", "s", "p"],
                                          _flat(R, P, *motion_axis(body, R, P)) + [inertia.m] +
                                          _flat(inertia.h, inertia.I))
    t = Tape()
    R_c, P_c = _mat(t, "c", 9), _vec(t, "c", 18)
    X = JointTransforms([R_c], [R_c.T], [P_c])
    f, n = carried_wrench(None, X, 0, _vec(t, "p", 21), _vec(t, "p", 24), _vec(t, "c", 21), _vec(t, "c", 24))
    steps["carry"] = recorded_program("carry", t, ["c", "p"], _flat(f, n))

    t = Tape()
    total = _inertia(t, "p", 18) + _inertia(t, "c", 18)
    steps["composite"] = recorded_program("composite", t, ["c", "p"], [total.m] + _flat(total.h, total.I))

    t = Tape()
    moment, force = _inertia(t, "c", 18).times((_vec(t, "c", 12), _vec(t, "c", 15)))
    steps["force"] = recorded_program("force", t, ["c"], _flat(moment, force))

    t = Tape()
    steps["power"] = recorded_program("power", t, ["c", "f"], [power((_vec(t, "c", 12), _vec(t, "c", 15)),
                                                              (_vec(t, "f", 0), _vec(t, "f", 3)))])
    return steps


#: Where the model array holds the base's acceleration, −g (in the Newton–Euler loop's base block).
BASE_ACCELERATION = slice(3 + 6, 3 + 9)
#: What the C's own digest stands in for while the digest is computed (:func:`source_digest`).
UNDIGESTED = "0" * 64
#: The loops over the bodies and the extension's wrappers, C written by hand around the traced steps.
DRIVERS = r"""
/* ---- the loops over the bodies (written by hand: the iterations, not their equations) ---- */

#if defined(__FAST_MATH__) || (defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__)
#error "the native loop checks its inputs for NaN and infinity: build it without -ffast-math or -ffinite-math-only"
#endif

#define HEADER {header}
#define BODY {body}
#define RNEA_BLOCK {rnea_block}
#define CRBA_BLOCK {crba_block}

typedef void (*step_t)(const double *restrict, const double *restrict, const double *restrict, double *restrict);

/* The model array as the library made it, or NULL and an error: every number finite, every parent before its
   child, every joint kind and coordinate known. */
static int check_model(const double *model, Py_ssize_t length, Py_ssize_t *bodies, Py_ssize_t *n)
{{
    if (length < HEADER) goto bad;
    for (Py_ssize_t k = 0; k < length; k++)
        if (!isfinite(model[k])) goto bad;
    double nb = model[0], nc = model[1];
    if (nb < 1 || nc < 1 || nb > 100000 || nc > nb || nb != (double)(Py_ssize_t)nb || nc != (double)(Py_ssize_t)nc)
        goto bad;
    *bodies = (Py_ssize_t)nb;
    *n = (Py_ssize_t)nc;
    if (length != HEADER + *bodies * BODY) goto bad;
    for (Py_ssize_t i = 0; i < *bodies; i++) {{
        const double *b = model + HEADER + i * BODY;
        if (b[0] < -1 || b[0] >= (double)i || b[0] != (double)(Py_ssize_t)b[0]) goto bad;
        if (b[1] != 0 && b[1] != 1) goto bad;
        if (b[2] < 0 || b[2] >= nc || b[2] != (double)(Py_ssize_t)b[2]) goto bad;
    }}
    return 0;
bad:
    PyErr_SetString(PyExc_ValueError, "the model array is not one the library made");
    return -1;
}}

/* τ = Sᵀ τ_bodies by the outward iteration base to tips and the inward one tips to base. */
static void rnea(const double *model, Py_ssize_t bodies, Py_ssize_t n, const double *q, const double *qd,
                 const double *qdd, double *work, double *out)
{{
    static const step_t outward[2] = {{outward_revolute_one, outward_prismatic_one}};
    static const step_t torque[2] = {{torque_revolute_one, torque_prismatic_one}};
    for (Py_ssize_t i = 0; i < bodies; i++) {{
        const double *b = model + HEADER + i * BODY;
        Py_ssize_t p = (Py_ssize_t)b[0], j = (Py_ssize_t)b[2];
        const double a = b[3];
        const double s[3] = {{a * q[j] + b[4], a * qd[j], qdd ? a * qdd[j] : 0.0}};  /* θ_b = S Θ + b */
        outward[(int)b[1]](b, s, p < 0 ? model + 3 : work + p * RNEA_BLOCK, work + i * RNEA_BLOCK);
    }}
    for (Py_ssize_t j = 0; j < n; j++)
        out[j] = 0.0;
    for (Py_ssize_t i = bodies - 1; i >= 0; i--) {{
        const double *b = model + HEADER + i * BODY;
        Py_ssize_t p = (Py_ssize_t)b[0];
        double t, carried[6];
        torque[(int)b[1]](b, work + i * RNEA_BLOCK, NULL, &t);
        out[(Py_ssize_t)b[2]] += b[3] * t;                                            /* τ = Sᵀ τ_bodies */
        if (p >= 0) {{
            carry_one(work + i * RNEA_BLOCK, work + p * RNEA_BLOCK, NULL, carried);
            memcpy(work + p * RNEA_BLOCK + 21, carried, sizeof carried);
        }}
    }}
}}

/* M = Sᵀ M_bodies S by the composite-rigid-body algorithm. */
static void crba(const double *model, Py_ssize_t bodies, Py_ssize_t n, const double *q, double *work,
                 double *out)
{{
    static const step_t place[2] = {{place_revolute_one, place_prismatic_one}};
    for (Py_ssize_t i = 0; i < bodies; i++) {{
        const double *b = model + HEADER + i * BODY;
        Py_ssize_t p = (Py_ssize_t)b[0];
        const double s[1] = {{b[3] * q[(Py_ssize_t)b[2]] + b[4]}};
        place[(int)b[1]](b, s, p < 0 ? model + 3 + RNEA_BLOCK : work + p * CRBA_BLOCK, work + i * CRBA_BLOCK);
    }}
    for (Py_ssize_t i = bodies - 1; i >= 0; i--) {{
        Py_ssize_t p = (Py_ssize_t)model[HEADER + i * BODY];
        if (p >= 0) {{
            double total[13];
            composite_one(work + i * CRBA_BLOCK, work + p * CRBA_BLOCK, NULL, total);
            memcpy(work + p * CRBA_BLOCK + 18, total, sizeof total);
        }}
    }}
    for (Py_ssize_t k = 0; k < n * n; k++)
        out[k] = 0.0;
    for (Py_ssize_t i = 0; i < bodies; i++) {{      /* M_bodies[k][i] for i and each ancestor k, into Sᵀ M_bodies S */
        const double *bi = model + HEADER + i * BODY;
        const Py_ssize_t ji = (Py_ssize_t)bi[2];
        double F[6];
        force_one(work + i * CRBA_BLOCK, NULL, NULL, F);
        for (Py_ssize_t k = i; k >= 0; k = (Py_ssize_t)model[HEADER + k * BODY]) {{
            const double *bk = model + HEADER + k * BODY;
            const Py_ssize_t jk = (Py_ssize_t)bk[2];
            double m;
            power_one(work + k * CRBA_BLOCK, F, NULL, &m);
            out[jk * n + ji] += bk[3] * bi[3] * m;
            if (k != i)
                out[ji * n + jk] += bi[3] * bk[3] * m;
        }}
    }}
}}

/* name(model, inputs…, out): one loop over every state of the inputs, the GIL released. */
static PyObject *run(PyObject *const *args, Py_ssize_t nargs, Py_ssize_t inputs, int which, const char *name)
{{
    Py_buffer views[5];
    Py_ssize_t got = 0, states = 0, bodies = 0, n = 0;
    PyObject *result = NULL;
    double *work = NULL, *model = NULL;
    if (nargs != inputs + 2) {{
        PyErr_Format(PyExc_TypeError, "%s takes the model array, %zd input arrays and one output array", name,
                     inputs);
        return NULL;
    }}
    for (; got < inputs + 2; got++) {{
        int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (got == inputs + 1 ? PyBUF_WRITABLE : 0);
        if (PyObject_GetBuffer(args[got], &views[got], flags) != 0)
            goto done;
        if (views[got].itemsize != 8 || strcmp(views[got].format, "d") != 0) {{
            PyErr_Format(PyExc_TypeError, "%s takes C-contiguous float64 arrays", name);
            got++;
            goto done;
        }}
    }}
    /* the model is copied before it is checked: what is computed from is what was checked, whatever the caller's
       array holds meanwhile (another thread, an output that overlaps it) */
    if ((model = malloc(views[0].len ? (size_t)views[0].len : 1)) == NULL) {{
        PyErr_NoMemory();
        goto done;
    }}
    memcpy(model, views[0].buf, (size_t)views[0].len);
    if (check_model(model, views[0].len / 8, &bodies, &n) != 0)
        goto done;
    Py_ssize_t width = which == 1 ? n * n : n;
    states = views[inputs + 1].len / (8 * width);
    if (views[inputs + 1].len != states * 8 * width) {{
        PyErr_Format(PyExc_ValueError, "%s: the output holds no whole number of states", name);
        goto done;
    }}
    for (Py_ssize_t i = 1; i <= inputs; i++) {{
        if (views[i].len != states * 8 * n) {{
            PyErr_Format(PyExc_ValueError, "%s: an input holds another number of states than the output", name);
            goto done;
        }}
        for (Py_ssize_t k = 0; k < states * n; k++) {{
            if (!isfinite(((const double *)views[i].buf)[k])) {{
                PyErr_Format(PyExc_ValueError, "%s: an input is not finite", name);
                goto done;
            }}
        }}
    }}
    size_t size = (size_t)bodies * (which == 1 ? CRBA_BLOCK : RNEA_BLOCK);
    if ((work = malloc(sizeof(double) * size)) == NULL) {{
        PyErr_NoMemory();
        goto done;
    }}
    const double *in[3] = {{NULL, NULL, NULL}};
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t k = 0; k < states; k++) {{
        for (Py_ssize_t i = 0; i < inputs; i++)
            in[i] = (const double *)views[i + 1].buf + k * n;
        double *o = (double *)views[inputs + 1].buf + k * width;
        if (which == 1)
            crba(model, bodies, n, in[0], work, o);
        else
            rnea(model, bodies, n, in[0], in[1], which == 0 ? in[2] : NULL, work, o);
    }}
    Py_END_ALLOW_THREADS
    Py_INCREF(Py_None);
    result = Py_None;
done:
    free(work);
    free(model);
    for (Py_ssize_t i = 0; i < got; i++)
        PyBuffer_Release(&views[i]);
    return result;
}}

static PyObject *tau(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{{ return run(args, nargs, 3, 0, "tau"); }}

static PyObject *mass_matrix(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{{ return run(args, nargs, 1, 1, "mass_matrix"); }}

static PyObject *bias(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{{ return run(args, nargs, 2, 2, "bias"); }}
{rollout}
{impulses}
{stopping}
{entry}
static PyMethodDef methods[] = {{
    {{"tau", (PyCFunction)(void (*)(void))tau, METH_FASTCALL, "tau(model, q, qd, qdd, out)"}},
    {{"mass_matrix", (PyCFunction)(void (*)(void))mass_matrix, METH_FASTCALL, "mass_matrix(model, q, out)"}},
    {{"bias", (PyCFunction)(void (*)(void))bias, METH_FASTCALL, "bias(model, q, qd, out)"}},
    {{"rollout", (PyCFunction)(void (*)(void))rollout, METH_FASTCALL,
      "rollout(terms, times, q, qd, qdd, tau, table, parameters, status, scheme, k0, k1, m0, m1"
      "[, held, reaction, bounds, records])"}},
    {{"remember", (PyCFunction)(void (*)(void))remember, METH_FASTCALL,
      "remember(model, owner, source, environ, names, writes, empty)"}},
    {{"forget", (PyCFunction)(void (*)(void))forget, METH_FASTCALL, "forget(model_id)"}},
    {{"remembered", (PyCFunction)(void (*)(void))remembered, METH_FASTCALL, "remembered(model)"}},
    {{"one", (PyCFunction)(void (*)(void))one, METH_FASTCALL, "one(model, code, *arrays)"}},
    {{NULL, NULL, 0, NULL}}
}};

static struct PyModuleDef module = {{PyModuleDef_HEAD_INIT, "_looped", NULL, -1, methods}};

PyMODINIT_FUNC PyInit__looped(void)
{{
    PyObject *m = PyModule_Create(&module);
    if (m != NULL && PyModule_AddStringConstant(m, "SOURCE_SHA256", "{digest}") != 0) {{
        Py_DECREF(m);
        return NULL;
    }}
    return m;
}}
"""

def _step_function(program: Program) -> str:
    """``static void <name>_one(in, in, in, out)``: the step's operations, one line each (unused inputs NULL)."""
    inputs = {f"{name}{j}": f"{name}[{j}]" for name in program.inputs for j in range(max(BODY, HEADER))}
    unused = range(len(program.inputs), 3)
    parameters = [f"const double *restrict {name}" for name in program.inputs]
    parameters += [f"const double *restrict unused{k}" for k in unused]
    lines = [f"static void {program.name}_one({', '.join(parameters)}, double *restrict out)", "{"]
    lines += [f"    (void)unused{k};" for k in unused]
    for i, (op, *operands) in enumerate(program.nodes):
        if op != "input":
            arguments = (native.c_argument(a, program.nodes, inputs) for a in operands)
            lines.append(f"    const double t{i} = {native.OPERATIONS[op].format(*arguments)};")
    lines += [f"    out[{k}] = {native.c_argument(o, program.nodes, inputs)};" for k, o in enumerate(program.outputs)]
    return "\n".join(lines + ["}"])


def c_source(steps: dict[str, Program] | None = None) -> str:
    """The native loop's C: every step as a C function (one line per operation), the loops, the wrappers.

    Every step function takes three inputs and an output (its unused inputs NULL), so that the loops can pick
    a joint kind's step from a table.

    Parameters
    ----------
    steps : dict of str to Program, optional
        The traced steps (:func:`trace_steps`, by default).

    Returns
    -------
    str
        The C source, as ``looped.c`` holds it.

    Examples
    --------
    >>> source = c_source()
    >>> "static void outward_revolute_one(" in source and "static void rnea(" in source
    True
    """
    steps = steps or trace_steps()
    parts = ["/* course-dynamics' native loop: generated by course_dynamics.core.compiled.steps.c_source() from the",
             "   library's recursions, one line per operation of each body's step; do not edit (regenerate). */",
             "#define PY_SSIZE_T_CLEAN", "#include <Python.h>", "#include <math.h>", "#include <stdlib.h>",
             "#include <string.h>", ""]
    parts += [_step_function(program) for _, program in sorted(steps.items())]
    body = "\n\n".join(parts)
    source = body + DRIVERS.format(header=HEADER, body=BODY, rnea_block=RNEA_BLOCK, crba_block=CRBA_BLOCK,
                                 digest=UNDIGESTED, rollout=rollout.C, impulses=impulses.C,
                                 stopping=stopping.C,
                                 entry=entry.C)
    return source.replace(f'"SOURCE_SHA256", "{UNDIGESTED}"', f'"SOURCE_SHA256", "{source_digest(source)}"')


def source_digest(source: str) -> str:
    """The SHA-256 of a native loop's whole C, its own digest (which it holds as ``SOURCE_SHA256``, the built
    library's constant) taken as :data:`UNDIGESTED`: a library built from any other C is told apart.

    Parameters
    ----------
    source : str
        The C source (:func:`c_source`, or ``looped.c``).

    Returns
    -------
    str
        The hex digest.

    Examples
    --------
    >>> source = c_source()
    >>> source_digest(source) in source
    True
    """
    unset = re.sub(r'"SOURCE_SHA256", "[0-9a-f]{64}"', f'"SOURCE_SHA256", "{UNDIGESTED}"', source)
    return hashlib.sha256(unset.encode()).hexdigest()


def model_array(model: Model) -> np.ndarray:
    """The model as the native loop reads it: a header, then one record of :data:`BODY` doubles per body.

    The header holds the counts of bodies and coordinates, and the base's
    block of each loop (at rest, lifted by −g: :meth:`~course_dynamics.core.operations.Operations.base_acceleration`;
    and placed at the origin). A body's record holds its numbers at :data:`SLOTS`.

    Parameters
    ----------
    model : Model
        The robot (float numbers; a model with symbols has no array).

    Returns
    -------
    numpy.ndarray, shape (HEADER + BODY n_bodies,)
        float64.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> array = model_array(load_robot("two_link"))
    >>> array.shape, array[:2].tolist(), (array[9:12] + 0.0).tolist()      # two bodies, two coordinates; −g
    ((192,), [2.0, 2.0], [0.0, 0.0, 9.81])
    """
    out = np.zeros(HEADER + BODY * model.n_bodies)
    out[:2] = model.n_bodies, model.n
    out[BASE_ACCELERATION] = list(EXACT.base_acceleration(model.gravity_v))
    out[3 + RNEA_BLOCK:3 + RNEA_BLOCK + 9] = np.eye(3).ravel()
    for i, (body, (j, a, b)) in enumerate(zip(model.bodies, model.coupling)):
        record = out[HEADER + i * BODY:HEADER + (i + 1) * BODY]
        S = SLOTS
        record[:5] = body.parent, KIND_CODES[body.joint_type], j, a, b
        record[S["rotation_parts"]:S["rotation_parts"] + 27] = np.ravel(body.rotation_parts)
        record[S["R0"]:S["R0"] + 9] = np.ravel(body.R0)
        record[S["P"]:S["P"] + 3] = body.P
        record[S["axis"]:S["axis"] + 3] = body.axis
        record[S["R0_axis"]:S["R0_axis"] + 3] = list(body.R0_axis_v)
        record[S["p_com"]:S["p_com"] + 3] = body.p_com
        record[S["mass"]] = body.mass_s
        record[S["I_com"]:S["I_com"] + 9] = np.ravel(body.I_com)
    return out


__all__ = ["BASE_ACCELERATION", "BODY", "CRBA_BLOCK", "DRIVERS", "HEADER", "RNEA_BLOCK", "SLOTS", "SOURCE",
           "UNDIGESTED", "c_source", "model_array", "source_digest", "trace_steps"]
