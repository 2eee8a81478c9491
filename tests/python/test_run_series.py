"""The drag from a run file's force series (analysis.runs.run_series, through analysis.runs.runs): the
cumulative average checked against the series, the first travel of a pull (window_drag), and a
real pull's errors against the engine's (tests/python/engine_estimator.py)."""
import math
import subprocess

import h5py
import numpy as np
import pytest
from test_runs import BED, BINARY, write_run

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
