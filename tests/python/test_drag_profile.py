"""analysis.drag_profile: the drag in windows of travel and the drag of a pull's late part, against
analytic means of a decaying start."""
import math

import h5py
import numpy as np
import pandas as pd
import pytest

from analysis import drag_profile as dp

STEP = 0.05    # d of travel per force sample


def decaying(travel=20.0, steady=1000.0, excess=4000.0, tau=2.0, noise=0.0, seed=0):
    """A pull's force series whose start decays: drag = steady + excess exp(-x / tau) (+ noise)."""
    x = np.arange(1, int(round(travel / STEP)) + 1) * STEP
    rng = np.random.default_rng(seed)
    return x, steady + excess * np.exp(-x / tau) + noise * rng.standard_normal(len(x))


def window_mean(lo, hi, steady=1000.0, excess=4000.0, tau=2.0):
    """The exact mean of the samples in (lo, hi] of decaying()'s series (a geometric sum)."""
    x = np.arange(1, int(round(20.0 / STEP)) + 1) * STEP
    inside = (x > lo) & (x <= hi + 1e-9)
    return float(np.mean(steady + excess * np.exp(-x[inside] / tau)))


def integral_mean(lo, hi, steady=1000.0, excess=4000.0, tau=2.0):
    """The continuous mean of decaying()'s drag over (lo, hi]: steady + excess tau (e^-lo/tau -
    e^-hi/tau) / (hi - lo); the samples' mean (right ends of their intervals) is within 0.2 % of it at STEP."""
    return steady + excess * tau * (math.exp(-lo / tau) - math.exp(-hi / tau)) / (hi - lo)


def test_windows_hold_the_mean_of_their_samples():
    x, drag = decaying()
    w = dp.windows(x, drag, 2.0)
    assert list(w.x_lo) == [2.0 * k for k in range(10)] and (w.samples == 40).all()
    assert w.drag.to_numpy() == pytest.approx([window_mean(lo, lo + 2) for lo in w.x_lo])
    # The decay shows: the first window far above the steady drag, the last within 0.2 % of it.
    assert w.drag.iloc[0] > 2.5 * 1000 and w.drag.iloc[-1] == pytest.approx(1000, rel=2e-3)
    # Only whole windows: 19 d of travel in 2 d windows is 9 of them.
    assert len(dp.windows(x[x <= 19.0], drag[x <= 19.0], 2.0)) == 9


def test_late_drag_leaves_the_start_behind_and_its_error_is_the_batch_means():
    x, drag = decaying()
    mean, err = dp.late_drag(x, drag, 8.0, 2.0)
    # Analytic: 1000 + 4000 <exp(-x/2)> over x in (8, 20], 1.2 % above the steady drag.
    assert mean == pytest.approx(integral_mean(8.0, 20.0), rel=2e-3) and 1000 < mean < 1015
    batches = dp.windows(x[x > 8] - 8, drag[x > 8], 2.0).drag
    assert err == pytest.approx(batches.std(ddof=1) / math.sqrt(6))
    # The table's drag after a 3 d transient keeps part of the start: 10.5 % high here.
    assert float(drag[x > 3.0].mean()) == pytest.approx(integral_mean(3.0, 20.0), rel=2e-3)
    assert integral_mean(3.0, 20.0) / 1000 == pytest.approx(1.105, abs=1e-3)
    assert math.isnan(dp.late_drag(x, drag, 17.0, 2.0)[1])       # one window: no error


def write_run(path, x, drag, speed=2.0, transient=3.0):
    """A run file with what drag_profile reads: the force series, the speed, the transient, and
    the convergence table read_convergence requires."""
    with h5py.File(path, "w") as f:
        f.create_group("run").attrs["speed"] = speed
        g = f.create_group("observables/drag/convergence")
        for k in ("samples", "travel", "value", "error", "dof", "plateau"):
            g[k] = np.ones(2)
        f["observables/drag"].attrs["transient_distance"] = transient
        force = np.zeros((len(x), 3))
        force[:, 0] = -drag
        f["observables/intruder_force/time"] = x / speed
        f["observables/intruder_force/value"] = force


def test_compare_sets_the_late_drag_against_the_tables_over_the_beds(tmp_path):
    rows = []
    for Fr, excess in ((1.0, 0.0), (10.0, 4000.0)):
        for seed in (1, 2):
            x, drag = decaying(excess=excess, noise=50.0, seed=seed)
            p = tmp_path / f"Fr{Fr}_seed{seed}.h5"
            write_run(p, x, drag)
            table = float(drag[x > 3.0].mean())
            rows.append(dict(path=str(p), D=3.0, Fr=Fr, seed=seed, V=2.0, drag=table, drag_err=20.0))
    runs = pd.DataFrame(rows)
    late = dp.compare(runs, late_from=8.0, width=2.0)
    assert list(late.Fr) == [1.0, 10.0] and (late.beds == 2).all()
    slow, fast = late.iloc[0], late.iloc[1]
    assert slow.ratio == pytest.approx(1.0, abs=0.01) and abs(slow.z) < 2
    # The start the table kept: late / table = integral_mean(8, 20) / integral_mean(3, 20), noise aside.
    assert fast.ratio == pytest.approx(integral_mean(8.0, 20.0) / integral_mean(3.0, 20.0), abs=0.01)
    assert fast.z < -2
    assert fast.drag == pytest.approx(runs[runs.Fr == 10].drag.mean())
    prof = dp.profiles(runs, 2.0)
    assert len(prof) == 4 * 10 and set(prof.seed) == {1, 2}


def test_the_command_writes_its_tables_and_names_a_table_that_is_not_a_runs_csv(tmp_path, capsys):
    x, drag = decaying()
    write_run(tmp_path / "run.h5", x, drag)
    pd.DataFrame([dict(path=str(tmp_path / "run.h5"), D=3.0, Fr=5.0, seed=1, V=2.0, drag=1500.0,
                       drag_err=30.0)]).to_csv(tmp_path / "runs.csv", index=False)
    assert dp.main([str(tmp_path / "runs.csv"), "--output-dir", str(tmp_path / "out")]) == 0
    assert len(pd.read_csv(tmp_path / "out" / "drag_profile.csv")) == 10
    assert pd.read_csv(tmp_path / "out" / "drag_late.csv").late_drag.iloc[0] == pytest.approx(
        float(drag[x > 8].mean()))
    pd.DataFrame([dict(D=3.0, Fr=5.0)]).to_csv(tmp_path / "bad.csv", index=False)
    with pytest.raises(SystemExit):
        dp.main([str(tmp_path / "bad.csv")])
    assert "has no column(s) ['drag', 'drag_err', 'path', 'seed']" in capsys.readouterr().err
