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
* refuses a longer gap with its time, unless asked to split there (``split_gaps``): the pieces
  are then separate segments, each differentiated on its own;
* refuses steps that are neither Δt nor a multiple of it (a jittering clock), pointing at
  ``resample``;
* with ``resample`` (Hz) puts every column on an even clock at that rate by the same cubic
  splines (no gap check then beyond the long-gap rule), and says so.

>>> import numpy as np
>>> t = np.array([0.0, 0.01, 0.02, 0.04, 0.05, 0.06])                # the sample at 0.03 s was dropped
>>> result = even_clock(t, {"q_a": t**2})
>>> np.round(result.t, 3).tolist()
[0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06]
>>> result.notes[0]
'filled 1 dropped sample (1 gap; the largest 2 periods long, at t = 0.02 s)'
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError

#: A step within this share of Δt is Δt; of k Δt, within it of Δt, is k periods.
JITTER = 0.1               # a step within 10 % of Δt is Δt; of k Δt, within 10 % of Δt, is k periods
#: The longest gap filled, in periods (4 dropped samples in a row); a longer one is refused or split.
MAX_FILLED_PERIODS = 5     # a gap of up to 5 periods (4 dropped samples in a row) is filled
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
        What was filled, resampled or split.
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


def even_clock(t, columns: dict, *, resample: float | None = None, split_gaps: bool = False,
               where: str = "the log", line=None) -> EvenLog:
    """``columns`` (our name → (K,) values at times ``t``) on an even clock (module docstring).

    ``line(row)`` names a logged row in messages (default ``row N``). Raises
    :class:`~course_dynamics.base.errors.InputError` for a gap longer
    than :data:`MAX_FILLED_PERIODS` periods (unless ``split_gaps``), a step that is no whole number of periods
    (unless ``resample``), or a bad ``resample`` rate.

    Parameters
    ----------
    t : numpy.ndarray, shape (K,)
        Sample times as logged, s, increasing.
    columns : dict
        Our column name → values of shape (K,).
    resample : float, optional
        Put every column on an even clock at this rate, Hz.
    split_gaps : bool
        Split at long gaps into segments instead of refusing them.
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
        A long gap (without ``split_gaps``), a segment of one sample, a step that is no whole number of periods
        (without ``resample``), t not increasing, or a resampling rate not positive or above
        :data:`MAX_UPSAMPLING` times the log's own.
    """
    t = np.asarray(t, dtype=float)
    line = line or (lambda row: f"row {row + 1}")
    if len(t) < 2:
        return EvenLog(t, dict(columns), 0.0, ((0, len(t)),))
    if resample is not None:
        if not (np.isfinite(resample) and resample > 0):
            raise InputError(f"the resampling rate must be a positive number of Hz, got {resample:.6g}")
        own = 1.0 / _median_step(t, where)
        if resample > MAX_UPSAMPLING * own:
            raise InputError(f"{where}: resampling at {resample:.6g} Hz a log recorded at about {own:.6g} Hz would "
                             f"invent {resample / own:.3g} samples for each one logged (at most {MAX_UPSAMPLING:g}x "
                             f"its own rate)")
        dt = 1.0 / float(resample)
    else:
        dt = _median_step(t, where)
    steps = np.diff(t)
    periods = steps / dt
    long_gaps = np.flatnonzero(periods > MAX_FILLED_PERIODS + JITTER)
    if len(long_gaps) and not split_gaps:
        row = int(long_gaps[0])
        raise InputError(f"{where}: {steps[row]:.6g} s pass between t = {t[row]:.9g} s and t = {t[row + 1]:.9g} s "
                         f"({line(row + 1)}), {periods[row]:.1f} sample periods: more than {MAX_FILLED_PERIODS} "
                         f"are not filled in; --split-gaps treats the pieces as separate segments")
    pieces = np.split(np.arange(len(t)), long_gaps + 1)
    for piece in pieces:
        if len(piece) < MIN_SEGMENT_ROWS:
            raise InputError(f"{where}: the segment at t = {t[piece[0]]:.9g} s ({line(int(piece[0]))}) has a single "
                             f"sample between two long gaps; nothing can be differentiated there")
    if resample is None:
        k = np.rint(periods)
        off = np.flatnonzero((np.abs(periods - k) > JITTER) & (periods <= MAX_FILLED_PERIODS + JITTER))
        if len(off):
            row = int(off[0])
            raise InputError(f"{where}: the step before {line(row + 1)} is {steps[row]:.6g} s, {periods[row]:.2f} "
                             f"sample periods of {dt:.6g} s: the samples are not on one clock; --resample HZ puts "
                             f"them on one")
    grids, kept, segments, start = [], [], [], 0
    for piece in pieces:
        ts = t[piece]
        if resample is None:
            # each step is a whole number of periods (checked above); counting them step by step, not from the
            # first time, keeps a clock that drifts within the tolerance from putting two samples in one slot
            slots = np.concatenate([[0], np.cumsum(np.rint(np.diff(ts) / dt))]).astype(int)
            count = int(slots[-1]) + 1
            grid = np.interp(np.arange(count), slots, ts)   # logged samples keep their own times, filled ones between
            logged = np.zeros(count, dtype=bool)
            logged[slots] = True
        else:
            grid = ts[0] + dt * np.arange(int(np.floor((ts[-1] - ts[0]) / dt + 1e-9)) + 1)
            logged = np.zeros(len(grid), dtype=bool)
        grids.append(grid)
        kept.append(logged)
        segments.append((start, start + len(grid)))
        start += len(grid)
    new_t = np.concatenate(grids)
    logged = np.concatenate(kept)
    out = {}
    for name, values in columns.items():
        values = np.asarray(values, dtype=float)
        parts = []
        for piece, grid, mask in zip(pieces, grids, kept):
            part = np.empty(len(grid))
            if resample is None:
                part[mask] = values[piece]
                if not mask.all():
                    part[~mask] = _spline(t[piece], values[piece], grid[~mask])
            else:
                part[:] = _spline(t[piece], values[piece], grid)
            parts.append(part)
        out[name] = np.concatenate(parts)
    notes = []
    if resample is not None:
        notes.append(f"resampled to {resample:g} Hz ({len(new_t)} samples from {len(t)}) by cubic splines")
    else:
        filled = int((~logged).sum())
        if filled:
            gaps = np.flatnonzero(np.rint(periods) > 1)
            gaps = gaps[periods[gaps] <= MAX_FILLED_PERIODS + JITTER]
            worst = int(gaps[np.argmax(periods[gaps])])
            notes.append(f"filled {filled} dropped sample{'s' if filled > 1 else ''} ({len(gaps)} gap"
                         f"{'s' if len(gaps) > 1 else ''}; the largest {int(np.rint(periods[worst]))} periods long, "
                         f"at t = {t[worst]:.6g} s)")
    if len(pieces) > 1:
        notes.append(f"split at {len(pieces) - 1} long gap{'s' if len(pieces) > 2 else ''} into {len(pieces)} "
                     "segments, each differentiated on its own")
    return EvenLog(new_t, out, dt, tuple(segments), tuple(notes), None if resample is not None else ~logged)


__all__ = ["JITTER", "MAX_FILLED_PERIODS", "MAX_UPSAMPLING", "EvenLog", "even_clock"]
