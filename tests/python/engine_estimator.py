"""The engine's error of a mean (src/protocol/observables.cpp, `mean_error`) in Python: the oracle
that analysis.runs.series_error is compared with on the same series (tests/python/test_series_error.py).
It reproduces the errors a pull's run file records for its prefixes (/observables/drag/convergence)
and, with the N/6 fallback window the engine had when they were recorded, those of the 192 yield
pulls in tests/data/yield_pulls_D2.h5."""
import math

import numpy as np


def _autocovariance(d):
    """gamma(t) = sum_i d_i d_{i+t} / (n - t) of a centred series, as the engine's."""
    n = len(d)
    f = np.fft.rfft(d, 2 * n)
    return np.fft.irfft(f * np.conj(f), 2 * n)[:n] / (n - np.arange(n))


def _window_sum(g, n, w_min):
    """Wolff's automatic window (S = 2), summed on to w_min; bias-corrected sum, window, found."""
    t_max = (n - 1) // 3
    if not g[0] > 0:
        return 0.0, 0, False
    found, c, w_found, s, w = False, 0.0, 0, 0.0, 1
    while w <= t_max:
        s += g[w]
        if not found:
            tau = 0.5 + s / g[0]
            tau_w = 1e-12 if tau <= 0.5 else 2.0 / math.log((2 * tau + 1) / (2 * tau - 1))
            if math.exp(-w / tau_w) - tau_w / math.sqrt(w * n) < 0:
                found, w_found, c = True, w, g[0] + 2 * s
        if found and w >= w_min:
            break
        w += 1
    w = min(w, t_max)
    if not found or w_min > w_found:
        w_found, c = w, g[0] + 2 * s
    return c / (1.0 - (2.0 * w_found + 1) / n), w_found, found


def _negative_lobe(g, n, var_mean):
    """The Bartlett window of width 1.5 z2 through a negative lobe (step 5), or None."""
    t_max = (n - 1) // 3
    rho = (g[:t_max + 1] + var_mean) / (g[0] + var_mean)
    z1 = z2 = 0
    for t in range(1, t_max + 1):
        if not z1 and rho[t] < 0:
            z1 = t
        elif z1 and rho[t] >= 0:
            z2 = t
            break
    if not z2:
        return None
    positive, lobe = rho[1:z1].sum(), rho[z1:z2].sum()
    t_deep = z1 + int(np.argmin(rho[z1:z2]))
    deepest = min(0.0, float(rho[t_deep]))
    se = math.sqrt((1 + 2 * np.sum(rho[1:t_deep] ** 2)) / n)
    m = (3 * z2) // 2
    if lobe > -0.7 * positive or deepest > -se or m > n // 2:
        return None
    t = np.arange(1, m)
    c = g[0] + 2 * np.sum((1 - t / m) * g[1:m])
    return c / (1.0 - m / n), m


def engine_error(x, fallback=5):
    """(error, dof, plateau) of the mean of x, as the engine's mean_error (its fallback window N/5;
    N/6 before 2026-11-27)."""
    x = np.asarray(x, dtype=float)
    n = len(x)
    if n < 8:
        return math.nan, math.nan, False
    g = _autocovariance(x - x.mean())

    def se(c):
        return math.sqrt(max(c, 0.0) / n)

    c, w, found = _window_sum(g, n, 0)
    if found and (lobe := _negative_lobe(g, n, max(c, 0.0) / n)):
        err, dof, plateau = se(lobe[0]), 1.5 * n / lobe[1], math.sqrt(lobe[1] / (3.0 * n)) <= 0.25
    else:
        err, dof = se(c), n / (2.0 * w + 1)
        plateau = found and math.sqrt((2.0 * w + 1) / (2.0 * n)) <= 0.25
        if w == 0:
            dof = n - 1.0
        if not (plateau or w == 0):
            cb, wb, _ = _window_sum(g, n, n // fallback)
            err, dof = max(err, se(cb)), min(dof, n / (2.0 * wb + 1))
    if not err > 0 and g[0] > 0:
        return math.sqrt(g[0] / (n - 1)), n - 1.0, False
    return err, dof, plateau
