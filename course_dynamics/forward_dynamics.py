"""Forward dynamics (6.115): Θ̈ = M⁻¹(Θ) [τ − V(Θ, Θ̇) − G(Θ) − F(Θ̇)].

M, V and G come from our Newton–Euler recursion; the linear system is solved
by Cholesky factorisation (M is symmetric positive definite for a physical
robot). A singular M — a chain ending in massless links, say — is an error,
never a silently huge acceleration.
"""
from __future__ import annotations

import numpy as np

from .dynamics import _mass_matrix_and_bias_columns, mass_matrix_and_bias
from .friction import Friction
from .model import Model
from .state import as_state

# Smallest allowed ratio of Cholesky pivots (squared), min/max: below it M is singular.
SINGULAR_PIVOT_RATIO = 1e-14


class SingularMassMatrixError(ValueError):
    """M(Θ) is singular: some joint moves no mass."""


def forward_dynamics(model: Model, q, qd, tau, friction: Friction | None = None) -> np.ndarray:
    """Θ̈ from Θ, Θ̇ and applied τ (6.115): shape (n,) or (N, n), rad/s² or m/s².

    Parameters
    ----------
    q, qd, tau : array_like, shape (n,) or (N, n)
    friction : Friction, optional
        Subtracted from τ as F(Θ̇) (6.114); default none.
    """
    q, qd, tau = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, tau, "tau")
    if q.ndim == 1 and qd.ndim == 1 and tau.ndim == 1:
        return accelerations(model, q, qd, tau, friction)
    M, bias = mass_matrix_and_bias(model, q, qd)
    return _solve(model, M, bias, q, qd, tau, friction)


def accelerations(model: Model, q: np.ndarray, qd: np.ndarray, tau: np.ndarray, friction: Friction | None = None) -> np.ndarray:
    """(6.115) for one state of already checked float arrays (n,): the simulator's inner call."""
    M, bias = _mass_matrix_and_bias_columns(model, q.tolist(), qd.tolist())
    return _solve(model, np.array(M), np.array(bias), q, qd, tau, friction)


def _solve(model: Model, M: np.ndarray, bias: np.ndarray, q, qd, tau, friction) -> np.ndarray:
    rhs = tau - bias  # τ − V − G
    if friction is not None:
        rhs = rhs - friction.torques(qd)  # − F (6.114)
    _check_positive_definite(model, M, q)
    return np.linalg.solve(M, rhs[..., None])[..., 0]  # (6.115)


def _check_positive_definite(model: Model, M: np.ndarray, q: np.ndarray) -> None:
    """Cholesky pivots all well above round-off, or SingularMassMatrixError naming the joint."""
    try:
        pivots = np.diagonal(np.linalg.cholesky(M), axis1=-2, axis2=-1) ** 2
        if np.all(pivots.min(axis=-1) > SINGULAR_PIVOT_RATIO * pivots.max(axis=-1)):
            return
    except np.linalg.LinAlgError:
        pass
    eigenvalues = np.linalg.eigvalsh(M)
    q = np.broadcast_to(q, M.shape[:-1])
    k = np.unravel_index(np.argmin(eigenvalues[..., 0] / np.maximum(eigenvalues[..., -1], 1e-300)), eigenvalues.shape[:-1])
    weakest = np.linalg.eigh(M[k])[1][:, 0]
    joint = model.joint_names[int(np.argmax(np.abs(weakest)))]
    raise SingularMassMatrixError(
        f"the mass matrix of robot '{model.name}' is singular at q = {np.round(q[k], 6).tolist()} "
        f"(smallest eigenvalue {eigenvalues[k][0]:.3g}): joint '{joint}' moves no mass (a massless chain?)"
    )
