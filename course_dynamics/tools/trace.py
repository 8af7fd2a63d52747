"""The Newton–Euler iterations kept step by step, as the notes' worked example lays them out.

:func:`trace` evaluates the outward iteration (6.45)–(6.50) and the inward
iteration (6.51)–(6.53) once and keeps, for every link, ⁱωᵢ, ⁱω̇ᵢ, ⁱv̇ᵢ, ⁱv̇_Cᵢ,
ⁱFᵢ, ⁱNᵢ, ⁱfᵢ, ⁱnᵢ and τᵢ (each vector in its own link's frame), numeric or
symbolic: the recursion's own :class:`~course_dynamics.core.newton_euler.LinkQuantities`,
with the names a page needs. :mod:`course_dynamics.output.render` turns a :class:`Trace`
into a text table, LaTeX or a JSON record.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from ..core.model import Model
from ..core.newton_euler import LinkQuantities, newton_euler_links
from ..core.parameters import check_symbolic_size, joint_symbols, symbolic_model
from ..core.symbolic import check_decimals, decimal, tidy

#: The outward iteration's quantities (6.45)–(6.50) ⁱωᵢ, ⁱω̇ᵢ, ⁱv̇ᵢ, ⁱv̇_Cᵢ, ⁱFᵢ, ⁱNᵢ, as keys of :attr:`Trace.values`.
OUTWARD_QUANTITIES = ("omega", "omega_dot", "v_dot", "v_dot_c", "F", "N")  # (6.45)–(6.50)
#: The inward iteration's quantities (6.51)–(6.52) ⁱfᵢ, ⁱnᵢ, as keys of :attr:`Trace.values`.
INWARD_QUANTITIES = ("f", "n")  # (6.51)–(6.52)


@dataclass(frozen=True)
class Trace:
    """One Newton–Euler evaluation, link by link: its
    :class:`~course_dynamics.core.newton_euler.LinkQuantities` and the names that label them.

    ``quantities`` holds numbers, or simplified sympy expressions for a symbolic trace;
    ``values[key][i]`` is link i's vector and ``tau[i]`` its joint's τ, as plain lists.

    Parameters
    ----------
    model_name : str
        The robot's name.
    links : tuple of str
        The moving links' names, base outwards.
    prismatic : tuple of bool
        Whether each link's joint is prismatic.
    quantities : LinkQuantities
        The recursion's vectors per link (each in its own link's frame) and τ.
    symbolic : bool
        Whether the entries are sympy expressions rather than numbers.
    """

    model_name: str
    links: tuple[str, ...]
    prismatic: tuple[bool, ...]
    quantities: LinkQuantities
    symbolic: bool

    @property
    def joints(self) -> tuple[str, ...]:
        """The joints' names, in the model's order."""
        return self.quantities.joints

    @cached_property
    def values(self) -> dict:
        """Per key of :data:`OUTWARD_QUANTITIES` and :data:`INWARD_QUANTITIES`, the per-link vectors as nested
        lists (rad/s, rad/s², m/s², N and N·m as the quantity is)."""
        return {key: getattr(self.quantities, key).tolist() for key in OUTWARD_QUANTITIES + INWARD_QUANTITIES}

    @cached_property
    def tau(self) -> list:
        """τᵢ of every joint as a plain list, N·m (N for a prismatic joint)."""
        return self.quantities.tau.tolist()


def trace(model: Model, q, qd, qdd, symbols=None, decimals: int | None = None) -> Trace:
    """Run both iterations and keep every intermediate quantity.

    ``symbols`` = None gives numbers at the state (q, qd, qdd). Otherwise the
    trace is symbolic: joint variables are the symbols q_<joint>, qd_<joint>,
    qdd_<joint> (q, qd, qdd are ignored), ``symbols`` names the parameters kept
    symbolic (see :mod:`course_dynamics.core.symbolic`), and entries are simplified
    (with the model's numbers as ``decimals``-digit decimals if given).

    Parameters
    ----------
    model : Model
        The robot.
    q : numpy.ndarray, shape (n,)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : numpy.ndarray, shape (n,)
        Joint velocities Θ̇, rad/s (m/s).
    qdd : numpy.ndarray, shape (n,)
        Joint accelerations Θ̈, rad/s² (m/s²).
    symbols : str or sequence of str, optional
        The parameters kept symbolic; None for a numeric trace.
    decimals : int, optional
        Digits of the model's numbers in a symbolic trace; None keeps them exact.

    Returns
    -------
    Trace
        Every intermediate quantity, link by link.

    Raises
    ------
    StateError
        If ``q``, ``qd`` or ``qdd`` is not a finite array of shape (n,) (numeric trace).
    ~course_dynamics.core.parameters.SymbolError
        If ``decimals`` or ``symbols`` is not accepted, or the model is too large for a symbolic trace.
    """
    check_decimals(decimals)
    if symbols is None:
        quantities = newton_euler_links(model, q, qd, qdd)
    else:
        check_symbolic_size(model)
        exact, _ = symbolic_model(model, symbols)
        q_s, qd_s, qdd_s = joint_symbols(model)
        links = newton_euler_links(exact, q_s, qd_s, qdd_s)
        form = np.frompyfunc(lambda x: decimal(tidy(x, q_s), decimals), 1, 1)
        keys = OUTWARD_QUANTITIES + INWARD_QUANTITIES + ("tau",)
        quantities = replace(links, **{key: form(getattr(links, key)) for key in keys})
    return Trace(model_name=model.name, links=tuple(b.name for b in model.bodies),
                 prismatic=tuple(b.is_prismatic for b in model.bodies), quantities=quantities,
                 symbolic=symbols is not None)


__all__ = ["INWARD_QUANTITIES", "OUTWARD_QUANTITIES", "Trace", "trace"]
