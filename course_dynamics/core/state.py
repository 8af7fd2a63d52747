"""Joint-space states: checking them, and moving between arrays and per-joint scalars.

A state vector Θ, Θ̇ or Θ̈ is an array whose last axis runs over the model's
joints (``model.joint_names``): shape (n,) for one state, (N, n) for a batch of
N states, or a numpy object array of sympy expressions. The recursion works on
one scalar per joint (a float, an (N,) array or a sympy expression); these
helpers split arrays into such per-joint *entries* and assemble results,
nested lists of entries, back into arrays.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base.errors import StateError


@dataclass(frozen=True)
class Layout:
    """How results are assembled: leading batch shape and element dtype.

    >>> Layout(batch=(3,), dtype=float).assemble([np.zeros(3), np.ones(3)], (2,))   # 3 states, 2 joints
    array([[0., 1.],
           [0., 1.],
           [0., 1.]])
    """

    batch: tuple[int, ...]
    dtype: object

    def assemble(self, entries, shape: tuple[int, ...]) -> np.ndarray:
        """Array of shape ``batch + shape`` from nested lists of scalars (or Vec3s)."""
        if not self.batch and len(shape) == 1 and self.dtype is float:
            return np.array(entries, dtype=float)  # one state: the common, fast case
        out = np.empty(self.batch + shape, dtype=self.dtype)
        for index in np.ndindex(*shape):
            value = entries
            for k in index:
                value = value[k]
            out[(Ellipsis, *index)] = value
        return out


def as_state(model, values, name: str = "q") -> np.ndarray:
    """``values`` as a checked array of shape (..., n); numeric input becomes float.

    A float array of the right shape whose values are finite is returned as it is (no copy): the one-state
    path of the compiled models calls this for every argument.

    Parameters
    ----------
    model : Model
        The robot (its n joints, named in a refusal).
    values : array_like, shape (n,) or (N, n)
        A state Θ, Θ̇ or Θ̈ (rad, rad/s, rad/s²; m, m/s, m/s² for a prismatic joint), numbers, complex numbers
        (for complex-step derivatives) or sympy expressions.
    name : str, optional
        The argument's name in a refusal: ``"q"``, ``"qd"``, ``"qdd"``, ….

    Returns
    -------
    numpy.ndarray, shape (n,) or (N, n)
        The state: float for numbers, complex or object (sympy) as given.

    Raises
    ------
    StateError
        If ``values`` is not numeric, is a scalar, its last axis is not the model's n joints, or a value is
        NaN or infinite (naming the joint and the row).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> as_state(load_robot("two_link"), [0, 1])
    array([0., 1.])
    """
    if type(values) is np.ndarray and values.dtype == np.float64 and values.ndim and values.shape[-1] == model.n \
            and math.isfinite(sum(values.tolist()) if values.ndim == 1 else values.sum()):
        return values  # finite: a NaN or an inf (or a sum that overflows) takes the checks below
    array = np.asarray(values)
    if array.dtype != object and array.dtype.kind != "c":  # complex: for complex-step derivatives
        try:
            array = array.astype(float)
        except (TypeError, ValueError):
            raise StateError(f"{name} must be numbers, got {values!r}") from None
    if array.ndim == 0 or array.shape[-1] != model.n:
        got = "a scalar" if array.ndim == 0 else f"{array.shape[-1]} values"
        raise StateError(
            f"{name} has {got} but robot '{model.name}' has {model.n} joints ({', '.join(model.joint_names)})"
        )
    if array.dtype != object and not np.all(np.isfinite(array)):
        bad = np.argwhere(~np.isfinite(array))[0]
        row = f" at row {bad[0]}" if array.ndim == 2 else ""
        raise StateError(f"{name} for joint '{model.joint_names[bad[-1]]}' is {array[tuple(bad)]}{row} "
                         "(must be finite)")
    return array


def entries(array: np.ndarray) -> list:
    """One scalar per joint: Python floats for one state, (N,) arrays for a batch.

    Parameters
    ----------
    array : numpy.ndarray, shape (n,) or (N, n)
        A state, as :func:`as_state` gives it.

    Returns
    -------
    list
        n entries: Python floats (or sympy expressions) for one state, arrays of shape (N,) for a batch.

    Examples
    --------

    >>> entries(np.array([0.5, 1.0]))
    [0.5, 1.0]
    >>> entries(np.zeros((3, 2)))   # a batch of 3 states: one (3,) array per joint
    [array([0., 0., 0.]), array([0., 0., 0.])]
    """
    if array.ndim == 1:
        return array.tolist()  # Python floats (much faster than numpy scalars) or sympy objects
    return [array[..., j] for j in range(array.shape[-1])]


def batch_shape(*arrays: np.ndarray) -> tuple[int, ...]:
    """The batch shape the states share (numpy's broadcasting); StateError when they share none.

    >>> batch_shape(np.zeros((5, 2)), np.zeros(2))
    (5,)
    """
    shapes = [a.shape[:-1] for a in arrays]
    try:
        return tuple(np.broadcast_shapes(*shapes))
    except ValueError:
        raise StateError(f"the states hold batches of different lengths {', '.join(map(str, shapes))}: give each "
                         "argument the same number of rows (or one state, shared by every row)") from None


def layout_of(*arrays: np.ndarray) -> Layout:
    """The common batch shape of the inputs; object dtype if any is symbolic, complex if any is complex.

    >>> layout_of(np.zeros((5, 2)), np.zeros(2))
    Layout(batch=(5,), dtype=<class 'float'>)
    """
    batch = batch_shape(*arrays)
    dtype = float
    if any(a.dtype.kind == "c" for a in arrays):
        dtype = complex
    if any(a.dtype == object for a in arrays):
        dtype = object
    return Layout(batch=tuple(batch), dtype=dtype)


__all__ = ["as_state", "entries"]
