"""Near-identical submissions: a lead for the instructor, never a verdict.

Each submission is parsed (never run) and read as a stream of tokens from its
syntax tree, in source order: the kinds of node and operator, attribute names
(``np.cos``), numbers, and one placeholder for every name a student chooses
(variables, functions, arguments); imported and built-in names stay what they
are (``cos`` is not ``log``). Comments, docstrings, ``pass``, blank lines and
formatting never reach the tree, and renaming changes nothing. Every run of
:data:`GRAM` tokens within one top-level statement is a fingerprint (so the
order of the functions does not matter); what the starter code gives everyone is
removed from every submission's fingerprints first. Two submissions score by
the share of the smaller one's fingerprints that the other holds too (1.0: the
smaller is contained in the other), and a pair is listed when the score reaches
the threshold and the smaller has at least :data:`MIN_GRAMS` fingerprints of
its own. Independent implementations of one algorithm share short runs, not
long ones: :data:`GRAM` is long enough that they score low (see the tests).

A function of a math module is one token however it is spelled (``np.sin``, ``numpy.sin``,
``math.sin``, ``sin`` imported from either): a closed form pasted with another prefix is
the same code.

Each submission is also compared with what the package itself writes for the student's
robot (:func:`generated_code`: ``derive``'s closed forms, whose JSON, Markdown and LaTeX
formats hold the same expressions, written out as Python with the joint variables as names
and as indices, for robots of at most :data:`GENERATED_JOINTS` joints; and the compiled
model's module, :mod:`course_dynamics.core.compiled`). A submission whose own fingerprints
the generated code holds at the threshold's share is a pair with it (:func:`generated_pairs`)
and carries the ``generated-code`` flag.

=========================  ======================================================
name                       meaning
=========================  ======================================================
:class:`Comparison`        the pairs of a class, with the threshold and the starter
:class:`Fingerprints`      one submission's fingerprints and the lines each covers
:func:`fingerprints`       a submission's source to its fingerprints
:func:`similar_pairs`      every pair at or above the threshold, highest first
:func:`generated_code`     the Python the package writes for a robot
:func:`generated_pairs`    each submission that is mostly generated code, with it
=========================  ======================================================
"""
from __future__ import annotations

import ast
import hashlib
import itertools
import re
from dataclasses import dataclass, field
from pathlib import Path

from ..base.errors import InputError
from ..base.files import read_small
from ..core.compiled import model_key
from ..core.compiled.codegen import module_source
from ..core.compiled.tracing import trace_programs
from ..core.model import Model
from ..core.symbolic import derive
from ..output.render import derivation_record
from .uploads import parse_python

#: Tokens per fingerprint.
GRAM = 16
#: The fewest fingerprints of its own (beyond the starter's) a submission needs to be listed in a pair.
MIN_GRAMS = 30
#: The default score at which a pair is listed.
THRESHOLD = 0.8
#: The class size from which a fingerprint most submissions hold is common ground and counts for no pair.
COMMON_CLASS = 10
MAX_TOKENS = 200_000  # tokens read of one file (a dynamics answer has a few thousand)
MAX_STARTER_BYTES = 1_000_000  # as a submission may have
CONTEXTS = (ast.Load, ast.Store, ast.Del)
MATH_MODULES = ("numpy", "math", "cmath", "sympy")  # np.sin, math.sin and a bare sin are one token
#: The most joints of a robot whose ``derive`` closed forms are compared (a 3-joint arm takes minutes to derive).
GENERATED_JOINTS = 2
#: The name of generated code in a pair, before what generated it.
GENERATED = "generated:"


@dataclass(frozen=True)
class Fingerprints:
    """A submission's fingerprints: hash -> the source lines (first, last) its tokens span.

    Parameters
    ----------
    student : str
        Whose submission it is.
    source : str
        Its source.
    grams : dict of int to tuple of (int, int)
        Per fingerprint's hash, the first and last source lines its tokens span.
    """

    student: str
    source: str
    grams: dict[int, tuple[int, int]] = field(default_factory=dict)


@dataclass(frozen=True)
class Comparison:
    """A class compared: the pairs listed, the threshold they reached, the starter file's name (or None).

    Parameters
    ----------
    pairs : tuple of Pair
        The pairs listed, highest score first.
    threshold : float
        The score they reached.
    starter : str or None
        The starter file's name, None when there was none.
    """

    pairs: tuple
    threshold: float
    starter: str | None = None


@dataclass(frozen=True)
class Pair:
    """Two submissions and their score (the share of the smaller one's fingerprints the other holds).

    Parameters
    ----------
    first, second : Fingerprints
        The two submissions.
    score : float
        The share of the smaller one's own fingerprints that the other holds, 0 to 1.
    shared : frozenset of int
        The fingerprints both hold, less the common ground.
    """

    first: Fingerprints
    second: Fingerprints
    score: float
    shared: frozenset[int]

    def lines(self, which: Fingerprints) -> set[int]:
        """The source lines of ``which`` that the shared fingerprints cover.

        Parameters
        ----------
        which : Fingerprints
            One of the pair.

        Returns
        -------
        set of int
            Its line numbers, from 1.
        """
        covered = set()
        for gram in self.shared:
            first, last = which.grams[gram]
            covered.update(range(first, last + 1))
        return covered


def _is_docstring(node: ast.AST) -> bool:
    return isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str)


def _own_names(tree: ast.AST) -> tuple[set[str], dict[str, str]]:
    """The names the file binds itself (variables, functions, arguments), and what each imported name stands for."""
    own, imported = set(), {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and isinstance(node.ctx, (ast.Store, ast.Del)):
            own.add(node.id)
        elif isinstance(node, ast.arg):
            own.add(node.arg)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            own.add(node.name)
        elif isinstance(node, ast.alias):
            imported[node.asname or node.name.split(".")[0]] = node.name
    return own - set(imported), imported


def _constant(value) -> str:
    if isinstance(value, (str, bytes)):
        return "str"
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**30:
        return "int"  # a huge literal has no repr worth comparing (and may have none at all)
    return repr(value)[:40]


def _tokens(node: ast.AST, own: set[str], imported: dict[str, str]):
    """(token, line) in source order, depth first without recursion (a file may nest deeply): the names the
    student chose are one placeholder, imported and built-in names are themselves, ``pass`` is nothing."""
    stack = [(node, 1)]
    while stack:
        node, line = stack.pop()
        if isinstance(node, (*CONTEXTS, ast.Pass)) or _is_docstring(node):
            continue
        line = getattr(node, "lineno", line)
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
                and imported.get(node.value.id, "").split(".")[0] in MATH_MODULES:
            yield "Name", line  # np.sin as a bare sin
            yield node.attr, line
            continue
        yield type(node).__name__, line
        if isinstance(node, ast.Name):
            yield ("name" if node.id in own else imported.get(node.id, node.id)), line
        elif isinstance(node, ast.Attribute):
            yield "." + node.attr, line
        elif isinstance(node, ast.Constant):
            yield _constant(node.value), line
        elif isinstance(node, ast.alias):
            yield node.name, line  # what is imported (numpy), not what it is called
        stack.extend((child, line) for child in reversed(list(ast.iter_child_nodes(node))))


def _hash(tokens) -> int:
    return int.from_bytes(hashlib.blake2b("\x00".join(tokens).encode(), digest_size=8).digest(), "big")


def _grams(source: str, where: str) -> dict[int, tuple[int, int]]:
    try:
        tree = parse_python(source, where)
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return {}  # nothing to compare: the grader reports the file itself
    grams, own, imported, budget = {}, *_own_names(tree), MAX_TOKENS
    for statement in tree.body:  # windows stay inside one top-level statement: reordering functions changes nothing
        stream = list(itertools.islice(_tokens(statement, own, imported), budget))
        budget -= len(stream)
        for start in range(max(1, len(stream) - GRAM + 1)):
            window = stream[start:start + GRAM]
            if window:
                grams.setdefault(_hash(t for t, _ in window), (window[0][1], max(line for _, line in window)))
    return grams


def fingerprints(student: str, source: str, starter: Fingerprints | None = None) -> Fingerprints:
    """``source``'s fingerprints, less those of ``starter`` (the code every student was given).

    Parameters
    ----------
    student : str
        Whose submission it is.
    source : str
        Its source; one that does not parse has no fingerprints.
    starter : Fingerprints or None
        The starter code's fingerprints.

    Returns
    -------
    Fingerprints
        The fingerprints.
    """
    grams = _grams(source, student)
    if starter is not None:
        grams = {g: lines for g, lines in grams.items() if g not in starter.grams}
    return Fingerprints(student, source, grams)


def read_starter(path) -> Fingerprints:
    """The starter file's fingerprints; InputError when it cannot be read (as a regular file of at most 1 MB) or
    parsed.

    Parameters
    ----------
    path : str or os.PathLike
        The starter file.

    Returns
    -------
    Fingerprints
        Its fingerprints.

    Raises
    ------
    InputError
        If the file is missing, not a regular UTF-8 file of at most 1 MB, or not Python.
    """
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such starter file")
    try:
        source = read_small(path, MAX_STARTER_BYTES, "starter file").decode("utf-8")
        parse_python(source, str(path))
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: cannot read the starter file: {exc}") from None
    except SyntaxError as exc:
        raise InputError(f"{path}: the starter file is not Python: {exc.msg} (line {exc.lineno})") from None
    return fingerprints("starter", source)


def similar_pairs(submissions: list[Fingerprints], threshold: float = THRESHOLD) -> list[Pair]:
    """Every pair scoring at least ``threshold``, highest first.

    In a class of at least :data:`COMMON_CLASS`, a fingerprint that more than half the submissions hold is common
    ground, like the starter's, and counts for no pair. Only pairs that share a fingerprint are compared.

    Parameters
    ----------
    submissions : list of Fingerprints
        The class's submissions.
    threshold : float
        The score from which a pair is listed, 0 to 1.

    Returns
    -------
    list of Pair
        The pairs, highest score first.
    """
    owners: dict[int, list[int]] = {}
    for index, submission in enumerate(submissions):
        for gram in submission.grams:
            owners.setdefault(gram, []).append(index)
    common = {g for g, holders in owners.items()
              if len(submissions) >= COMMON_CLASS and len(holders) > len(submissions) / 2}
    own = [len(s.grams.keys() - common) for s in submissions]
    counts: dict[tuple[int, int], int] = {}
    for gram, holders in owners.items():
        if gram not in common:
            for a in range(len(holders)):
                for b in range(a + 1, len(holders)):
                    counts[holders[a], holders[b]] = counts.get((holders[a], holders[b]), 0) + 1
    pairs = []
    for (a, b), count in counts.items():
        smaller = min(own[a], own[b])
        if smaller >= MIN_GRAMS and count / smaller >= threshold:
            first, second = submissions[a], submissions[b]
            pairs.append(Pair(first, second, count / smaller,
                              frozenset(first.grams.keys() & second.grams.keys() - common)))
    return sorted(pairs, key=lambda p: (-p.score, p.first.student, p.second.student))


def _closed_form_module(record: dict, n: int, indices: bool) -> str:
    """derive's closed forms (its JSON record) as one Python function per term, the joint variables as names or
    as indices (q[0])."""
    joints = record["joints"]
    names = {f"{kind}_{joint}": f"{kind}[{j}]" for j, joint in enumerate(joints) for kind in ("q", "qd", "qdd")}
    pattern = re.compile(r"\b(" + "|".join(sorted(map(re.escape, names), key=len, reverse=True)) + r")\b")

    def text(expression: str) -> str:
        return pattern.sub(lambda m: names[m.group(1)], expression) if indices else expression

    def rows(value) -> str:
        return "[" + ", ".join(rows(v) if isinstance(v, list) else text(v) for v in value) + "]"

    lines = ["from math import cos, sin", ""]
    for term, arguments in (("tau", "q, qd, qdd"), ("M", "q"), ("V", "q, qd"), ("G", "q"), ("C", "q, qd")):
        lines.append(f"def {term}({arguments}):")
        if not indices:
            for kind in arguments.split(", "):
                lines.append(f"    {', '.join(f'{kind}_{joint}' for joint in joints)}{',' if n == 1 else ''} = {kind}")
        lines += [f"    return {rows(record[term])}", ""]
    return "\n".join(lines)


def generated_code(model: Model) -> dict[str, str]:
    """What the package writes for ``model`` (module docstring), as Python sources by what wrote them.

    Parameters
    ----------
    model : Model
        The student's robot.

    Returns
    -------
    dict of str to str
        Per generator (``"compiled model"``, ``"derive (joint names)"``, ``"derive (indices)"``), its source.
    """
    sources = {"compiled model": module_source(model, trace_programs(model), model_key(model))}
    if model.n <= GENERATED_JOINTS:
        record = derivation_record(derive(model))
        for label, indices in (("joint names", False), ("indices", True)):
            sources[f"derive ({label})"] = _closed_form_module(record, model.n, indices)
    return sources


def generated_pairs(submissions: list[Fingerprints], robots: dict[str, Model], threshold: float = THRESHOLD) -> list:
    """Each submission whose own fingerprints the code generated for its robot holds at ``threshold``'s share, as a
    pair with the closest generated source (named ``generated: <what wrote it>``).

    Parameters
    ----------
    submissions : list of Fingerprints
        The class's submissions (less the starter).
    robots : dict of str to Model
        Each student's robot.
    threshold : float
        The share from which a submission is listed, 0 to 1.

    Returns
    -------
    list of Pair
        The submission first, the generated code second; highest score first.
    """
    generated: dict[str, list[Fingerprints]] = {}
    pairs = []
    for submission in submissions:
        model = robots[submission.student]
        key = model_key(model)
        if key not in generated:
            generated[key] = [fingerprints(f"{GENERATED} {label}", source)
                              for label, source in generated_code(model).items()]
        if len(submission.grams) < MIN_GRAMS:
            continue
        best = max(generated[key], key=lambda g: len(submission.grams.keys() & g.grams.keys()))
        shared = frozenset(submission.grams.keys() & best.grams.keys())
        if len(shared) / len(submission.grams) >= threshold:
            pairs.append(Pair(submission, best, len(shared) / len(submission.grams), shared))
    return sorted(pairs, key=lambda p: (-p.score, p.first.student))


__all__ = ["COMMON_CLASS", "GENERATED", "GENERATED_JOINTS", "GRAM", "MIN_GRAMS", "THRESHOLD", "Comparison",
           "Fingerprints", "Pair", "fingerprints", "generated_code", "generated_pairs", "read_starter",
           "similar_pairs"]
