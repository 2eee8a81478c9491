"""The standard error of the mean of a correlated series (a pull's drag series), with its
Student-t degrees of freedom and a convergence flag: small pure numpy functions.

Why not the engine's estimator (src/protocol/observables.cpp, `mean_error`). A drag series is
anticorrelated beyond its first correlations: its autocorrelation falls through zero and a
negative lobe of about the positive part's area follows (the recorded series in tests/data:
zero at 30 samples, -0.34 at 52, back at 83; a stiff pull, K_n = 2e6: zero at 12, -0.16 from 13
to 35), so the sum of the autocorrelation over all lags (2 tau_int) is a third to a half of its
sum up to the first zero. The engine's automatic window stops near that zero; its remedy for the
lobe, a Bartlett window, weighs the lobe down by its taper, and a series short for its window
takes the larger of that and an N/5 window. Each errs wide: 1.2-1.3 times the scatter of the mean
on the recorded series at 1,000 samples (tests/python/test_series_error.py). Geyer's initial
sequences stop at the first negative pair of autocovariances, before the lobe, as wide.

Here (`mean_error`):
  1. The autocovariances gamma(k) (divided by N, so that the window sum below estimates N times
     the variance of the mean of N samples, Var(mean_N) = (1/N) sum_|k|<N (1 - |k|/N) gamma(k)).
  2. The first lobe: z1, the first lag where the autocorrelation (corrected for the mean's
     subtraction, 4) is negative, and z2, the first lag after z1 where it is not. A series
     without a negative lobe crosses zero in its noise once its correlations are gone and comes
     back later: z2 is then where the noise returns, past every correlation.
  3. A flat-top (trapezoid) lag window, 1 up to m = z2, tapering linearly to 0 at M = 2 z2: the
     whole lobe at full weight, and beyond it the average of the partial sums over [m, M] (a
     drag series' partial sums oscillate, period about 2 z2 - z1, around their limit). It is
     2 Bartlett(M) - Bartlett(M/2): batch means at batch length M extrapolated in 1/M
     (Richardson), whose bias, unlike one batch length's, does not fall as 1/M only.
     z2 is sought up to N/6 (M <= N/3); without it the window is m = N/6, M = N/3: the widest
     the series allows, with the few degrees of freedom (5) that it has.
  4. Subtracting the sample mean lowers each autocovariance: E[gamma_hat(k)] = (1 - k/N) gamma(k)
     + e_k, e_k = ((N - k) V - sum_{i<N-k} c_i - sum_{i>=k} c_i)/N, with c_i = Cov(x_i, mean)
     and V = Var(mean) (exact for any stationary series, `mean_subtraction_bias`). The e_k are
     computed from the windowed estimate itself, iterated to its fixed point (exact for any
     window; the engine's constant offset -V per lag assumes a window short beside N).
  5. Degrees of freedom: N / sum_k lambda_k^2 (Var of a lag-window estimate, 2/nu), times the
     fraction of the series the mean's subtraction leaves, 1 - sum_k lambda_k (1 - |k|/N) / N.
     (Without that factor, AR(1) series of 25-50 correlation times covered 0.90-0.92.)
  6. Converged (`plateau`): the lobe was found (3), the window is at most a third of the
     series, M <= N/3 (the series holds at least three windows, its mean's subtraction costs at
     most about half of the sum, 4), and the window's sum is positive. The error's precision is
     its dof, not this flag. (M <= N/4 converged 0.67 of the 500-sample windows, 20 d, of the
     D = 1 series against 0.87, and covered 0.970 with errors 1.40 times the scatter against
     0.945 and 1.17.) A sum through the lobe that is not positive is the lobe's noise, not a
     long-run variance of zero: until 2026-12-02 such a window took the independent-sample
     error (8), and the recorded windows of 500-2,000 samples that did (1-8 %) covered 0.46-0.75.
  7. Not converged: the error is a bound, the larger of (3) and the rectangular window up to
     the first zero z1 (up to N/6 without one), the sum's largest partial sum for a series
     with a negative lobe, with the dof of the larger. (Without it, 5-10 oscillations of the
     recorded series, 256-512 samples, covered 0.88, and AR(1) series of 25-50 correlation
     times 0.905-0.91.) The bounds cover every unconverged window of 1,024 samples or 20 d of
     the recorded series, with errors 1.3-1.8 times the scatter.
  8. Both sums not positive: the independent-sample error, as the engine's.
The cumulative average over the whole pull (paper Fig. 4) has no error of its own here:
`rescaled_error` gives it from the steady series' (analysis.runs.run_series says why).
Measured (tests/python/test_series_error.py; `python tests/python/test_series_error.py`
prints the tables): 95 % intervals cover AR(1) means (tau 2-20, 64-1,024 samples, 400 repeats
each) in 0.910-0.985 of the repeats, 15 of 20 cells within 0.93-0.97, the others above it
where short series' errors are bounds, but tau 20 at 64 samples, 0.910 (the engine:
0.860-0.953); windows of 20 d of the recorded drag series (500-2,000 samples) in 0.958-0.975,
converged in 0.87-0.99 of them (the engine: 0.69-1.00), the converged errors 1.12-1.17 times the
scatter of the means, all 1.16-1.27, against the engine's 1.25-1.30.
Convergence needs about ten lobes: series whose lobe ends after 14-18 samples (the recorded
sets averaged over 4-6 samples, the kind of a stiff pull's, K_n = 2e6, sampled every 0.02)
converge in 0.44-0.55 of their windows of 80 samples, 0.83-0.86 of 128, 0.88-0.93 of 160 and
0.93-0.97 of 192 (`tools/series_plateau.py` shows a pull's lobe and why it did not converge).
"""
import math
from typing import NamedTuple

import numpy as np

MIN_SAMPLES = 8          # fewer: no error (NaN), as the engine
LOBE_SEARCH = 1 / 6      # z2 sought up to N/6 lags, so the window M = 2 z2 <= N/3
PLATEAU_WINDOWS = 3      # converged: M <= N/3
BIAS_ITERATIONS = 3   # mean-subtraction fixed point: iterates, then Aitken (window_sum)


class MeanError(NamedTuple):
    mean: float
    error: float          # standard error of the mean
    dof: float            # Student-t degrees of freedom of `error`
    window: int           # M, the lag window's end (samples)
    plateau: bool         # the correlations were resolved (module docstring, 6)


def autocovariance(x):
    """gamma_hat(k) = (1/N) sum_i (x_i - mean)(x_{i+k} - mean), k = 0..N-1 (by FFT)."""
    x = np.asarray(x, dtype=float)
    n = len(x)
    d = x - x.mean()
    f = np.fft.rfft(d, 2 * n)
    return np.fft.irfft(f * np.conj(f), 2 * n)[:n] / n


def mean_subtraction_bias(acf, n, lags):
    """e_k = E[gamma_hat(k)] - (1 - k/n) gamma(k), k = 0..lags-1, for a stationary series of n
    samples whose autocovariance is `acf` (gamma(0), gamma(1), ...; zero beyond it)."""
    P = np.cumsum(np.asarray(acf, dtype=float)[:n])
    K = len(P)
    i = np.arange(n)
    # c_i = Cov(x_i, mean) = (1/n) sum_j gamma(i - j): lags -(n-1-i) .. i within the support
    c = (P[np.minimum(i, K - 1)] + P[np.minimum(n - 1 - i, K - 1)] - P[0]) / n
    v = c.mean()                                        # Var(mean)
    pc = np.concatenate([[0.0], np.cumsum(c)])
    k = i[:min(lags, n)]
    return ((n - k) * v - pc[n - k] - (pc[n] - pc[k])) / n


def trapezoid(m, M):
    """Flat-top lag window lambda_0..lambda_M: 1 up to lag m, linear to 0 at M."""
    k = np.arange(M + 1, dtype=float)
    lam = np.clip((M - k) / max(M - m, 1), 0.0, 1.0)
    lam[k <= m] = 1.0
    return lam


def _two(M):
    """Weights of lags 0..M in a sum over -M..M."""
    return np.where(np.arange(M + 1) == 0, 1.0, 2.0)


def window_sum(gamma, lam, n):
    """N Var(mean) estimated with lag window `lam`: sum_|k|<=M lambda_k (gamma_hat(k) - e_k), the
    e_k those of the windowed estimate itself (iterated to its fixed point)."""
    M = len(lam) - 1
    k = np.arange(M + 1)
    g = np.asarray(gamma[:M + 1], dtype=float)
    w = _two(M) * lam
    e = np.zeros(M + 1)
    sums = []
    for _ in range(BIAS_ITERATIONS):
        e = mean_subtraction_bias(lam * (g - e) / (1 - k / n), n, M + 1)
        sums.append(float(np.sum(w * (g - e))))
    # The map is linear and its sum converges geometrically with one ratio (about Lambda/N,
    # module docstring 5) from the first step: Aitken's delta-squared gives the limit.
    s0, s1, s2 = sums[-3:]
    ratio = (s2 - s1) / (s1 - s0) if s1 != s0 else 0.0
    return s2 + (s2 - s1) * ratio / (1 - ratio) if 0 < ratio < 1 else s2


def corrected_autocorrelation(gamma, n, lags):
    """The autocorrelation at lags 0..lags-1 with the mean's subtraction undone (4), taking as
    the series' autocovariance its estimate up to its own first zero (iterated)."""
    g = np.asarray(gamma, dtype=float)
    lags = min(lags, n)
    e = np.zeros(lags)
    for _ in range(4):
        r = g[:lags] - e
        z = int(np.argmax(r[1:] < 0)) + 1 if np.any(r[1:] < 0) else lags
        k = np.arange(z)
        e = mean_subtraction_bias(r[:z] / (1 - k / n), n, lags)
    r = g[:lags] - e
    return r / r[0]


def first_lobe(rho, lag_max):
    """(z1, z2): the first lag where rho < 0 and the first after it where rho >= 0, both at most
    lag_max; None for either not found."""
    rho = np.asarray(rho, dtype=float)[:int(lag_max) + 1]
    neg = np.flatnonzero(rho[1:] < 0)
    if not len(neg):
        return None, None
    z1 = int(neg[0]) + 1
    back = np.flatnonzero(rho[z1:] >= 0)
    return z1, (z1 + int(back[0]) if len(back) else None)


def mean_error(x):
    """MeanError of a series: its mean, the standard error of the mean, its dof, the window and
    whether the correlations were resolved (module docstring). NaN error below MIN_SAMPLES."""
    x = np.asarray(x, dtype=float)
    n = len(x)
    mean = float(x.mean()) if n else math.nan
    if n < MIN_SAMPLES or not np.all(np.isfinite(x)):
        return MeanError(mean, math.nan, math.nan, 0, False)
    gamma = autocovariance(x)
    if not gamma[0] > 0:                         # a constant series: exactly its mean
        return MeanError(mean, 0.0, n - 1.0, 0, False)
    search = int(n * LOBE_SEARCH)
    rho = corrected_autocorrelation(gamma, n, search + 1)
    z1, z2 = first_lobe(rho, search)
    found = z2 is not None
    m = z2 if found else max(search, 1)
    error, dof, M = _windowed(gamma, n, m, min(2 * m, n - 1))
    plateau = found and M * PLATEAU_WINDOWS <= n and error > 0   # NaN error: a sum not positive
    if not plateau:   # unresolved: the larger with the window up to the first zero (module doc, 7)
        bound, bound_dof, _ = _windowed(gamma, n, z1 or max(search, 1), z1 or max(search, 1))
        if not error >= bound:
            error, dof = bound, bound_dof
    if not error > 0:
        return MeanError(mean, math.sqrt(gamma[0] / (n - 1)), n - 1.0, M, False)
    return MeanError(mean, error, dof, M, bool(plateau))


def _windowed(gamma, n, m, M):
    """(error, dof, M) of the trapezoid window (m, M) (module docstring, 3-5); NaN error when
    its sum is not positive."""
    lam = trapezoid(m, M)
    s = window_sum(gamma, lam, n)
    two = _two(M)
    kept = 1 - np.sum(two * lam * (1 - np.arange(M + 1) / n)) / n
    dof = max(n / np.sum(two * lam ** 2) * kept, 1.0)
    return (math.sqrt(s / n) if s > 0 else math.nan), float(dof), int(M)


def rescaled_error(error, n_from, n_to):
    """The standard error of the mean of n_to samples of a series whose n_from samples have
    `error`: the same long-run variance, N Var(mean), over more (or fewer) samples."""
    return error * math.sqrt(n_from / n_to) if n_to > 0 else math.nan
