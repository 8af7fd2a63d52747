"""Logs on an even clock: dropped samples filled, a log resampled, long gaps split, never interpolated silently.

==================  =============  ===================================================
code                symbol         meaning (shape, unit)
==================  =============  ===================================================
``t``               t              sample times as logged (K,), s
``dt``              Δt             the log's sample period: the median step, s
``columns``                        our columns (``q_<joint>``, ``qd_<joint>``, …), each (K,)
``segments``                       (start, stop) row ranges of the evenly sampled result
==================  =============  ===================================================

Differentiating a log (a Savitzky–Golay filter) needs even steps. Real recorders drop
samples (RTDE drops packets under load), so :func:`even_clock`:

* leaves a log alone whose every step is Δt (within :data:`JITTER`);
* fills *isolated drops* — a step of k·Δt, k ≤ :data:`MAX_FILLED_PERIODS` — with the k − 1
  missing samples, each column interpolated by a cubic spline through the log's own samples
  (positions and rates are smooth; a cubic keeps their second derivative continuous, where
  straight lines would put a spike in Θ̈ at every filled sample), and says in a note how many
  samples were filled and the largest gap;
* splits at a longer gap when asked (``split_gaps``): the pieces are then separate segments, each
  differentiated on its own (a rate is never differentiated across a gap);
* with ``resample`` (Hz) puts every column on an even clock at that rate by the same cubic
  splines (no gap check then beyond the long-gap rule), and says so;
* with ``repair``, does all a real log needs at once: resamples on the median period when the steps are not
  whole periods (a log on one clock, drops and all, is left exactly as without it), splits at long gaps, and
  drops the segments too short to differentiate (a lone sample between two gaps; fewer than ``min_rows``),
  with a note for each. With ``resample`` too, the rate given wins. Nothing is ever sorted: t must increase.

Without ``repair``, a log that the options leave off one clock is refused in *one* message that names every
problem — the jittering steps, each long gap, each segment too short — and what ``repair`` would do about
each: a log is never mended one error at a time.

>>> import numpy as np
>>> t = np.array([0.0, 0.01, 0.02, 0.04, 0.05, 0.06])                # the sample at 0.03 s was dropped
>>> result = even_clock(t, {"q_a": t**2})
>>> np.round(result.t, 3).tolist()
[0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06]
>>> result.notes[0]
'filled 1 dropped sample (1 gap; the largest 2 periods long, at t = 0.02 s)'
>>> t = np.array([0.0, 0.011, 0.019, 0.03, 0.5, 0.9, 0.91, 0.919, 0.93])   # jitter, two gaps, a lone sample
>>> try:
...     even_clock(t, {"q_a": t**2})
... except InputError as error:
...     print(error)                                                             # doctest: +NORMALIZE_WHITESPACE
the log: the samples are not on one clock (median step 11 ms, steps from 8 ms to 11 ms; 2 not a whole
number of periods, the first before row 3) and it has 2 gaps longer than 5 sample periods (470 ms = 42.7 periods
after t = 0.03 s, before row 5; 400 ms = 36.4 periods after t = 0.5 s, before row 6) and 1 lone sample cut off by
the gaps (row 5, t = 0.5 s, between two gaps): --repair resamples on the median period, splits at the gaps and
drops the lone sample
>>> repaired = even_clock(t, {"q_a": t**2}, repair=True)
>>> repaired.segments                                 # 3 rows each, 11 ms apart: the lone sample at 0.5 s dropped
((0, 3), (3, 6))
>>> repaired.notes[1]
'split at 2 long gaps (after t = 0.03 s, 0.5 s) into 3 segments, each differentiated on its own'
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError

#: A step within this share of Δt is Δt; of k Δt, within it of Δt, is k periods.
JITTER = 0.1               # a step within 10 % of Δt is Δt; of k Δt, within 10 % of Δt, is k periods
#: The longest gap filled, in periods (4 dropped samples in a row); a longer one is refused or split.
MAX_FILLED_PERIODS = 5     # a gap of up to 5 periods (4 dropped samples in a row) is filled
#: The fewest rows a segment has unless the caller needs more (differentiating takes five).
MIN_SEGMENT_ROWS = 2
#: The highest resampling rate, as a multiple of the log's own (above it samples are invented, not evened).
MAX_UPSAMPLING = 4.0       # resampling above 4x the log's own rate invents, rather than evens, samples


@dataclass(frozen=True)
class EvenLog:
    """Columns on an even clock: ``t`` (K',) s, ``columns`` our name → (K',), ``segments`` (start, stop) rows.

    Parameters
    ----------
    t : numpy.ndarray, shape (K',)
        Sample times on the even clock, s.
    columns : dict
        Our column name → values of shape (K',), in the log's units.
    step : float
        The clock's period Δt, s (0 for a log of fewer than two rows).
    segments : tuple of (int, int)
        The (start, stop) row ranges, each differentiated on its own.
    notes : tuple of str
        What was filled, resampled, split or dropped.
    filled : numpy.ndarray of bool, shape (K',), optional
        True where a sample was interpolated rather than logged; None after resampling.
    """

    t: np.ndarray
    columns: dict
    step: float
    segments: tuple[tuple[int, int], ...]
    notes: tuple[str, ...] = ()
    filled: np.ndarray | None = None   # (K',) True where a sample was interpolated rather than logged


def _spline(t: np.ndarray, y: np.ndarray, at: np.ndarray) -> np.ndarray:
    from scipy.interpolate import CubicSpline  # scipy's import takes 0.2 s: only logs with drops pay it

    if len(t) < 4:
        return np.interp(at, t, y)
    return CubicSpline(t, y, bc_type="not-a-knot")(at)


def _median_step(t: np.ndarray, where: str) -> float:
    steps = np.diff(t)
    dt = float(np.median(steps))
    if not dt > 0:
        raise InputError(f"{where}: the median time step is {dt:g} s; t must increase")
    return dt


def _seconds(x: float) -> str:
    return f"{x * 1e3:.3g} ms" if abs(x) < 1 else f"{x:.6g} s"


def _at(x: float, dt: float) -> str:
    """A time to a hundredth of a period or finer, however large (a stamp since the epoch keeps its milliseconds)."""
    digits = max(6, int(np.ceil(np.log10(max(abs(x), dt) / dt))) + 3)
    return f"{x:.{min(digits, 17)}g}"


def _listed(items: list[str], most: int = 3, sep: str = "; ") -> str:
    return sep.join(items[:most]) + (f"{sep}and {len(items) - most} more" if len(items) > most else "")


def _check_times(t: np.ndarray, where: str, line) -> None:
    """t finite and increasing, or an error naming the first row that is not: nothing is ever sorted."""
    bad = np.flatnonzero(~np.isfinite(t))
    if len(bad):
        raise InputError(f"{where}: {line(int(bad[0]))}: t = {t[bad[0]]} is not a finite time")
    back = np.flatnonzero(np.diff(t) <= 0)
    if len(back):
        row = int(back[0]) + 1
        raise InputError(f"{where}: {line(row)}: t = {t[row]:.9g} s does not come after {t[row - 1]:.9g} s (t must "
                         "increase; a log is never sorted)")


def _grid_rows(ts: np.ndarray, dt: float, resampling: bool) -> int:
    """How many rows the piece of times ``ts`` has on the even clock of period ``dt``."""
    if resampling:
        return int(np.floor((ts[-1] - ts[0]) / dt + 1e-9)) + 1
    return int(np.sum(np.rint(np.diff(ts) / dt))) + 1


def _pieces_named(t, pieces, short, line, dt) -> list[str]:
    """Each short piece by its rows and times, and where it lies among the gaps."""
    names = []
    for k in short:
        piece = pieces[k]
        rows = line(int(piece[0])) if len(piece) == 1 else f"{line(int(piece[0]))} to {line(int(piece[-1]))}"
        first, last = _at(t[piece[0]], dt), _at(t[piece[-1]], dt)
        span = f"t = {first} s" if len(piece) == 1 else f"t = {first} to {last} s"
        place = ("before the first gap" if k == 0 else "after the last gap" if k == len(pieces) - 1 else
                 "between two gaps")
        names.append(f"{rows}, {span}, {place}")
    return names


def _short_phrase(t, pieces, short, line, min_rows: int, dt: float) -> str:
    lone = all(len(pieces[k]) == 1 for k in short)
    what = (f"{len(short)} lone sample{'s' * (len(short) > 1)}" if lone else
            f"{len(short)} segment{'s' * (len(short) > 1)} too short to differentiate (fewer than {min_rows} rows)")
    return f"{what} cut off by the gaps ({_listed(_pieces_named(t, pieces, short, line, dt))})"


def _refusal(where, t, own, steps, off, gaps, periods, pieces, short, min_rows, line, resampling) -> str:
    """One line naming every clock problem the options leave, and what ``repair`` would do about each."""
    problems, actions = [], []
    if len(off) and not resampling:
        inside = steps[steps / own <= MAX_FILLED_PERIODS + JITTER]
        problems.append(f"the samples are not on one clock (median step {_seconds(own)}, steps from "
                        f"{_seconds(inside.min())} to {_seconds(inside.max())}; {len(off)} not a whole number of "
                        f"periods, the first before {line(int(off[0]) + 1)})")
        actions.append("resamples on the median period")
    if len(gaps):
        listed = [f"{_seconds(steps[r])} = {periods[r]:.1f} periods after t = {_at(t[r], own)} s, before "
                  f"{line(int(r) + 1)}" for r in gaps]
        problems.append(f"it has {len(gaps)} gap{'s' * (len(gaps) > 1)} longer than {MAX_FILLED_PERIODS} sample "
                        f"periods ({_listed(listed)})")
        actions.append("splits at the gaps")
    if short:
        problems.append(_short_phrase(t, pieces, short, line, min_rows, own))
        several = "s" * (len(short) > 1)
        lone = all(len(pieces[k]) == 1 for k in short)
        actions.append(f"drops the lone sample{several}" if lone else f"drops the segment{several} too short")
    hint = "--repair " + (", ".join(actions[:-1]) + " and " + actions[-1] if len(actions) > 1 else actions[0])
    if len(gaps) and not short and len(actions) == 1:
        hint += " (as --split-gaps does)"
    return f"{where}: " + " and ".join(problems) + f": {hint}"


def even_clock(t, columns: dict, *, resample: float | None = None, split_gaps: bool = False, repair: bool = False,
               min_rows: int = MIN_SEGMENT_ROWS, where: str = "the log", line=None) -> EvenLog:
    """``columns`` (our name → (K,) values at times ``t``) on an even clock (module docstring).

    ``line(row)`` names a logged row in messages (default ``row N``). Without ``repair``, a log the options leave
    off one clock is refused in one :class:`~course_dynamics.base.errors.InputError` naming every problem: steps
    that are no whole number of periods (unless ``resample``), gaps longer than :data:`MAX_FILLED_PERIODS`
    periods (unless ``split_gaps``), and the pieces between them too short to differentiate.

    Parameters
    ----------
    t : numpy.ndarray, shape (K,)
        Sample times as logged, s, increasing.
    columns : dict
        Our column name → values of shape (K,).
    resample : float, optional
        Put every column on an even clock at this rate, Hz (with ``repair`` too: the rate wins).
    split_gaps : bool
        Split at long gaps into segments instead of refusing them.
    repair : bool
        Resample on the median period where the steps are not whole periods (a log on one clock is left as it
        is), split at long gaps, and drop the segments shorter than ``min_rows``, each with a note.
    min_rows : int
        The fewest rows a segment needs (what differentiating it takes).
    where : str
        The log's name in messages.
    line : callable, optional
        ``line(row)`` names a logged row in messages.

    Returns
    -------
    EvenLog
        The columns on the even clock, its segments and the notes.

    Raises
    ------
    InputError
        t not finite or not increasing (naming the row); the clock problems above, all in one line; every segment
        too short (with ``repair``); a resampling rate not positive or above :data:`MAX_UPSAMPLING` times the
        log's own.
    """
    t = np.asarray(t, dtype=float)
    line = line or (lambda row: f"row {row + 1}")
    _check_times(t, where, line)
    if len(t) < 2:
        return EvenLog(t, dict(columns), 0.0, ((0, len(t)),))
    own = _median_step(t, where)
    if resample is not None:
        if not (np.isfinite(resample) and resample > 0):
            raise InputError(f"the resampling rate must be a positive number of Hz, got {resample:.6g}")
        if resample > MAX_UPSAMPLING / own:
            raise InputError(f"{where}: resampling at {resample:.6g} Hz a log recorded at about {1 / own:.6g} Hz "
                             f"would invent {resample * own:.3g} samples for each one logged (at most "
                             f"{MAX_UPSAMPLING:g}x its own rate)")
    steps = np.diff(t)
    on_own = steps / own
    off = np.flatnonzero((np.abs(on_own - np.rint(on_own)) > JITTER) & (on_own <= MAX_FILLED_PERIODS + JITTER))
    resampling = resample is not None or (repair and len(off) > 0)
    dt = 1.0 / float(resample) if resample is not None else own
    periods = steps / dt
    long_gaps = np.flatnonzero(periods > MAX_FILLED_PERIODS + JITTER)
    pieces = np.split(np.arange(len(t)), long_gaps + 1)
    rows = [_grid_rows(t[piece], dt, resampling) for piece in pieces]
    short = [k for k, count in enumerate(rows) if len(pieces) > 1 and count < min_rows]   # one piece: the filter says
    if (len(off) and not resampling) or (len(long_gaps) and not (split_gaps or repair)) or (short and not repair):
        raise InputError(_refusal(where, t, own, steps, [] if resampling else off,
                                  [] if split_gaps or repair else long_gaps, periods, pieces, short, min_rows, line,
                                  resampling))
    kept = [piece for k, piece in enumerate(pieces) if k not in short]
    if not kept:
        raise InputError(f"{where}: every segment between its {len(long_gaps)} long gaps is too short to "
                         f"differentiate (fewer than {min_rows} rows each): nothing is left to repair")
    grids, logged_parts, segments, start = [], [], [], 0
    for piece in kept:
        ts = t[piece]
        if resampling:
            grid = ts[0] + dt * np.arange(_grid_rows(ts, dt, True))
            logged = np.zeros(len(grid), dtype=bool)
        else:
            # each step is a whole number of periods (checked above); counting them step by step, not from the
            # first time, keeps a clock that drifts within the tolerance from putting two samples in one slot
            slots = np.concatenate([[0], np.cumsum(np.rint(np.diff(ts) / dt))]).astype(int)
            grid = np.interp(np.arange(int(slots[-1]) + 1), slots, ts)   # logged samples keep their own times
            logged = np.zeros(len(grid), dtype=bool)
            logged[slots] = True
        grids.append(grid)
        logged_parts.append(logged)
        segments.append((start, start + len(grid)))
        start += len(grid)
    new_t = np.concatenate(grids)
    logged = np.concatenate(logged_parts)
    out = {}
    for name, values in columns.items():
        values = np.asarray(values, dtype=float)
        parts = []
        for piece, grid, mask in zip(kept, grids, logged_parts):
            part = np.empty(len(grid))
            if resampling:
                part[:] = _spline(t[piece], values[piece], grid)
            else:
                part[mask] = values[piece]
                if not mask.all():
                    part[~mask] = _spline(t[piece], values[piece], grid[~mask])
            parts.append(part)
        out[name] = np.concatenate(parts)
    notes = _notes(t, steps, periods, own, dt, resample, resampling, long_gaps, pieces, kept, short, logged, new_t,
                   min_rows, line)
    return EvenLog(new_t, out, dt, tuple(segments), tuple(notes), None if resampling else ~logged)


def _notes(t, steps, periods, own, dt, resample, resampling, long_gaps, pieces, kept, short, logged, new_t, min_rows,
           line) -> list[str]:
    """What was resampled or filled, where the log was split and what was dropped."""
    notes = []
    inner = np.concatenate([piece[:-1] for piece in kept])          # the steps within the segments kept
    read = sum(len(piece) for piece in kept)
    if resample is not None:
        notes.append(f"resampled to {resample:g} Hz ({len(new_t)} samples from {read}) by cubic splines")
    elif resampling:
        notes.append(f"resampled on the median period {_seconds(dt)} ({1 / dt:.6g} Hz; the logged steps "
                     f"{_seconds(steps[inner].min())} to {_seconds(steps[inner].max())}): {len(new_t)} samples "
                     f"from {read}, by cubic splines")
    else:
        filled = int((~logged).sum())
        if filled:
            gaps = inner[np.rint(periods[inner]) > 1]
            worst = int(gaps[np.argmax(periods[gaps])])
            notes.append(f"filled {filled} dropped sample{'s' if filled > 1 else ''} ({len(gaps)} gap"
                         f"{'s' if len(gaps) > 1 else ''}; the largest {int(np.rint(periods[worst]))} periods long, "
                         f"at t = {_at(t[worst], dt)} s)")
    if len(long_gaps):
        at = "after t = " + _listed([f"{_at(t[r], dt)} s" for r in long_gaps], sep=", ")
        notes.append(f"split at {len(long_gaps)} long gap{'s' if len(long_gaps) > 1 else ''} ({at}) into "
                     f"{len(pieces)} segments, each differentiated on its own")
    if short:
        notes.append(f"dropped {_short_phrase(t, pieces, short, line, min_rows, dt)}: {len(kept)} segment"
                     f"{'s' * (len(kept) > 1)} left")
    return notes


__all__ = ["JITTER", "MAX_FILLED_PERIODS", "MAX_UPSAMPLING", "MIN_SEGMENT_ROWS", "EvenLog", "even_clock"]
