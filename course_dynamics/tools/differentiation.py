"""Θ̇ and Θ̈ from logged Θ (and Θ̇): Savitzky–Golay filters whose windows come from the log's own noise.

==============  ==========  =========================================================================
code            symbol      meaning (shape, unit)
==============  ==========  =========================================================================
``t_step``      Δt          the sample step, s
``q``           Θ           joint positions (K, n), rad or m
``qd``          Θ̇           joint rates (K, n), rad/s or m/s: logged (passed through) or differentiated
``qdd``         Θ̈           joint accelerations (K, n), rad/s² or m/s²
``noise_q``     σ_Θ         the position noise estimated per joint (n,), rad or m
``noise_qd``    σ_Θ̇         the rate noise estimated per joint (n,), rad/s or m/s
``sigma_qdd``   σ_Θ̈         the estimated error of Θ̈ (K, n), rad/s²: the noise left after filtering and the fit's bias
``window``      w           the filter's window per joint (n,), samples (odd); w Δt in s
``h``           h           a filter's weights on its w samples; d-th derivative = Σ h_j y_j / Δtᵈ
==============  ==========  =========================================================================

A Savitzky–Golay filter fits a polynomial by least squares to the w samples around a row and
differentiates the fit; it is linear, so the row's value is Σ h_j y_j / Δtᵈ. Θ̈ is what torques
depend on most: it is the first derivative of a logged Θ̇ (d = 1), else the second derivative
of Θ (d = 2). Inside the log the window is centred and the fit cubic; the first and last w//2
rows (where a centred window does not fit) come from one fit of the first (last) N ≥ w samples,
cubic or quintic. All of it is chosen per joint from the signal y (Θ, or Θ̇ when logged) itself,
with yₛ⁽ᵐ⁾ = Δtᵐ y⁽ᵐ⁾ its m-th derivative per sample:

1. Noise. σ̂ = 1.4826 · median ``|Δ⁴y|`` / √70, where Δ⁴y is the fourth difference of successive
   samples: for white noise of standard deviation σ it has standard deviation σ √C(8,4) = σ √70, and
   1.4826 · median ``|·|`` is the standard deviation of a normal variable, untouched by a few outliers.
   It assumes white noise and a smooth motion, ``|yₛ⁽⁴⁾|`` ≪ 8σ (so at 125 Hz and beyond, motions of a
   few Hz); what the motion adds to Δ⁴y counts as noise. If more than half the differences are zero
   (a quantized signal at rest) the RMS of Δ⁴y takes the median's place.
2. Error of a filter h: its noise is σ̂ ‖h‖₂ (per sample); its bias is the first term of y's Taylor
   series that it does not reproduce, β yₛ⁽ᵐ⁾ with β = Σ h_j (j − row)ᵐ / m!: m = 4 for the centred
   second derivative (its weights are even), m = 5 for the centred first derivative (odd), m = p + 1
   for a one-sided fit of degree p. Over the log, E²(h) = β² Rₘ + σ̂² ‖h‖₂², Rₘ the mean of yₛ⁽ᵐ⁾².
3. Rₘ is measured, not assumed: two centred filters reproducing degree m − 1, of windows w and 2w + 1,
   differ by (β₂ − β₁) yₛ⁽ᵐ⁾ + noise, so Rₘ = (mean of their difference² − σ̂² ‖h₂ − h₁‖²) / (β₂ − β₁)²,
   or 0. From 20 ms, w moves to the odd window (7 to 1001 samples, 5 % apart) minimizing E², at most
   a factor 3 away (the Taylor term holds near where Rₘ was measured), and Rₘ is measured again there,
   until w stays (six times at most). The edge fit (degree p, N samples) minimizes E² of its end row
   the same way. Data without noise (σ̂ below 1e-12 of ``|y|``: rounding) keep the shortest window, 7.

σ_Θ̈ of a row is √(σ̂² ‖h‖₂² + β² Rₘ) / Δtᵈ with the row's own weights h (the end rows' bias is the end
row's one-sided fit's): the noise left after filtering and the fit's own error, larger at the ends. An end row is a
one-sided fit and errs more than the centred rows: about 2–3 × for Θ̈ from Θ, 5–8 × for Θ̈ from a
logged Θ̇ (whose centred first derivative is unusually good), measured on ``tests/logmakers.py``'s
motion. A ``window`` given by hand is scipy's ``savgol_filter(mode="interp")``: cubic everywhere.

>>> import numpy as np
>>> from course_dynamics.tools.differentiation import derivatives
>>> t = np.arange(0, 2, 2e-3)[:, None]                                       # 500 Hz, s
>>> q = np.sin(3 * t) + np.random.default_rng(0).normal(0, 2e-5, t.shape)     # rad
>>> result = derivatives(2e-3, q, None)
>>> f"{result.noise_q[0]:.1e}", bool(result.window[0] > 11)
('2.0e-05', True)
>>> bool(np.abs(result.qdd - (-9 * np.sin(3 * t))).max() < 0.05)            # rad/s²
True
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from math import comb, factorial

import numpy as np

from ..base.errors import InputError

POLYORDER = 3                  # the centred fits: cubic (their Θ̈ is exact for cubic Θ)
EDGE_ORDERS = (3, 5)           # an edge fit's degrees: a longer quintic beats a cubic on smooth motion
#: Where the window search starts, and the window of a log too short to search, s.
DEFAULT_WINDOW_SECONDS = 0.02  # where the search starts, and the window of a log too short to search
#: The shortest window chosen, samples.
MIN_WINDOW = 7
#: How many multiply-adds of the direct correlation one step of an FFT is worth (``size log₂ size`` steps).
FFT_WORK = 6
#: The longest window chosen, samples (1 s at 1 kHz); longer fits of a robot's motion are not local any more.
MAX_WINDOW = 1001              # samples: 1 s at 1 kHz; longer fits of a robot's motion are not local any more
GRID_RATIO = 1.05              # successive candidate windows differ by 5 %
MAX_PILOTS = 6
PILOT_ROWS = 20_000            # rows enough to measure Rₘ to a few per cent; longer logs give blocks of them
PILOT_BLOCKS = 10
STEP = 3.0                     # the farthest one pilot may move the window (a factor)
MAD_TO_SIGMA = 1.4826          # standard deviation / median absolute value of a normal variable
DIFFERENCE_ORDER = 4
NOISE_FREE = 1e-12             # σ̂ below this share of max |y| is rounding: the data are taken as exact


@dataclass(frozen=True)
class Derivatives:
    """Θ̇ and Θ̈ on the samples of a log, with the windows, noise and uncertainty they came with (module docstring).

    ``noise_qd`` is None when Θ̇ was not given; ``notes`` has one line per decision.

    Parameters
    ----------
    qd : numpy.ndarray, shape (K, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint): given, or differentiated.
    qdd : numpy.ndarray, shape (K, n)
        Joint accelerations Θ̈, rad/s² (m/s²).
    window : numpy.ndarray, shape (n,)
        The centred filter's window per joint, samples (odd).
    noise_q : numpy.ndarray, shape (n,)
        The position noise σ_Θ estimated per joint, rad (m).
    noise_qd : numpy.ndarray, shape (n,), optional
        The rate noise σ_Θ̇ estimated per joint, rad/s (m/s); None when Θ̇ was not given.
    sigma_qdd : numpy.ndarray, shape (K, n)
        The estimated error σ_Θ̈ of Θ̈, rad/s² (m/s²).
    notes : tuple of str
        One line per decision.
    """

    qd: np.ndarray
    qdd: np.ndarray
    window: np.ndarray
    noise_q: np.ndarray
    noise_qd: np.ndarray | None
    sigma_qdd: np.ndarray
    notes: tuple[str, ...] = ()


def noise_level(y: np.ndarray) -> np.ndarray:
    """The standard deviation of white noise on each column of ``y`` (K, n), from its fourth differences.

    Parameters
    ----------
    y : numpy.ndarray, shape (K, n)
        A sampled signal, one column per joint.

    Returns
    -------
    numpy.ndarray, shape (n,)
        σ̂ per column, in ``y``'s unit; NaN for fewer than 5 rows.

    Examples
    --------
    >>> import numpy as np
    >>> y = np.linspace(0, 1, 4000)[:, None] ** 3 + np.random.default_rng(1).normal(0, 1e-4, (4000, 1))
    >>> f"{noise_level(y)[0]:.1e}"
    '1.0e-04'
    """
    y = np.asarray(y, dtype=float)
    if len(y) <= DIFFERENCE_ORDER:
        return np.full(y.shape[1:], np.nan)
    scale = np.sqrt(comb(2 * DIFFERENCE_ORDER, DIFFERENCE_ORDER))   # Var Δ⁴e = 70 σ² for white e
    differences = np.diff(y, DIFFERENCE_ORDER, axis=0)
    robust = MAD_TO_SIGMA * np.median(np.abs(differences), axis=0) / scale
    rms = np.sqrt(np.mean(differences**2, axis=0)) / scale
    return np.where(robust > 0, robust, rms)


def _odd_floor(value: float) -> int:
    value = int(value)
    return value if value % 2 else value - 1


def _candidates(samples: int) -> np.ndarray:
    """Odd windows from 7 (or the log's length) up to MAX_WINDOW or the log's length, 5 % apart."""
    largest = _odd_floor(min(samples, MAX_WINDOW))
    found = [min(MIN_WINDOW, largest)]
    while found[-1] < largest:
        found.append(min(largest, max(found[-1] + 2, _odd_floor(found[-1] * GRID_RATIO))))
    return np.array(found)


@lru_cache(maxsize=4096)
def _least_squares(samples: int, order: int) -> tuple[float, float, np.ndarray]:
    """(centre, scale, pinv): the least-squares polynomial of degree ``order`` on ``samples`` samples has the
    coefficients pinv @ y in powers of u = (j − centre) / scale. Scaling j to [−1, 1] keeps a quintic over a
    thousand samples well conditioned: scipy's savgol_coeffs fits powers of j itself, and its one-sided quintics
    are wrong by 400 samples."""
    centre = (samples - 1) / 2
    scale = max(centre, 1.0)
    pinv = np.linalg.pinv(np.vander((np.arange(samples) - centre) / scale, order + 1, increasing=True))
    pinv.setflags(write=False)
    return centre, scale, pinv


def _weights(samples: int, order: int, deriv: int, positions=None) -> np.ndarray:
    """h (a row per position, default the centre): the ``deriv``-th derivative (Δt = 1) of the least-squares fit."""
    centre, scale, pinv = _least_squares(samples, order)
    u = (np.atleast_1d(centre if positions is None else positions).astype(float) - centre) / scale
    powers = np.arange(deriv, order + 1)
    derivative = np.zeros((len(u), order + 1))
    derivative[:, deriv:] = [factorial(k) / factorial(k - deriv) for k in powers] * u[:, None] ** (powers - deriv)
    h = derivative @ pinv / scale**deriv
    return h[0] if positions is None or np.ndim(positions) == 0 else h


def _bias(h: np.ndarray, m: int, pos: int) -> float:
    """β = Σ h_j (j − pos)ᵐ / m!: what the filter makes of the Taylor term yₛ⁽ᵐ⁾ (j − pos)ᵐ / m!."""
    return float(h @ (np.arange(len(h), dtype=float) - pos) ** m) / factorial(m)


@lru_cache(maxsize=4096)
def _gain_and_bias(samples: int, order: int, deriv: int, at_end: bool, m: int) -> tuple[float, float]:
    """‖h‖₂ and β of the filter at the centre (or the first row, ``at_end``) of a fit of ``samples`` samples."""
    pos = 0 if at_end else samples // 2
    h = _weights(samples, order, deriv, pos)
    return float(np.linalg.norm(h)), _bias(h, m, pos)


def _correlate(y: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Σ_j h_j y_{k+j} for every k where the window fits: numpy's direct sum where it is the less work, else
    numpy's FFT (as ``scipy.signal.correlate`` chooses, without importing scipy.signal and scipy.stats with it,
    0.4 s of a command's start)."""
    samples, width = len(y), len(h)
    size = 1 << int(np.ceil(np.log2(samples + width - 1)))   # the FFT's length, a power of 2
    if samples * width <= FFT_WORK * size * np.log2(size):
        return np.correlate(y, h, mode="valid")
    product = np.fft.rfft(y, size) * np.fft.rfft(h[::-1], size)
    return np.fft.irfft(product, size)[width - 1:samples]


def _mean_square(y: np.ndarray, sigma: float, m: int, window: int) -> float | None:
    """Rₘ, the mean of yₛ⁽ᵐ⁾², measured by two centred filters around ``window`` (module docstring, 3)."""
    deriv = 2 - m % 2                        # centred weights of this parity see yₛ⁽ᵐ⁾ (odd ones miss even powers)
    wide = _odd_floor(min(2 * window + 1, (len(y) + 1) // 2))
    narrow = min(window, _odd_floor((wide - 1) // 2))
    if narrow <= m:
        return None
    h_wide = _weights(wide, m - 1, deriv)
    h_narrow = _weights(narrow, m - 1, deriv)
    difference = h_wide.copy()
    offset = (wide - narrow) // 2
    difference[offset:offset + narrow] -= h_narrow
    beta = _bias(h_wide, m, wide // 2) - _bias(h_narrow, m, narrow // 2)
    rows = len(y) - wide + 1                 # a long log is sampled in PILOT_BLOCKS blocks spread over it
    block = min(rows, PILOT_ROWS // PILOT_BLOCKS)
    starts = np.unique(np.linspace(0, rows - block, PILOT_BLOCKS).astype(int)) if rows > PILOT_ROWS else [0]
    length = rows if rows <= PILOT_ROWS else block
    values = np.concatenate([np.correlate(y[s:s + length + wide - 1], difference, "valid") for s in starts])
    excess = float(np.mean(values**2)) - sigma**2 * float(difference @ difference)
    return max(excess, 0.0) / beta**2


def _choose(y: np.ndarray, sigma: float, m: int, windows: np.ndarray, gain: np.ndarray, bias: np.ndarray,
            start: int) -> tuple[int, float]:
    """The index into ``windows`` minimizing E² = β² Rₘ + σ² ‖h‖² (Rₘ measured there), and that E².

    Each step moves at most a factor STEP from where Rₘ was measured: only there does its first Taylor term hold.
    """
    chosen, error = start, np.inf
    for _ in range(MAX_PILOTS):
        here = int(windows[chosen])
        r_m = _mean_square(y, sigma, m, here)
        if r_m is None:
            break
        squared = bias**2 * r_m + (sigma * gain) ** 2
        squared[(windows > STEP * here) | (windows < here / STEP)] = np.inf
        best = int(np.argmin(squared))
        error = float(squared[best])
        if best == chosen:
            break
        chosen = best
    return chosen, error


@dataclass(frozen=True)
class _Plan:
    """A joint's filters: a centred cubic of ``window`` inside; degree ``edge_order`` on ``edge_window`` at the ends."""

    window: int
    edge_window: int
    edge_order: int
    bias: float = 0.0        # √(β² Rₘ) of the centred filter, per sample (divide by Δtᵈ)
    edge_bias: float = 0.0   # the same for the end row's one-sided fit


def _plan(y: np.ndarray, sigma: float, deriv: int, windows: np.ndarray, start: int) -> _Plan:
    """The windows minimizing the estimated error of the ``deriv``-th derivative of ``y`` (module docstring, 2–3)."""
    if not np.isfinite(sigma):
        return _Plan(int(windows[start]), int(windows[start]), POLYORDER)
    if sigma <= NOISE_FREE * np.abs(y).max():       # rounding, not noise: bias alone decides (the shortest window)
        sigma = 0.0
    y = y - y.mean()                                # the filters below ignore a constant; removing it saves digits
    m = 4 if deriv % 2 == 0 else 5
    gain, bias = np.array([_gain_and_bias(int(w), POLYORDER, deriv, False, m) for w in windows]).T
    inner, error = _choose(y, sigma, m, windows, gain, bias, start)
    window = int(windows[inner])
    inner_bias = np.sqrt(max(error - (sigma * gain[inner]) ** 2, 0.0)) if np.isfinite(error) else 0.0
    best = (np.inf, window, POLYORDER, 0.0)
    for order in EDGE_ORDERS:
        lengths = windows[(windows >= window) & (windows >= order + 2)]
        if len(lengths) == 0:
            continue
        gain, bias = np.array([_gain_and_bias(int(n), order, deriv, True, order + 1) for n in lengths]).T
        index, error = _choose(y, sigma, order + 1, lengths, gain, bias, 0)
        if error < best[0]:
            best = (error, int(lengths[index]), order, np.sqrt(max(error - (sigma * gain[index]) ** 2, 0.0)))
    return _Plan(window, best[1], best[2], float(inner_bias), float(best[3]))


def _filter(y: np.ndarray, plan: _Plan, deriv: int, t_step: float, sigma: float = 0.0):
    """The ``deriv``-th derivative of ``y`` (K,) by ``plan``, ‖h‖₂ / Δtᵈ of each row's weights, and each row's
    disagreement / Δtᵈ at the ends: between the cubic and the quintic fit of the same samples (0 inside)."""
    samples, half, n = len(y), plan.window // 2, plan.edge_window
    h = _weights(plan.window, POLYORDER, deriv)
    offset = y.mean() if deriv else 0.0             # derivatives ignore a constant; removing it saves digits
    values = np.empty(samples)
    gains = np.full(samples, np.linalg.norm(h))
    values[half:samples - half] = _correlate(y - offset, h)
    edge = _weights(n, plan.edge_order, deriv, np.arange(half))                  # rows 0 … w//2 − 1
    values[:half] = edge @ (y[:n] - offset)
    mirrored = edge[::-1, ::-1] * (-1) ** deriv                                  # rows K − w//2 … K − 1
    values[samples - half:] = mirrored @ (y[samples - n:] - offset)
    gains[:half] = np.linalg.norm(edge, axis=1)
    gains[samples - half:] = gains[:half][::-1]
    spread = np.zeros(samples)
    other = next((o for o in EDGE_ORDERS if o != plan.edge_order and n >= o + 2), None)
    if other is not None:
        alternative = _weights(n, other, deriv, np.arange(half))
        spread[:half] = np.abs(alternative @ (y[:n] - offset) - values[:half])
        spread[samples - half:] = np.abs((alternative[::-1, ::-1] * (-1) ** deriv) @ (y[samples - n:] - offset)
                                         - values[samples - half:])
    return values / t_step**deriv, gains / t_step**deriv, spread / t_step**deriv


def _explicit_window(samples: int, window: int, where: str) -> int:
    if window != int(window) or window < POLYORDER + 2 or window % 2 == 0:
        raise InputError(f"the smoothing window must be an odd number of samples, at least {POLYORDER + 2}; "
                         f"got {window}")
    if window > samples:
        raise InputError(f"{where}: the smoothing window ({window} samples) is longer than the log ({samples} rows)")
    return int(window)


def _span(values, unit: str = "", digits: str = ".2g") -> str:
    low, high = f"{min(values):{digits}}", f"{max(values):{digits}}"
    return f"{low}{unit}" if low == high else f"{low}–{high}{unit}"


def derivatives(t_step: float, q, qd=None, window: int | None = None, *, where: str = "the log") -> Derivatives:
    """Θ̇ (given, or differentiated from Θ) and Θ̈ (from Θ̇ if given, else from Θ) of a log sampled every ``t_step``.

    Parameters
    ----------
    t_step : float
        The (even) sample step Δt, s.
    q : numpy.ndarray, shape (K, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : numpy.ndarray, shape (K, n), optional
        A logged Θ̇, rad/s (m/s), passed through unchanged; None differentiates Θ.
    window : int, optional
        The Savitzky–Golay window in samples (odd) for every joint and row (scipy's
        ``savgol_filter(mode="interp")``, as chosen by hand); None chooses per joint (module docstring).
    where : str
        The log's name, for messages.

    Returns
    -------
    Derivatives
        ``qd``, ``qdd`` (K, n); ``window`` (n,) samples; ``noise_q`` (n,); ``noise_qd`` (n,) or None;
        ``sigma_qdd`` (K, n); ``notes``.

    Raises
    ------
    InputError
        If ``q`` is not a table of shape (K, n), ``qd`` has another shape, the sample step is not a positive
        number of seconds, the window is even, below 5 or longer than the log, there are fewer than 5 rows, or
        the derivatives leave the floating-point range.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 1, 1e-3)[:, None]
    >>> result = derivatives(1e-3, t**3, None)                # a cubic: exact, with the shortest window
    >>> int(result.window[0]), bool(np.allclose(result.qdd, 6 * t))
    (7, True)
    """
    q = np.asarray(q, dtype=float)
    if q.ndim != 2:
        raise InputError(f"{where}: q must be a table of shape (rows, joints), got shape {q.shape}")
    samples, joints = q.shape
    if qd is not None:
        qd = np.asarray(qd, dtype=float)
        if qd.shape != q.shape:
            raise InputError(f"{where}: qd has shape {qd.shape}, q has {q.shape}")
    if not (np.isfinite(t_step) and t_step > 0):
        raise InputError(f"the sample step must be a positive number of seconds, got {t_step}")
    for name, values in (("q", q), ("qd", qd)):
        if values is not None and not np.all(np.isfinite(values)):
            row, column = map(int, np.argwhere(~np.isfinite(values))[0])
            raise InputError(f"{where}: {name} in row {row}, column {column} is {values[row, column]}: "
                             "a table to differentiate must be finite")
    if window is not None:
        window = _explicit_window(samples, window, where)
    elif samples < POLYORDER + 2:
        raise InputError(f"{where}: {samples} rows are too few to differentiate "
                         f"(at least {POLYORDER + 2} are needed)")

    noise_q = noise_level(q)
    noise_qd = None if qd is None else noise_level(qd)
    source, sigma, deriv = (q, noise_q, 2) if qd is None else (qd, noise_qd, 1)
    windows = _candidates(samples)
    start = int(np.argmin(np.abs(windows - DEFAULT_WINDOW_SECONDS / t_step)))
    plans = []
    for j in range(joints):
        if window is not None:
            plans.append(_Plan(window, window, POLYORDER))
        else:
            plans.append(_plan(source[:, j], float(sigma[j]), deriv, windows, start))

    qdd = np.empty_like(q)
    sigma_qdd = np.empty_like(q)
    rates = np.empty_like(q) if qd is None else qd
    with np.errstate(all="ignore"):
        for j, plan in enumerate(plans):
            qdd[:, j], gains, spread = _filter(source[:, j], plan, deriv, t_step, float(np.nan_to_num(sigma[j])))
            bias = np.full(samples, plan.bias)              # the fit's own error, in quadrature with the noise's
            half = min(plan.window // 2, samples // 2)
            bias[:half] = bias[samples - half:] = plan.edge_bias
            # the fit's error: the log-wide estimate, or at the ends the two end fits' disagreement where larger
            sigma_qdd[:, j] = np.sqrt((sigma[j] * gains) ** 2 + np.maximum(bias / t_step**deriv, spread) ** 2)
            if qd is None:
                rates[:, j] = _filter(q[:, j], plan, 1, t_step)[0]
    if not (np.all(np.isfinite(qdd)) and np.all(np.isfinite(rates))):
        raise InputError(f"{where}: differentiating {'q' if qd is None else 'qd'} gives values beyond floating-point "
                         f"range")
    chosen = np.array([p.window for p in plans])
    return Derivatives(qd=rates, qdd=qdd, window=chosen, noise_q=noise_q, noise_qd=noise_qd, sigma_qdd=sigma_qdd,
                       notes=_notes(plans, t_step, qd is None, sigma, window is not None))


def _notes(plans: list[_Plan], t_step: float, positions_only: bool, sigma: np.ndarray, explicit: bool) -> tuple:
    windows = [p.window for p in plans]
    if explicit:
        how = f"Savitzky-Golay derivative ({windows[0]}-sample window = {windows[0] * t_step:.4g} s, cubic)"
        lines = [f"qd: first {how} of q"] if positions_only else []
        source = "q" if positions_only else "qd"
        return tuple(lines + [f"qdd: {'second' if positions_only else 'first'} {how} of {source}"])
    size = (f"window{'s' if len(set(windows)) > 1 else ''} {_span(windows, digits='d')} samples "
            f"({_span([w * t_step for w in windows], ' s', '.3g')})")
    if positions_only:
        noise = f"position noise {_span(sigma, ' rad (or m)')}"
    else:
        noise = f"rate noise {_span(sigma, ' rad/s (or m/s)')}"
    lines = [f"qd: first Savitzky-Golay derivative of q, cubic, the {size} chosen for qdd"] if positions_only else []
    lines.append(f"qdd: {'second' if positions_only else 'first'} Savitzky-Golay derivative of "
                 f"{'q' if positions_only else 'qd'}, cubic, {size} chosen from the {noise} estimated")
    orders = {3: "cubic", 5: "quintic"}
    lines.append(f"edges: the first and last {_span([w // 2 for w in windows], digits='d')} rows from one fit of the "
                 f"first and last {_span([p.edge_window for p in plans], digits='d')} samples "
                 f"({', '.join(orders.get(o, str(o)) for o in sorted({p.edge_order for p in plans}))})")
    return tuple(lines)


__all__ = ["DEFAULT_WINDOW_SECONDS", "MAX_WINDOW", "MIN_WINDOW", "Derivatives", "derivatives", "noise_level"]
