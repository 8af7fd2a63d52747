"""The Newton–Euler iterations kept step by step, as the notes' worked example lays them out.

:func:`trace` evaluates the outward iteration (6.45)–(6.50) and the inward
iteration (6.51)–(6.53) once and keeps, for every link, ⁱωᵢ, ⁱω̇ᵢ, ⁱv̇ᵢ, ⁱv̇_Cᵢ,
ⁱFᵢ, ⁱNᵢ, ⁱfᵢ, ⁱnᵢ and τᵢ (each vector in its own link's frame), numeric or
symbolic. :mod:`course_dynamics.output.render` turns a :class:`Trace` into a text
table, LaTeX or a JSON record.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..core.model import Model
from ..core.newton_euler import newton_euler_links
from ..core.symbolic import (
    SymbolError,
    check_symbolic_size,
    decimal,
    joint_symbols,
    symbolic_model,
    tidy,
)

OUTWARD_QUANTITIES = ("omega", "omega_dot", "v_dot", "v_dot_c", "F", "N")  # (6.45)–(6.50)
INWARD_QUANTITIES = ("f", "n")  # (6.51)–(6.52)


@dataclass(frozen=True)
class Trace:
    """Per-link quantities of one Newton–Euler evaluation; ``values[key][i]`` is link i's vector."""

    model_name: str
    joints: tuple[str, ...]
    links: tuple[str, ...]
    prismatic: tuple[bool, ...]
    values: dict
    tau: list
    symbolic: bool


def trace(model: Model, q, qd, qdd, symbols=None, decimals: int | None = None) -> Trace:
    """Run both iterations and keep every intermediate quantity.

    ``symbols`` = None gives numbers at the state (q, qd, qdd). Otherwise the
    trace is symbolic: joint variables are the symbols q_<joint>, qd_<joint>,
    qdd_<joint> (q, qd, qdd are ignored), ``symbols`` names the parameters kept
    symbolic (see :mod:`course_dynamics.core.symbolic`), and entries are simplified
    (with the model's numbers as ``decimals``-digit decimals if given).
    """
    keys = OUTWARD_QUANTITIES + INWARD_QUANTITIES
    if decimals is not None and not (isinstance(decimals, int) and 1 <= decimals <= 30):

        raise SymbolError(f"decimals must be a whole number of digits from 1 to 30, got {decimals!r}")
    if symbols is None:
        links = newton_euler_links(model, q, qd, qdd)
        values = {key: getattr(links, key).tolist() for key in keys}
        tau = links.tau.tolist()
    else:

        check_symbolic_size(model)
        exact, _ = symbolic_model(model, symbols)
        q_s, qd_s, qdd_s = joint_symbols(model)
        links = newton_euler_links(exact, q_s, qd_s, qdd_s)

        def form(x):
            return decimal(tidy(x, q_s), decimals)

        values = {key: [[form(x) for x in row] for row in getattr(links, key)] for key in keys}
        tau = [form(x) for x in links.tau]
    return Trace(model_name=model.name, joints=model.joint_names, links=tuple(b.name for b in model.bodies),
                 prismatic=tuple(b.is_prismatic for b in model.bodies), values=values, tau=tau, symbolic=symbols is not None)


__all__ = ["INWARD_QUANTITIES", "OUTWARD_QUANTITIES", "Trace", "trace"]
