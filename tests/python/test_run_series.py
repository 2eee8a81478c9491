"""The drag from a run file's force series (analysis.runs.run_series, through analysis.runs.runs): the
cumulative average checked against the series, the first travel of a pull (window_drag), and a
real pull's errors against the engine's (tests/python/engine_estimator.py)."""
import math
import subprocess

import h5py
import numpy as np
import pytest
from test_runs import BED, BINARY, write_run

from analysis.runs.run_series import box_cumulative, drags
from analysis.runs.runs import RunFileError, read_run, window_drag
from analysis.runs.series_error import mean_error


def test_a_cumulative_drag_that_is_not_the_force_series_mean_is_refused(tmp_path):
    p = write_run(tmp_path / "pulls" / BED / "Fr~1" / "run.h5")
    with h5py.File(p, "a") as f:
        f["observables/cumulative_drag/value"][-1] += 1e-3
    with pytest.raises(RunFileError, match=r"run\.h5: the cumulative drag .* is not the mean of -F_x over the "
                                           r"force series .*the file's series disagree"):
        read_run(p)
    with h5py.File(p, "a") as f:        # a file without it (or before it was recorded) is read
        del f["observables/cumulative_drag"]
    assert math.isfinite(read_run(p)["drag_cumulative"])


def test_window_drag_takes_the_first_travel_of_a_pull(tmp_path):
    # 200 samples every 0.02 at V = 0.75: 0.015 d each, the transient 10 samples (0.15 d).
    p = write_run(tmp_path / "system~I" / "run.h5", n_samples=200)
    with h5py.File(p) as f:
        drag_t = -f["observables/intruder_force/value"][:, 0]
    whole, first = window_drag(p, 1e9), window_drag(p, 1.5)
    row = read_run(p)
    assert whole["samples"] == 200 and whole["drag_err"] == row["drag_err"]
    assert whole["drag_cumulative"] == row["drag_cumulative"] and whole["travel"] == pytest.approx(3.0)
    assert first["samples"] == 100 and first["travel"] == pytest.approx(1.5)
    assert first["drag_series"] == pytest.approx(drag_t[10:100].mean())
    assert first["drag_err"] == mean_error(drag_t[10:100]).error
    assert first["drag_cumulative"] == pytest.approx(drag_t[:100].mean())
    assert first["drag_cumulative_err"] == pytest.approx(first["drag_err"] * np.sqrt(90 / 100))
    inside = window_drag(p, 0.1)                    # within the transient: no steady drag
    assert inside["samples"] == 6 and math.isnan(inside["drag_series"]) and math.isnan(inside["drag_err"])
    assert inside["drag_cumulative"] == pytest.approx(drag_t[:6].mean())


def _pull_series(n, skip=10, level=1000.0, noise=0.0, seed=0):
    """A pull's drag series: a start of `skip` samples that decays from 10x the level, then the level
    (plus white noise of `noise`)."""
    rng = np.random.default_rng(seed)
    start = level * (1 + 9 * np.exp(-np.arange(skip) / 3.0))
    return np.concatenate([start, level + noise * rng.standard_normal(n - skip)])


def test_the_box_length_average_of_a_half_pull_is_the_whole_pulls_when_the_drag_stays_steady():
    """The paper's cumulative average over one box length (box_cumulative): a pull of the box reads
    its own cumulative average, a longer one its first box length's, and a pull of half the box
    the steady drag plus its start's excess spread over the box, which for a drag that stays at
    its steady value is the whole box's average exactly."""
    V, dt = 1.0, 0.02                                  # 0.02 d per sample: 2,000 samples to 40 d
    drag_t = _pull_series(2000)
    t = dt * np.arange(1, 2001)
    whole = box_cumulative(t, drag_t, 10, V, 40.0)
    assert whole == (pytest.approx(drag_t.mean(), rel=1e-12), drags(drag_t, 10)["drag_cumulative_err"])
    assert box_cumulative(t, drag_t, 10, V, 20.0)[0] == pytest.approx(drag_t[:1000].mean(), rel=1e-12)
    half = box_cumulative(t[:1000], drag_t[:1000], 10, V, 40.0)
    assert half[0] == pytest.approx(drag_t.mean(), rel=1e-12)
    # The plain cumulative average of the half pull holds twice the start's excess.
    assert drag_t[:1000].mean() - 1000 == pytest.approx(2 * (drag_t.mean() - 1000), rel=1e-12)
    assert all(math.isnan(v) for v in box_cumulative(t, drag_t, 10, V, math.nan))


def test_the_box_length_average_of_a_noisy_half_pull_agrees_within_its_error():
    """With noise, the half pull's extrapolation and the whole pull's measured average differ by
    the noise of the unpulled half: within 3 of the extrapolation's error in each of 20 pulls,
    whose error (1 - f) σ_S + f σ_C is between the two it mixes."""
    V, dt = 1.0, 0.02
    t = dt * np.arange(1, 2001)
    for seed in range(20):
        drag_t = _pull_series(2000, noise=50.0, seed=seed)
        value, err = box_cumulative(t[:1000], drag_t[:1000], 10, V, 40.0)
        half = drags(drag_t[:1000], 10)
        assert half["drag_cumulative_err"] <= err <= half["drag_err"]
        assert err == pytest.approx(0.5 * half["drag_err"] + 0.5 * half["drag_cumulative_err"])
        assert abs(value - drag_t.mean()) < 3 * err, seed


def test_the_table_reads_the_box_length_average(tmp_path):
    p = write_run(tmp_path / "system~I" / "run.h5", n_samples=200)
    row = read_run(p)
    with h5py.File(p) as f:
        t = f["observables/intruder_force/time"][()]
        drag_t = -f["observables/intruder_force/value"][:, 0]
        skip = int(f["observables/drag"].attrs["transient_samples"])
        speed = float(f["run"].attrs["speed"])
    expected = box_cumulative(t, drag_t, skip, speed, row["lx"])
    assert row["distance"] < row["lx"]            # a pull shorter than its box: extrapolated
    assert (row["drag_cumulative_box"], row["drag_cumulative_box_err"]) == expected
    assert row["drag_cumulative_box"] != row["drag_cumulative"]


def test_the_engine_error_oracle_and_the_readers_agree_with_a_real_pull(tmp_path):
    """A real pour and a 3 d pull: the engine's errors of the drag over its prefixes
    (/observables/drag/convergence) are tests/python/engine_estimator.py's, to 1e-9; the
    stored cumulative average ends at the force series' mean, and read_run's drag error is
    analysis.runs.series_error's of the series after the engine's transient."""
    from engine_estimator import engine_error
    subprocess.run([str(BINARY), "pour", "--output", str(tmp_path / "bed.h5"), "--grains", "150",
                    "--lx", "5", "--ly", "4.5", "--intruder_diameter", "1.5", "--depth", "1.5",
                    "--kn", "2e4", "--max_settle_time", "0.5", "--quiet"], check=True, capture_output=True)
    run = tmp_path / "system~I" / "run.h5"
    run.parent.mkdir()
    subprocess.run([str(BINARY), "pull", "--bed", str(tmp_path / "bed.h5"), "--output", str(run),
                    "--distance", "3", "--speed", "1", "--snapshots", "0", "--quiet"], check=True,
                   capture_output=True)
    with h5py.File(run) as f:
        drag_t = -f["observables/intruder_force/value"][:, 0]
        skip = int(f["observables/drag"].attrs["transient_samples"])
        conv = {k: f["observables/drag/convergence"][k][()] for k in ("samples", "error", "dof", "plateau")}
        stored = f["observables/drag"].attrs["error"]
    assert len(conv["samples"]) >= 8
    for n, err, dof, plateau in zip(*conv.values()):
        assert engine_error(drag_t[skip:skip + n]) == (pytest.approx(err, rel=1e-9), pytest.approx(dof, rel=1e-9),
                                                       bool(plateau))
    row = read_run(run)
    assert row["drag_err_engine"] == stored and row["drag_err"] == mean_error(drag_t[skip:]).error
    assert row["drag_cumulative"] == pytest.approx(drag_t.mean(), rel=1e-12)
