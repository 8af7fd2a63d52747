"""The results document a submission's process sends back, read as hostile input.

The harness writes it, but the harness runs next to student code, so the
student can write anything to the same channel instead: a document nested
200 000 deep, integers of 400 digits, 64 MiB of empty objects, a status that
is a spreadsheet formula. :func:`read_results` bounds the document's size
before parsing (:func:`results_cap`, from the plan: what a correct answer can
take, with room for error messages), parses it with bounded integers, and
checks its whole shape and every number before the grader uses any of it.
Anything unexpected is :class:`InvalidResults` for that student alone, whose
status becomes ``invalid result``.

Shape (as :mod:`~course_dynamics.grading.harness` writes it)::

    {"status": one of STATUSES, "message": str, "defined": [names], "forbidden_attempts": [names],
     "results": {name: [{"value": nested floats, "shape": [ints]} or {"error": str}, one per call]}}
"""
from __future__ import annotations

import hashlib
import hmac
import json

import numpy as np

from ..base.errors import CourseDynamicsError
from .harness import FUNCTIONS, MAX_DIMENSIONS, MAX_VALUES, STATUSES
from .integrity import FLAGS, MAX_FLAG_DETAIL, MAX_FLAG_LINES, first_key, next_key, tag

MAX_TEXT = 2000            # characters of a message or an error
MAX_NAMES = 100            # forbidden import attempts listed
MAX_DIGITS = 18            # an integer in the document (a shape, a returned int) has at most this many digits
BYTES_PER_VALUE = 32       # a float's repr with its separator
BYTES_PER_RECORD = 2 * MAX_TEXT + 256
#: The most bytes of the integrity channel read (every flag code's lines, and the closing line).
FLAGS_BYTES = (len(FLAGS) * MAX_FLAG_LINES + 2) * (4 * MAX_FLAG_DETAIL + 64)  # the integrity channel, read at most
KEY_WINDOW = 8  # a tagged line may come this many keys ahead (a line lost, two threads' lines crossed)
MAX_FOREIGN = 1000  # lines that are not the hook's, checked at most (one is enough to say so)


class InvalidResults(CourseDynamicsError):
    """A results document that is not what the harness writes (the message says what is wrong)."""


def results_cap(plan: dict) -> int:
    """Bytes a results document for ``plan`` may take: every call answered with an n×n array or an error.

    Parameters
    ----------
    plan : dict
        The harness's plan: ``functions``, per function its argument lists.

    Returns
    -------
    int
        The cap, bytes.
    """
    total = 4 * MAX_TEXT + MAX_NAMES * 256 + 4096
    for calls in plan.get("functions", {}).values():
        for arguments in calls:
            n = len(arguments[0]) if arguments else 1
            total += BYTES_PER_VALUE * n * n + BYTES_PER_RECORD
    return total


def _integer(text: str) -> int:
    if len(text.lstrip("-")) > MAX_DIGITS:
        raise InvalidResults(f"an integer of {len(text)} digits")
    return int(text)


def _constant(name: str) -> float:
    return float(name)  # NaN, Infinity, -Infinity: what a student's function may return


def _text(value, what: str) -> str:
    if not isinstance(value, str) or len(value) > MAX_TEXT:
        raise InvalidResults(f"{what} is not a text of at most {MAX_TEXT} characters")
    return value


def _names(value, what: str, allowed=None) -> list[str]:
    if not isinstance(value, list) or len(value) > MAX_NAMES:
        raise InvalidResults(f"{what} is not a list of at most {MAX_NAMES} names")
    for name in value:
        if not isinstance(name, str) or len(name) > 200 or (allowed is not None and name not in allowed):
            raise InvalidResults(f"{what} holds something other than a name")
    return list(dict.fromkeys(value))


def _numbers(value, depth: int = 0) -> int:
    """How many numbers a nested list holds (at most MAX_VALUES); InvalidResults for anything else."""
    if isinstance(value, bool):
        raise InvalidResults("a returned value holds true/false, not a number")
    if isinstance(value, (int, float)):
        return 1
    if not isinstance(value, list) or depth > MAX_DIMENSIONS:
        raise InvalidResults(f"a returned value is not a nested list of numbers of depth at most {MAX_DIMENSIONS}")
    count = 0
    for item in value:
        count += _numbers(item, depth + 1)
        if count > MAX_VALUES:
            raise InvalidResults(f"a returned value holds more than {MAX_VALUES} numbers")
    return count


def _record(record) -> dict:
    if not isinstance(record, dict):
        raise InvalidResults("a result is not a record")
    if set(record) == {"error"}:
        return {"error": _text(record["error"], "an error")}
    if set(record) != {"value", "shape"}:
        raise InvalidResults(f"a result has the fields {sorted(map(str, record))[:5]}")
    _numbers(record["value"])
    shape = record["shape"]
    if not isinstance(shape, list) or len(shape) > MAX_DIMENSIONS or \
            not all(type(s) is int and 0 <= s <= MAX_VALUES for s in shape):
        raise InvalidResults(f"a result's shape is not a list of at most {MAX_DIMENSIONS} sizes")
    try:
        array = np.array(record["value"], dtype=float)
    except (ValueError, OverflowError):
        raise InvalidResults("a returned value is ragged or out of range") from None
    if list(array.shape) != shape:
        raise InvalidResults(f"a returned value has shape {list(array.shape)}, its record says {shape}")
    return {"value": array.tolist(), "shape": shape}


def read_results(data: bytes, plan: dict) -> dict:
    """The checked document (module docstring) from the raw bytes; InvalidResults for anything else.

    Parameters
    ----------
    data : bytes
        What came back on the results channel.
    plan : dict
        The harness's plan the document answers.

    Returns
    -------
    dict
        The document, checked: ``status``, ``message``, ``defined``, ``forbidden_attempts`` and ``results``.

    Raises
    ------
    InvalidResults
        If the document is larger than :func:`results_cap`, not JSON of a bounded depth, or not of the shape the
        harness writes (any field, name, record, number or shape).
    """
    cap = results_cap(plan)
    if len(data) > cap:
        raise InvalidResults(f"the results document has more than {cap} bytes")
    try:
        document = json.loads(data.decode("utf-8"), parse_int=_integer, parse_constant=_constant)
    except InvalidResults:
        raise
    except (ValueError, RecursionError, MemoryError):
        raise InvalidResults("the results document is not valid JSON of a reasonable depth") from None
    if not isinstance(document, dict):
        raise InvalidResults("the results document is not a JSON object")
    unknown = set(document) - {"status", "message", "defined", "forbidden_attempts", "results"}
    if unknown:
        raise InvalidResults(f"the results document has unknown fields {sorted(unknown)[:5]}")
    status = document.get("status")
    if status not in STATUSES:
        raise InvalidResults("the results document's status is not one the harness writes")
    checked = {"status": status, "message": _text(document.get("message", ""), "the message"),
               "defined": _names(document.get("defined", []), "defined", FUNCTIONS),
               "forbidden_attempts": _names(document.get("forbidden_attempts", []), "forbidden_attempts"),
               "results": {}}
    results = document.get("results", {})
    functions = plan.get("functions", {})
    if not isinstance(results, dict) or not set(results) <= set(functions):
        raise InvalidResults("the results are not a record of the functions asked for")
    for name, records in results.items():
        if not isinstance(records, list) or len(records) != len(functions[name]):
            raise InvalidResults(f"the results of {name} are not one record per call")
        checked["results"][name] = [_record(r) for r in records]
    return checked


def read_flags(data: bytes, nonce: str, results: bytes | None) -> list[tuple[str, str]]:
    """The integrity flags from the channel's raw bytes (integrity.integrity_hook), as ``(code, detail)`` once each.

    The channel is hostile input like the results: a line counts only when its tag is the HMAC of its text under one
    of the next keys from the nonce (integrity.first_key, each key used once), so a line the submission wrote is
    never a flag but the flag ``channel-closed``, as are unknown codes and anything after the closing line. At most
    MAX_FLAG_LINES are kept per code. ``results`` are the results document's bytes (None: none came back, and the
    status says what happened); a channel whose closing line (``end<TAB>digest``) does not hold their SHA-256 is
    ``channel-closed`` too: the hook withheld it (it saw tampering), or was switched off, or the line was forged early.

    Parameters
    ----------
    data : bytes
        What came back on the integrity channel.
    nonce : str
        The run's secret, which the keys come from.
    results : bytes or None
        The results document's bytes, None when none came back.

    Returns
    -------
    list of tuple of (str, str)
        The flags (code, detail), each once, in the order they came.
    """
    flags, closed, counts, foreign = [], False, dict.fromkeys(FLAGS, 0), 0
    keys, used = [first_key(nonce)] if nonce else [], set()
    digest = hashlib.sha256(results).hexdigest() if results is not None else None
    for line in data[:FLAGS_BYTES].split(b"\n"):
        if not line:
            continue  # the hook starts every line on a line of its own
        body, tab, mark = line.rpartition(b"\t")
        index = None
        if not closed and tab and len(mark) == len(tag(b"", b"")) and foreign < MAX_FOREIGN:
            while keys and len(keys) < (max(used) + 1 if used else 0) + KEY_WINDOW:
                keys.append(next_key(keys[-1]))
            index = next((i for i, key in enumerate(keys)
                          if i not in used and hmac.compare_digest(tag(key, body), mark)),
                         None)
        if index is None:
            foreign += 1  # nothing the hook wrote: the submission wrote on the channel
            continue
        used.add(index)
        code, _, detail = body.decode("utf-8", "replace").partition("\t")
        if code == "end":
            closed = detail == digest
            foreign += not closed
        elif code in FLAGS and code != "channel-closed":
            if counts[code] < MAX_FLAG_LINES:
                counts[code] += 1
                detail = "".join(c if c.isprintable() else f"\\x{ord(c):02x}" for c in " ".join(detail.split()))
                flags.append((code, detail[:MAX_FLAG_DETAIL]))
        else:
            foreign += 1
    if results is not None and not closed:
        flags.append(("channel-closed", ""))
    elif results is not None and (foreign or len(data) > FLAGS_BYTES):
        flags.append(("channel-closed", "written to by the submission"))
    return list(dict.fromkeys(flags))


__all__ = ["FLAGS_BYTES", "InvalidResults", "read_flags", "read_results", "results_cap"]
