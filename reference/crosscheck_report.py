"""A cross-engine check as text, as a JSON-ready document and as one offline HTML page.

The page is built by :mod:`course_dynamics.output.page` (one stylesheet, no script, no request): it opens
from disk. Robot, joint and link names and the engines' messages come from URDFs and engines: they reach the
page only as text, which the page builder escapes.
"""
from __future__ import annotations

from course_dynamics.output import page

from .crosscheck import CONVENTIONS, TERM_TITLES, TERMS, CrossCheck, EngineCheck


def _number(x: float) -> str:
    return f"{x:.1e}"


def convention_size(convention: dict) -> str:
    """A convention's size as one line: per term its largest absolute amount, or what it concerns.

    Parameters
    ----------
    convention : dict
        ``{"name", "size", "detail"?}`` as :func:`~course_dynamics_reference.crosscheck.check_engine` gives it.

    Returns
    -------
    str
        For example ``tau 3.5e+00, M 1.5e+00`` or ``2 links held by fixed joints``.
    """
    size = convention["size"]
    if isinstance(size, dict):
        text = ", ".join(f"{TERM_TITLES[t]} {_number(v)}" for t, v in size.items() if v)
        text = text or "none at these states"
    else:
        text = str(size)
    return text + (f" ({convention['detail']})" if convention.get("detail") else "")


def _verdict(e: EngineCheck) -> str:
    if e.status == "skipped":
        return "skipped"
    if e.status == "refused":
        return "refused (explained)" if e.explained else "REFUSED"
    return "yes" if e.explained else "NO"


def _row(e: EngineCheck) -> list[str]:
    residual = [_number(e.residual[t]) if e.residual else "-" for t in TERMS]
    return [e.engine, e.version or "-", *residual, _verdict(e)]


def summary(check: CrossCheck) -> str:
    """The last line of the text: whether every engine agrees once the conventions are applied.

    Parameters
    ----------
    check : CrossCheck
        The comparison.

    Returns
    -------
    str
        One sentence; it starts ``NO ENGINE COMPARED`` when every engine was skipped or refused.
    """
    if not check.compared:
        return "NO ENGINE COMPARED: " + ", ".join(f"{e.engine} {e.status}" for e in check.engines) + " (see the notes)"
    if check.ok:
        return "every engine agrees with course_dynamics once the named conventions are applied"
    parted = [e.engine + (f" (first at link {e.first_link}, joint {e.first_joint})" if e.first_link else "")
              for e in check.engines if not e.explained]
    return "UNEXPLAINED DIFFERENCE: " + ", ".join(parted)


def crosscheck_text(check: CrossCheck) -> str:
    """The report as the command prints it.

    Parameters
    ----------
    check : CrossCheck
        The comparison.

    Returns
    -------
    str
        Lines ending in a newline: the table of residuals, the conventions with their sizes, the notes.
    """
    lines = [f"{check.robot}: course_dynamics against each engine at {check.samples} seeded states "
             f"(seed {check.seed}); largest relative difference once the conventions are applied, tolerance "
             f"{check.tolerance:g}",
             f"{'engine':<10} {'version':<8} " + " ".join(f"{TERM_TITLES[t]:>8}" for t in TERMS) + "  agrees"]
    for e in check.engines:
        row = _row(e)
        lines.append(f"{row[0]:<10} {row[1]:<8} " + " ".join(f"{v:>8}" for v in row[2:-1]) + f"  {row[-1]}")
    conventions = [(e.engine, c) for e in check.engines for c in e.conventions]
    if conventions:
        lines.append("conventions (size: the largest absolute amount each accounts for, per term):")
        lines += [f"  {engine:<10} {c['name']}: {convention_size(c)}" for engine, c in conventions]
    notes = [(e.engine, n) for e in check.engines for n in e.notes]
    notes += [(e.engine, f"refused: {e.reason}") for e in check.engines if e.status == "refused" and not e.explained]
    if notes:
        lines.append("notes:")
        lines += [f"  {engine:<10} {n}" for engine, n in notes]
    lines.append(summary(check))
    return "\n".join(lines) + "\n"


def crosscheck_document(check: CrossCheck) -> dict:
    """The report as ``--json`` prints it.

    Parameters
    ----------
    check : CrossCheck
        The comparison.

    Returns
    -------
    dict
        ``robot, urdf, joints, samples, seed, tolerance, ok, conventions`` (name → what it is) and ``engines``
        (each ``engine, status, version, reason, calls, raw, residual, conventions, notes, first_link,
        first_joint, explained``).
    """
    return check.as_dict()


def crosscheck_html(check: CrossCheck) -> str:
    """The report as one offline page.

    Parameters
    ----------
    check : CrossCheck
        The comparison.

    Returns
    -------
    str
        A whole HTML document.
    """
    title = f"{check.robot}: one URDF in four engines"
    parts = [page.heading(title),
             page.paragraph(f"τ, M, G, the bias forces and the forward dynamics of {check.robot} "
                            f"({len(check.joints)} joints: {', '.join(check.joints)}) by course_dynamics and by each "
                            f"engine through its own API, at {check.samples} seeded states (seed {check.seed}). "
                            "The table gives the largest relative difference from course_dynamics once the named "
                            f"conventions are applied; the tolerance is {check.tolerance:g}.")]
    header = ("engine", "version", *[TERM_TITLES[t] for t in TERMS], "agrees")
    parts.append(page.table([_row(e) for e in check.engines], header=header, css="numbers"))
    raw = [[e.engine, *[_number(e.raw[t]) for t in TERMS]] for e in check.engines if e.raw]
    if raw:
        parts.append(page.section("Before the conventions", page.paragraph(
            "The same differences as each engine gives them, nothing undone:"),
            page.table(raw, header=("engine", *[TERM_TITLES[t] for t in TERMS]), css="numbers")))
    rows = [(e.engine, c["name"], convention_size(c)) for e in check.engines for c in e.conventions]
    if rows:
        parts.append(page.section("Conventions", page.paragraph(
            "Size: the largest absolute amount each accounts for, per term, in the term's units."),
            page.table(rows, header=("engine", "convention", "size"))))
    notes = [f"{e.engine}: {n}" for e in check.engines for n in e.notes]
    notes += [f"{e.engine} refused the model: {e.reason}" for e in check.engines
              if e.status == "refused" and not e.explained]
    if notes:
        parts.append(page.section("Notes", page.bullet_list(notes)))
    calls = [(e.engine, *[e.calls.get(t, "") for t in TERMS]) for e in check.engines if e.calls]
    if calls:
        parts.append(page.section("What was called", page.table(calls, header=("engine", *TERMS))))
    parts.append(page.section("The named conventions", page.table(sorted(CONVENTIONS.items()),
                                                                  header=("convention", "what it is"))))
    parts.append(page.paragraph(summary(check)))
    return page.page(title, parts)


__all__ = ["convention_size", "crosscheck_document", "crosscheck_html", "crosscheck_text", "summary"]
