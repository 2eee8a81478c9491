"""analysis.validation.pull_length: the travel from which a pull's drag and error hold, per regime."""
import h5py
import numpy as np
import pandas as pd
import pytest

from analysis.validation import pull_length as pl
from analysis.validation import validation as val

# Drag of the first L d: converges to 100, error 10/sqrt(L) (a 5 % error at L = 4).
TRAVEL = np.array([0.5, 1, 2, 4, 8, 16])
VALUE = np.array([130, 120, 101, 100, 100.5, 100])
ERROR = 10 / np.sqrt(TRAVEL)


def conv(plateau):
    return pd.DataFrame(dict(samples=(TRAVEL * 100).astype(int), travel=TRAVEL, value=VALUE, error=ERROR,
                             dof=TRAVEL * 3, plateau=np.array(plateau, bool)))


def test_min_distance_is_where_every_longer_prefix_agrees_with_the_whole_pull():
    rows = pl.prefixes(conv([0, 0, 1, 1, 1, 1]))
    # The rest of the pull after L has the error e sqrt(T/L - 1), e = 2.5 the whole pull's:
    # L = 1: 20/(2.5 sqrt(15)) = 2.07 disagrees; L = 2: 1/(2.5 sqrt(7)) agrees.
    assert rows.z.iloc[1] == pytest.approx(20 / (2.5 * np.sqrt(15)))
    assert list(rows.agrees) == [False, False, True, True, True, True]
    assert pl.min_distance(rows) == 2 and pl.converged_from(rows) == 2
    later = pl.prefixes(conv([0, 0, 0, 1, 1, 1]))
    assert pl.min_distance(later) == 2 and pl.converged_from(later) == 4   # the error converges later
    assert np.isnan(pl.converged_from(pl.prefixes(conv([1, 1, 1, 1, 1, 0]))))  # not the whole pull's
    # An error far below the whole pull's 2.5 sqrt(16/2) = 7.1 at L = 2: too small to stop on.
    small = pl.prefixes(conv([1] * 6).assign(error=np.where(TRAVEL == 2, 1.0, ERROR)))
    assert small.error_ratio.iloc[2] == pytest.approx(1 / 7.0711, rel=1e-4) and not small.honest.iloc[2]
    assert pl.min_distance(small) == 4
    drifting = pl.prefixes(conv([1] * 6).assign(value=[130, 120, 115, 110, 108, 100]))
    assert not drifting.agrees.iloc[4]                  # 8/(2.5 sqrt(1)) = 3.2
    assert np.isnan(pl.min_distance(drifting))          # only the whole pull agrees with itself


def test_target_distance_is_measured_or_extrapolated_as_one_over_root_travel():
    rows = pl.prefixes(conv([0, 0, 1, 1, 1, 1]))
    assert pl.target_distance(rows, 0.05) == (4.0, True)               # 10/sqrt(4)/100 = 5 %
    # 1 %: never reached; the whole pull has 2.5 % at 16 d, so 16 (2.5)^2 = 100 d.
    L, measured = pl.target_distance(rows, 0.01)
    assert L == pytest.approx(100) and not measured


def series(tau, transient, F=100.0, amplitude=1.0, noise=2.0, travel=16.0, step=0.01, seed=0):
    rng = np.random.default_rng(seed)
    x = np.arange(1, int(travel / step) + 1) * step
    return dict(travel=x, drag=F * (1 + amplitude * np.exp(-x / tau)) + noise * rng.standard_normal(len(x)),
                transient=transient)


def test_settling_finds_where_the_drag_enters_the_steady_band():
    # The excess decays as exp(-x/tau); windows of transient/2 = 1.5 d with 150 samples each
    # average the noise to 2/sqrt(150) = 0.16: the band is about +-0.33 of 100.
    fast, width, step = pl.settling(series(tau=0.3, transient=3))
    assert width == pytest.approx(1.5) and step == pytest.approx(0.01)
    assert fast <= 3                                         # settled within the transient
    slow, _, _ = pl.settling(series(tau=1.5, transient=3))
    # The window from s has a mean excess 100 (tau/w) exp(-s/tau) (1 - exp(-w/tau)) = 63 exp(-s/1.5),
    # which falls below the band's 0.33 at s = 1.5 ln(191) = 7.9 d: windows start at 0, 1.5, ...,
    # so 9 d, or the start before or after it as the noise moves the band.
    assert slow in (7.5, 9.0, 10.5)
    # Under 3 windows in the second half: no band, so no answer (said, not guessed).
    short, _, _ = pl.settling(series(tau=0.3, transient=3, travel=8))
    assert np.isnan(short)


def write_run(path, plateau, speed=0.375, transient=3.0, tau=0.3):
    s = series(tau=tau, transient=transient)
    c = conv(plateau)
    with h5py.File(path, "w") as f:
        f.create_group("run").attrs["speed"] = speed
        g = f.create_group("observables/drag/convergence")
        for k in c.columns:
            g[k] = c[k].to_numpy().astype(np.int64 if k in ("samples", "plateau") else float)
        f["observables/drag"].attrs["transient_distance"] = transient
        force = np.zeros((len(s["drag"]), 3))
        force[:, 0] = -s["drag"]
        f["observables/intruder_force/time"] = s["travel"] / speed
        f["observables/intruder_force/value"] = force


def runs_table(tmp_path):
    rows = []
    for Fr, plateau in ((0.5, [0, 0, 1, 1, 1, 1]), (2.0, [0, 0, 0, 1, 1, 1])):
        for seed in (1, 2):
            p = tmp_path / f"Fr{Fr}_seed{seed}.h5"
            write_run(p, plateau)
            rows.append(dict(path=str(p), Fr=Fr, V=Fr * 0.75, D=2.0, mu=0.5, seed=seed, sanity="clean"))
    return pd.DataFrame(rows)


def test_study_answers_per_regime_and_validate_writes_its_files(tmp_path):
    runs = runs_table(tmp_path)
    rows, answers = pl.study(runs)
    assert len(rows) == 4 * len(TRAVEL)
    assert list(answers.regime) == ["mu = 0.5, Fr = 0.5", "mu = 0.5, Fr = 2"]
    assert list(answers.min_distance) == [2, 2] and list(answers.converged_from) == [2, 4]
    assert list(answers.beds) == [2, 2]
    assert answers.transient_enough.all() and answers.transient_checked.all()
    text = pl.conclusion(answers)
    assert "mu = 0.5, Fr = 2 (2 beds): min_distance 2 d, error converged from 4 d; 5 % error after 4 d" in text, text
    paths = val.validate(runs, "pull_length", tmp_path / "out")
    assert sorted(p.name for p in paths) == ["validate_pull_length.csv", "validate_pull_length.md",
                                             "validate_pull_length.pdf", "validate_pull_length.png"]
    assert (tmp_path / "out" / "validate_pull_length.png").stat().st_size > 5000
    assert "min_distance 2 d" in (tmp_path / "out" / "validate_pull_length.md").read_text()
    back = pd.read_csv(tmp_path / "out" / "validate_pull_length_answers.csv")
    assert list(back.converged_from) == [2, 4]


def test_a_run_file_without_the_convergence_table_is_named(tmp_path):
    old = tmp_path / "old.h5"
    with h5py.File(old, "w") as f:
        f.create_group("observables/drag")
    runs = pd.DataFrame([dict(path=str(old), Fr=1.0, V=1.0, D=2.0, mu=0.5, seed=1)])
    with pytest.raises(val.ValidationError, match="old.h5: no /observables/drag/convergence"):
        pl.study(runs)
    with pytest.raises(val.ValidationError, match="no 'path' column"):
        pl.study(runs.drop(columns="path"))
