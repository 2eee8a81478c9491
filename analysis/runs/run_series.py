"""A pull's drag from its recorded force series (run file /observables/intruder_force): both
averagings, each with its error from analysis.runs.series_error.

- The steady drag: the mean of -F_x over the samples after the transient the engine discarded
  (/observables/drag attribute transient_samples), the table's `drag`. Its error, dof and
  convergence flag are series_error.mean_error's of those samples (the table's `drag_err`,
  `drag_dof`, `plateau`); the engine's own (/observables/drag error, plateau) are kept beside.
- The cumulative average from t = 0 (the paper's Fig. 4: the running mean of -F_x over every
  sample, its last value; the table's `drag_cumulative`). The run file stores the running mean
  (/observables/cumulative_drag/value); its last element must be the mean of the force series,
  or the file is refused.

The cumulative average's error (`drag_cumulative_err`) is the steady series' long-run variance
(N Var(mean), series_error) spread over all the samples: error_steady sqrt(N_steady/N_all). The
start-up (the drag rising from rest, at speed an impact peak) is a trend, the same in every bed
pulled the same way: it moves the cumulative average (that is what the paper's averaging
measures) but is not noise of one pull, while the fluctuations about it are of the kind after
it. The estimator applied to the whole series would read the trend as a long correlation and
widen the error by the trend's size (a stiff pull, K_n = 2e6, D = 2, Fr = 3, 20 d: 2.1 times;
its first samples, the impact of the start, are ten times its steady drag). What bed-to-bed differences there are in the
start-up are in the point table's scatter between beds, as for the steady drag.

The paper pulls one box length and averages over all of it, so the start's excess in its average is
diluted over the box, E / L_box. A pull of another length L dilutes it over L: the same bed pulled 20 d
and 40 d reads cumulative averages that differ by E/40 (about 0.3 % of the drag at Fr 2, 4 % at Fr 15
at K_n = 2e6), and a drag curve whose fast speeds were pulled longer than its slow ones steps where the
length changes. `box_cumulative` therefore gives the cumulative average at the paper's length (the
table's `drag_cumulative_box`): over the first box length when the pull is that long, else the steady
drag plus the start's excess spread over one box length, S + (C - S) L / L_box, which assumes the drag
stays at its steady value past the pull's end. Checked on 40 d pulls read over their first 20 d
(tools/box_average_check.py): within their errors, but the drag relaxes along a pull (its second
20 d read 2-3 % below its first), so the extrapolation reads about 1.5 % high.

`first_travel` gives both over the first travel_max d of a pull (analysis.runs.runs.window_drag: a
40 d pull's first 20 d against its whole). The error of kappa from the intruder coordination
series is here too (`kappa_error`). analysis.runs.runs reads the file and turns SeriesError into its
RunFileError.
"""
import math

import numpy as np

from .series_error import mean_error, rescaled_error


class SeriesError(ValueError):
    """A run file whose force series is unusable; the message names the file and why."""


def read_series(f, path):
    """(t, drag_t, skip, speed) of an open run file: interval end times, -F_x per sample
    interval, the samples in the transient, the pulling speed. Checks the stored cumulative
    average against the series (SeriesError when they disagree); files without one pass."""
    try:
        t = np.asarray(f["observables/intruder_force/time"][()], dtype=float)
        force = np.asarray(f["observables/intruder_force/value"][()], dtype=float)
        skip = int(f["observables/drag"].attrs["transient_samples"])
        speed = float(f["run"].attrs["speed"])
    except (KeyError, TypeError, ValueError) as exc:
        raise SeriesError(f"{path}: damaged run file: force series: {exc}") from None
    if force.ndim != 2 or force.shape[1] != 3 or len(t) != len(force):
        raise SeriesError(f"{path}: damaged run file: /observables/intruder_force/value is "
                      f"{force.shape}, time {t.shape}: not one (F_x, F_y, F_z) per sample")
    drag_t = -force[:, 0]
    if "observables/cumulative_drag/value" in f and len(drag_t):
        stored = np.asarray(f["observables/cumulative_drag/value"][()], dtype=float)
        mean = float(drag_t.mean())
        last = float(stored[-1]) if stored.size else math.nan
        failed = not (math.isfinite(mean) or math.isfinite(last))   # a pull without a drag: runs says so
        if not failed and (stored.shape != drag_t.shape or not math.isclose(
                last, mean, rel_tol=1e-9, abs_tol=1e-9 * float(np.abs(drag_t).max()))):
            raise SeriesError(f"{path}: the cumulative drag (/observables/cumulative_drag/value, last "
                          f"{last:.10g} of {stored.size}) is not the mean of -F_x over the force series "
                          f"({mean:.10g} of {len(drag_t)} samples): the file's series disagree")
    return t, drag_t, max(skip, 0), speed


def drags(drag_t, skip):
    """The steady drag (after `skip` samples) and the cumulative average (all samples), with
    errors: {drag_series, drag_err, drag_dof, plateau, window, drag_cumulative,
    drag_cumulative_err, samples, steady_samples}."""
    drag_t = np.asarray(drag_t, dtype=float)
    steady = mean_error(drag_t[skip:])
    n, n_steady = len(drag_t), max(len(drag_t) - skip, 0)
    return {"drag_series": steady.mean, "drag_err": steady.error, "drag_dof": steady.dof,
            "plateau": steady.plateau, "window": steady.window,
            "drag_cumulative": float(drag_t.mean()) if n else math.nan,
            "drag_cumulative_err": rescaled_error(steady.error, n_steady, n) if n_steady else math.nan,
            "samples": n, "steady_samples": n_steady}


def first_travel(t, drag_t, skip, speed, travel_max):
    """drags over the first `travel_max` d of a pull (read_series's t, drag_t, skip, speed): the
    steady drag after the engine's transient and the cumulative average from t = 0, with
    `travel`, the travel of the last sample kept (a sample's travel is its interval's end time
    times the speed), and `travel_max`. The steady drag (and its error) is NaN when travel_max
    ends within the transient."""
    keep = int(np.searchsorted(np.asarray(t, dtype=float) * speed, travel_max * (1 + 1e-9), side="right"))
    out = drags(drag_t[:keep], min(skip, keep))
    out["travel"] = float(t[keep - 1] * speed) if keep else 0.0
    out["travel_max"] = float(travel_max)
    return out


def box_cumulative(t, drag_t, skip, speed, box_length):
    """(value, error) of the paper's cumulative average over one box length (module docstring), from
    read_series's t, drag_t, skip, speed. Error: the measured cumulative's when the pull is a box
    length; else (1 - f) σ_S + f σ_C, f = L / L_box, the steady and cumulative errors taken as fully
    correlated (the same steady samples drive both; the larger bound). NaN without a box length or
    a steady sample."""
    t, drag_t = np.asarray(t, dtype=float), np.asarray(drag_t, dtype=float)
    travel = float(t[-1] * speed) if len(t) else 0.0
    if not (math.isfinite(box_length) and box_length > 0 and travel > 0):
        return math.nan, math.nan
    if travel >= box_length * (1 - 1e-3):   # a box length within a sample's rounding, or longer
        w = first_travel(t, drag_t, skip, speed, box_length)
        return w["drag_cumulative"], w["drag_cumulative_err"]
    whole = drags(drag_t, skip)
    if not whole["steady_samples"]:
        return math.nan, math.nan
    f = travel / box_length
    s, c = whole["drag_series"], whole["drag_cumulative"]
    return s + f * (c - s), (1 - f) * whole["drag_err"] + f * whole["drag_cumulative_err"]


def block_error(x, min_blocks=8):
    """Standard error of the mean of a correlated series by block averaging: the largest
    standard error over pairwise blocking levels that keep at least min_blocks blocks."""
    x = np.asarray(x, float)
    best = np.std(x, ddof=1) / np.sqrt(len(x)) if len(x) > 1 else math.nan
    while len(x) >= 2 * min_blocks:
        x = 0.5 * (x[: len(x) // 2 * 2 : 2] + x[1 : len(x) // 2 * 2 : 2])
        best = max(best, np.std(x, ddof=1) / np.sqrt(len(x)))
    return float(best)


def kappa_error(obs, kappa, n, t0):
    """Error of kappa = (Z/n)(D+d)^2/(2 sqrt(3)) from the standard error of the intruder
    coordination n: the engine's (/observables/coordination error, the drag's estimator),
    or, in run files written before it was stored, block averaging of the stored series
    (/observables/intruder_contacts, samples after the transient). The bulk Z has no
    series in the file, so its sampling error is not included. NaN when unavailable."""
    if not (math.isfinite(kappa) and n > 0):
        return math.nan
    n_err = obs["coordination"].attrs.get("error", math.nan) if "coordination" in obs else math.nan
    if math.isfinite(float(n_err)):
        return abs(kappa) * float(n_err) / n
    try:
        g = obs["intruder_contacts"]
        t, c = g["time"][()], g["value"][()].astype(float)
    except KeyError:
        return math.nan
    c = c[t > t0]
    if len(c) < 2:
        return math.nan
    return abs(kappa) * block_error(c) / n
