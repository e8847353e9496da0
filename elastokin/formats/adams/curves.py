"""How ADAMS and elastokin interpolate a property-file curve, and how far apart they are.

Pure numpy. ADAMS interpolates the curves of a property file (bushing, spring) with an Akima
spline (Akima 1970: cubic Hermite pieces whose slopes at the table points are a weighted mean
of the neighbouring chord slopes, end slopes from chords extrapolated linearly); elastokin's law
is piecewise linear through the same points. The two agree at every table point; between points
they differ by at most :func:`akima_deviation`. Conventions: ``docs/adams.md``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["akima", "akima_deviation"]


def _akima_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    m = np.diff(y) / np.diff(x)
    if m.size == 1:
        return np.array([m[0], m[0]])
    left = 2.0 * m[0] - m[1]
    right = 2.0 * m[-1] - m[-2]
    ext = np.concatenate([[2.0 * left - m[0], left], m, [right, 2.0 * right - m[-1]]])
    w1 = np.abs(ext[3:] - ext[2:-1])     # |m_{i+1} - m_i|
    w2 = np.abs(ext[1:-2] - ext[:-3])    # |m_{i-1} - m_{i-2}|
    den = w1 + w2
    mean = 0.5 * (ext[1:-2] + ext[2:-1])
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(den > 0.0, (w1 * ext[1:-2] + w2 * ext[2:-1]) / np.where(den > 0, den, 1.0),
                     mean)
    return t


def akima(x, y, xq) -> np.ndarray:
    """The Akima spline through (``x``, ``y``) (x strictly increasing) at ``xq`` inside
    [x[0], x[-1]] (outside: the end cubic continued, as evaluated here; ADAMS' own behaviour
    beyond the table is not reproduced)."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    xq = np.asarray(xq, float)
    t = _akima_slopes(x, y)
    i = np.clip(np.searchsorted(x, xq, side="right") - 1, 0, x.size - 2)
    h = x[i + 1] - x[i]
    s = (xq - x[i]) / h
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    return h00 * y[i] + h10 * h * t[i] + h01 * y[i + 1] + h11 * h * t[i + 1]


def akima_deviation(x, y, samples: int = 32) -> tuple[float, float]:
    """Largest |Akima spline - piecewise-linear law| between the table points (sampled
    ``samples`` times per interval) and the deflection where it is: (load, deflection)."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    s = np.linspace(0.0, 1.0, samples + 1)[1:-1]
    xq = (x[:-1, None] + np.diff(x)[:, None] * s[None, :]).ravel()
    d = np.abs(akima(x, y, xq) - np.interp(xq, x, y))
    k = int(np.argmax(d)) if d.size else 0
    return (float(d[k]), float(xq[k])) if d.size else (0.0, float(x[0]))
