"""The one evaluator: for a model and a workload, the fastest implementation that gives the same numbers.

Two implementations compute every term: the recursions as written (:mod:`~course_dynamics.core.newton_euler`,
:mod:`~course_dynamics.core.crba`, …, the text a student reads; they take one state, a batch, sympy
symbols, dual or complex numbers) and the compiled programs traced from them
(:mod:`~course_dynamics.core.compiled`; float states only, agreeing to 1e-12). Which one runs is chosen
here and nowhere else: by the package's own functions (``course_dynamics.inverse_dynamics``,
``mass_matrix``, ``coriolis_matrix``, ``gravity_torques``, ``forward_dynamics``), by ``simulate`` and by
the torques of a log.

=========================  ===================================================================
workload                   implementation
=========================  ===================================================================
symbols, duals, complex    the recursions as written (the compiled programs take floats only)
floats, little work        the recursions as written, vectorised over a batch
floats, work that pays     the compiled model: loaded from the cache (or compiled) once per
                           process and model, then used for every later call on that model
=========================  ===================================================================

The compiled model runs as C where a compiler exists (:mod:`~course_dynamics.core.compiled.native`):
built when the work reaches :data:`NATIVE_SECONDS` (a long simulation; building takes seconds, once, as the
library is cached), and used at once wherever the cache already holds it. The build runs in the background
(:mod:`~course_dynamics.core.compiled.building`: bounded, and never tried again once it failed): this call
and the ones after it take the Python programs until a later choice finds the library built, never in the
middle of a call; ``compiled=True`` asks for the compiled model and waits for its build. A call whose
arguments are one finite float64 state each goes straight to the native code, with no other check.

"Work that pays" is an estimate in seconds of what the interpreted recursions would take —
:data:`CALL_SECONDS` a call plus :data:`STATE_SECONDS` a state of a batch — summed over the calls on one
model in this process; when it reaches :data:`COMPILE_SECONDS`, about what loading a compiled model from a
warm cache costs, the model is compiled. So a one-off call stays interpreted, a loop of calls or a
long simulation switches after a few milliseconds, and ``simulate`` (whose work is known in advance)
decides at its start. A robot too large to compile (:class:`~course_dynamics.core.compiled.ProgramTooLargeError`)
stays interpreted, with one :class:`~course_dynamics.core.compiled.CompileWarning`.

>>> import numpy as np
>>> from course_dynamics import load_robot
>>> arm = load_robot("two_link")
>>> implementation(arm, calls=1, states=10, compiled=None) is None          # a little work: interpreted
True
>>> fast = implementation(arm, calls=1000, states=1, compiled=None)         # a simulation's worth: compiled
>>> np.round(fast.inverse_dynamics([0.1, 0.2], [0, 0], [0, 0]), 6)
array([18.390227,  3.74874 ])
"""
from __future__ import annotations

import warnings
import weakref
from dataclasses import dataclass

import numpy as np

from . import dynamics
from . import forward_dynamics as interpreted_forward
from . import newton_euler
from .compiled import CompiledModel, CompileWarning, ProgramTooLargeError, compile_model
from .friction import Friction
from .model import Model
from .state import as_state, batch_shape

CALL_SECONDS = 3e-4     # the interpreted recursions' cost of one call (UR5: 0.26 ms for τ at one state)
STATE_SECONDS = 1.5e-6  # and of one more state in a vectorised batch (UR5: 13 ms for τ at 10 000 states)
COMPILE_SECONDS = 0.03  # a compiled model loaded from a warm cache (two-link 10 ms, UR5 25 ms, Panda 50 ms)
NATIVE_SECONDS = 1.0    # work that pays for building the C version once (UR5 about 3 s, then cached)


@dataclass
class _Record:
    """What this process knows of one model: the interpreted work done so far, and its compiled model."""

    model: weakref.ref
    seconds: float = 0.0
    compiled: CompiledModel | None = None
    too_large: bool = False
    native_tried: bool = False


_RECORDS: dict[int, _Record] = {}


def _record(model: Model) -> _Record:
    record = _RECORDS.get(id(model))
    if record is None or record.model() is not model:
        record = _Record(weakref.ref(model, lambda _, key=id(model): _RECORDS.pop(key, None)))
        _RECORDS[id(model)] = record
    return record


def interpreted_seconds(calls: int, states: int) -> float:
    """The estimated time of ``calls`` interpreted calls on ``states`` states each, s.

    >>> round(interpreted_seconds(calls=1000, states=1), 4)   # a simulation's worth of one-state calls, s
    0.3015
    """
    return calls * (CALL_SECONDS + states * STATE_SECONDS)


def implementation(model: Model, calls: int = 1, states: int = 1, compiled: bool | None = None) -> CompiledModel | None:
    """The compiled model to run ``calls`` calls of ``states`` float states each, or None for the recursions.

    ``compiled`` True compiles (a robot too large raises :class:`~course_dynamics.core.compiled.ProgramTooLargeError`),
    False never does, None decides by the work (module docstring), counting this work toward the model's total.

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> implementation(arm, calls=1, states=10) is None, implementation(arm, compiled=False) is None
    (True, True)
    """
    if compiled is False:
        return None
    record = _record(model)
    if record.compiled is not None and record.compiled.native_build is not None:
        record.compiled = record.compiled.collected()  # a new CompiledModel once its library is built
    if record.compiled is not None and (record.native_tried or record.compiled.native):
        return record.compiled
    if compiled is None:
        if record.too_large:
            return None
        record.seconds += interpreted_seconds(calls, states)
        if record.seconds < COMPILE_SECONDS:
            return None
    build = bool(compiled) or record.seconds >= NATIVE_SECONDS
    if record.compiled is not None and not build:
        return record.compiled
    try:
        record.compiled = compile_model(model, native_code=(True if compiled else "background") if build else None)
        record.native_tried = build
    except ProgramTooLargeError as error:
        if compiled:
            raise
        record.too_large = True
        warnings.warn(str(ProgramTooLargeError(error.what, "; running the interpreted recursions")), CompileWarning,
                      stacklevel=3)
        return None
    return record.compiled


def _native(model: Model, name: str, *arguments) -> np.ndarray | None:
    """The model's native result for one finite float64 state as given, or None (CompiledModel.native_call)."""
    record = _RECORDS.get(id(model))
    if record is None or record.compiled is None or not record.compiled.native or record.model() is not model:
        return None
    return record.compiled.native_call(name, *arguments)


def _float_work(model: Model, *arrays: np.ndarray) -> CompiledModel | None:
    """The implementation for one call on these checked states: compiled only for float arrays."""
    if not all(a.dtype == np.float64 for a in arrays):
        return None
    states = int(np.prod(batch_shape(*arrays), dtype=np.int64))
    return implementation(model, 1, states)


def inverse_dynamics(model: Model, q, qd, qdd) -> np.ndarray:
    """τ (6.45)–(6.53), shape (n,) or (..., n), N·m or N, by the fastest path (module docstring).

    As :func:`course_dynamics.core.newton_euler.inverse_dynamics`, which it calls for symbols and little work.

    >>> from course_dynamics import load_robot
    >>> np.round(inverse_dynamics(load_robot("two_link"), [0.1, 0.2], [1, 0], [0, 1]), 6)
    array([18.74624 ,  3.948474])
    """
    out = _native(model, "tau", q, qd, qdd)
    if out is not None:
        return out
    q, qd, qdd = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, qdd, "qdd")
    fast = _float_work(model, q, qd, qdd)
    return fast.inverse_dynamics(q, qd, qdd) if fast is not None else newton_euler.inverse_dynamics(model, q, qd, qdd)


def mass_matrix(model: Model, q) -> np.ndarray:
    """M(Θ), shape (n, n) or (..., n, n), by the fastest path; as :func:`course_dynamics.core.dynamics.mass_matrix`.

    >>> from course_dynamics import load_robot
    >>> np.round(mass_matrix(load_robot("two_link"), [0.0, 0.5]), 6)
    array([[1.261033, 0.335517],
           [0.335517, 0.16    ]])
    """
    out = _native(model, "mass_matrix", q)
    if out is not None:
        return out
    q = as_state(model, q, "q")
    fast = _float_work(model, q)
    return fast.mass_matrix(q) if fast is not None else dynamics.mass_matrix(model, q)


def coriolis_matrix(model: Model, q, qd) -> np.ndarray:
    """C(Θ, Θ̇), shape (n, n) or (..., n, n), by the fastest path; as :func:`course_dynamics.core.dynamics.coriolis_matrix`.

    >>> from course_dynamics import load_robot
    >>> np.round(coriolis_matrix(load_robot("two_link"), [0.0, 0.5], [1.0, 0.0]), 6)
    array([[ 0.      , -0.095885],
           [ 0.095885,  0.      ]])
    """
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    fast = _float_work(model, q, qd)
    return fast.coriolis_matrix(q, qd) if fast is not None else dynamics.coriolis_matrix(model, q, qd)


def gravity_torques(model: Model, q) -> np.ndarray:
    """G(Θ), shape (n,) or (..., n), by the fastest path; as :func:`course_dynamics.core.dynamics.gravity_torques`.

    >>> from course_dynamics import load_robot
    >>> np.round(gravity_torques(load_robot("two_link"), [0.0, 0.0]), 6)
    array([18.639,  3.924])
    """
    q = as_state(model, q, "q")
    fast = _float_work(model, q)
    return fast.bias(q, np.zeros_like(q)) if fast is not None else dynamics.gravity_torques(model, q)


def forward_dynamics(model: Model, q, qd, tau, friction: Friction | None = None) -> np.ndarray:
    """Θ̈ (6.115), shape (n,) or (..., n), by the fastest path; as
    :func:`course_dynamics.core.forward_dynamics.forward_dynamics`.

    >>> from course_dynamics import load_robot
    >>> np.round(forward_dynamics(load_robot("two_link"), [0.0, 0.5], [0, 0], [24.0, 5.0]), 6)
    array([4.623991, 0.030879])
    """
    out = _native(model, "forward_dynamics", q, qd, tau) if friction is None else None
    if out is not None:
        return out
    q, qd, tau = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, tau, "tau")
    fast = _float_work(model, q, qd, tau)
    if fast is not None:
        return fast.forward_dynamics(q, qd, tau, friction)
    return interpreted_forward.forward_dynamics(model, q, qd, tau, friction)
