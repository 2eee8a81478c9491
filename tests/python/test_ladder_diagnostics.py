"""analysis.ladder.ladder's diagnostics: parsing fitted numbers, the kappa shell slopes and their
decomposition, the start of each pull kept as the paper's cumulative average, the Fr_2-range
refits, the broken line and the knee at Fr 5."""
import numpy as np
import pandas as pd
import pytest
import synth
from test_ladder import FR, SHELL_SLOPES, point_table, shell_table

from analysis.fits.fits import evaluate, fit_broken_line
from analysis.ladder.ladder import (
    fr2_vs_range,
    inside_box,
    kappa_decomposition,
    kappa_shell_slopes,
    kept_drag,
    knee_at_five,
    parse_fitted,
    startup_refit,
)


def test_parse_fitted():
    assert parse_fitted("1.23 ± 0.05") == (1.23, 0.05)
    assert parse_fitted("μ_c = -0.12 ± 0.03") == (-0.12, 0.03)
    v, e = parse_fitted("1.234")
    assert v == 1.234 and np.isnan(e)
    assert all(np.isnan(parse_fitted("n/a")))


# --- diagnostics ---------------------------------------------------------------

def test_kappa_shell_slopes_recover_a_known_slope():
    s = kappa_shell_slopes(shell_table(seed=3))
    for w, k1 in SHELL_SLOPES:
        row = s[(s.D == "all") & (s.width == w)].iloc[0]
        # Stated tolerance: 3 standard errors, and an error small enough to mean something.
        assert abs(row.k1 - k1) < 3 * row.k1_err and row.k1_err < 0.01, row
        assert abs(row.k0 - 0.9) < 3 * row.k0_err
        assert row.n_points == 20 and row.n_runs == 60         # 2 D x 10 Fr, 3 beds averaged; μ = 0 left out
        assert row.errors_from.startswith("between-bed")
    per_d = s[(s.D == "2") & (s.width == 1.0)].iloc[0]
    assert per_d.n_points == 10 and abs(per_d.k1 - 0.2) < 3 * per_d.k1_err


def test_kappa_shells_at_one_speed_per_d_are_not_studied():
    # A yield and depth sweep pulls system I at μ = 0.5 only at its yield speed, one Fr per D:
    # a line through those three κ (scaling-k2e4-box20's shells gave slopes of 17-29) measures
    # nothing of Eq. 8, and the shell table leaves the rung out, as the report does.
    t = shell_table(seed=3)
    one_speed = t[np.isclose(t.Fr, 1.0)].assign(Fr=lambda d: d.Fr * (1 + 0.1 * d.D))   # 2 Fr, one per D
    both = pd.concat([t.assign(rung="swept"), one_speed.assign(rung="yield-sweep")])
    s = kappa_shell_slopes(both)
    assert set(s.rung) == {"swept"}
    # Four speeds per D are still too few; five are enough.
    few = t[t.Fr.isin([1, 2, 3, 4])]
    assert kappa_shell_slopes(few).empty and len(kappa_shell_slopes(t[t.Fr.isin([1, 2, 3, 4, 5])]))


def test_shells_that_wrap_around_the_periodic_box_are_left_out():
    # D = 3 in a 12 d box: R + w must stay within 6 d, so widths 5 and 6 go; in 20 d all stay.
    rows = pd.DataFrame([dict(D=3.0, width=w, lx=L, ly=L) for L in (12.0, 20.0) for w in (0.5, 4.0, 4.5, 5.0, 6.0)])
    kept = inside_box(rows)
    assert sorted(kept[kept.lx == 12.0].width) == [0.5, 4.0, 4.5]
    assert len(kept[kept.lx == 20.0]) == 5
    assert len(inside_box(rows.drop(columns=["lx", "ly"]))) == len(rows)   # files without the box: kept


def test_kappa_decomposition_takes_the_ratios_at_the_nearest_froude_numbers():
    # n halves and Z falls by a quarter from Fr 1 to 10 (beds averaged): kappa rises x1.5; the
    # nearest pulled Fr stand for 1 and 10 (here 1.1 and 9.5); mu = 0 rows are not Fig. 8's.
    rows = []
    for seed, bump in ((1, 0.1), (2, -0.1)):
        for fr, n, z in ((0.5, 12.0, 4.2), (1.1, 10.0, 4.0), (5.0, 7.0, 3.5), (9.5, 5.0, 3.0)):
            for w in (2.0, 6.0):
                rows.append(dict(system="I", D=3.0, mu=0.5, kn=2e5, Fr=fr, seed=seed, width=w,
                                 n_contacts=n + bump, Z=z + (0.5 if w == 6.0 else 0.0),
                                 kappa=(z / n) * 16 / (2 * np.sqrt(3))))
                rows.append({**rows[-1], "mu": 0.0, "n_contacts": 1.0})
    d = kappa_decomposition(pd.DataFrame(rows).assign(rung="r"))
    assert list(d.width) == [2.0, 6.0] and (d.Fr_low == 1.1).all() and (d.Fr_high == 9.5).all()
    at2 = d.iloc[0]
    assert at2.n_ratio == pytest.approx(0.5) and at2.Z_ratio == pytest.approx(0.75)
    assert at2.kappa_ratio == pytest.approx(1.5)
    assert d.iloc[1].Z_ratio == pytest.approx(3.5 / 4.5)


def test_startup_kept_spreads_the_start_over_the_papers_pull_and_refits():
    # 12 d pulled with a mean of 180 over the whole pull and 100 steady: 960 of excess work,
    # spread over 40 d: +24.
    assert kept_drag(100.0, 180.0, 12.0) == pytest.approx(124.0)
    assert kept_drag(100.0, 180.0, 12.0, pull=12.0) == pytest.approx(180.0)
    # The steady fit is fr2_vs_range's (same series, weights and bed scatter); without start
    # excess the kept drag is the steady one, so both fits agree and find the known Fr_2 = 5;
    # mu = 0 rows are not the series.
    table = point_table(seed=4, Ds=(2,))
    rows = [dict(system=r.system, D=r.D, mu=r.mu, kn=r.kn, Fr=r.Fr, seed=1, drag=r.drag, drag_err=r.drag_err,
                 whole_mean=r.drag, travel=12.0) for r in table.itertuples()]
    r = startup_refit(pd.DataFrame(rows), table, fr_max_values=(15.0,), n_boot=40, rung="x")
    assert len(r) == 4 and set(r.pull) == {"steady", "start kept, 40 d"}
    cont = r[r.continuous]
    assert cont.Fr2.iloc[0] == pytest.approx(cont.Fr2.iloc[1])
    assert abs(cont.Fr2.iloc[0] - 5.0) < 3 * cont.Fr2_err.iloc[0] and (cont.delta_at_5 < 3.84).all()
    ref = fr2_vs_range(table, fr_max_values=(15.0,), n_boot=40, seed=0, rung="x")
    assert cont.Fr2.iloc[0] == pytest.approx(ref[ref.continuous].Fr2.iloc[0])
    # A start excess of 40 per pulled d (whole_mean - drag = 40 over 12 d): +12 on every point.
    shifted = startup_refit(pd.DataFrame(rows).assign(whole_mean=lambda d: d.drag + 40.0), table,
                            fr_max_values=(15.0,), n_boot=0, rung="x")
    kept = shifted[(shifted.pull != "steady") & shifted.continuous].iloc[0]
    assert kept.Fr2 == pytest.approx(cont.Fr2.iloc[0], rel=0.05)   # a constant shift moves no crossover


def test_fr2_vs_range_recovers_fr2_and_drops_points_above_fr_max():
    table = point_table(seed=4, Ds=(2,))
    r = fr2_vs_range(table, fr_max_values=(0.5, 8, 15), n_boot=40, seed=0, rung="x").set_index(
        ["fr_max", "continuous"])
    full = r.loc[(15.0, True)]
    assert abs(full.Fr2 - 5.0) < 3 * full.Fr2_err and full.Fr2_err < 1.5, full
    assert full.n_points == len(FR) and full.fr_used_max == 15
    cut = r.loc[(8.0, False)]
    assert cut.n_points == int(np.sum(FR <= 8)) and cut.fr_used_max == 8
    short = r.loc[(0.5, True)]                               # 2 points: no fit, said why
    assert np.isnan(short.Fr2) and "at least" in short.note
    assert (r.rung == "x").all() and (r.D == 2).all()


def test_broken_line_recovers_an_exact_broken_line():
    fr = np.array([1.0, 2, 3, 4, 6, 7, 8, 10])
    drag = 500 + 60 * np.minimum(fr - 5, 0) + 20 * np.maximum(fr - 5, 0)
    fit = fit_broken_line(fr, drag, np.full(fr.shape, 10.0))
    assert list(fit.values().values()) == pytest.approx([500, 60, 20])
    assert fit.meta["goodness"]["chi2_dof"] == pytest.approx(0, abs=1e-12)
    assert evaluate(fit, [0.0, 5.0, 9.0]) == pytest.approx([200, 500, 580])     # the knee kept
    # Unscaled (χ² < 1): the covariance is the weights' alone; halving the errors halves the slopes' errors.
    half = fit_broken_line(fr, drag, np.full(fr.shape, 5.0))
    assert np.sqrt(np.diag(half.covariance)) == pytest.approx(np.sqrt(np.diag(fit.covariance)) / 2)
    # The knee is a fixed parameter: a line bent at 4 is recovered with knee=4.
    bent4 = 440 + 60 * np.minimum(fr - 4, 0) + 20 * np.maximum(fr - 4, 0)
    at4 = fit_broken_line(fr, bent4, np.full(fr.shape, 10.0), knee=4.0)
    assert at4.meta["fixed"] == {"knee": 4.0} and list(at4.values().values()) == pytest.approx([440, 60, 20])


def test_knee_at_five_tells_a_quadratic_rise_from_a_plateau():
    table = point_table(seed=5)                     # regime III: a2 + b2 Fr² from Fr_2 = 5 on
    rise = knee_at_five(table, rung="x").set_index("D")
    assert list(rise.index) == [2.0, 3.0] and (rise.n_points == int(np.sum((FR >= 1) & (FR <= 10)))).all()
    assert (rise.z > 2).all() and (rise.ratio > 1.5).all(), rise[["ratio", "z"]]
    # The same drag held at its Fr = 5 level beyond: a plateau flattens the line past the knee.
    flat = table.copy()
    above = flat.Fr > 5
    flat.loc[above, "drag"] = [synth.drag_true(D, 14.0, 0.5, 5.0) for D in flat.D[above]]
    plateau = knee_at_five(flat, rung="x").set_index("D")
    assert (plateau.z < -2).all() and (plateau.ratio.abs() < 0.3).all(), plateau[["ratio", "z"]]
    assert (plateau.ratio_err > 0).all() and (plateau.note == "").all()
    # Too few points on a side: a row that says why, no numbers.
    few = knee_at_five(table[table.Fr <= 6], rung="x")
    assert few.slope_above.isna().all() and few.note.str.contains("2 points on each side").all()
    # A point without a drag (a failed pull) is left out, not fitted as missing: the rest agree.
    holed = table.copy()
    holed.loc[(holed.Fr == 8) & (holed.D == 2), "drag"] = np.nan
    gap = knee_at_five(holed, rung="x").set_index("D")
    assert gap.n_points[2.0] == rise.n_points[2.0] - 1 and gap.loc[3.0].equals(rise.loc[3.0])
    assert np.isfinite(gap.z[2.0]) and gap.z[2.0] > 2 and np.isfinite(gap.chi2_red[2.0])


# --- the command line ------------------------------------------------------------


def test_claim_a_quotes_the_regime_tests_under_each_averaging():
    """The claim table's row (a) quotes the regime tests of the shown series on Fr 1-15, one cell per
    averaging: a steady drag that is one line has the paper's size excluded, a cumulative average
    of the paper's shape from Fr 5 has it shown; a table without the cumulative average, one cell."""
    from test_regime_tests import _table, line, paper_shaped

    from analysis.ladder.ladder_summary import regime_cells
    df = _table().iloc[1:].reset_index(drop=True)
    fr = df.Fr.to_numpy()
    df["drag"], df["drag_err"] = line(fr, a=900.0), 10.0
    df["drag_cumulative_box"], df["drag_cumulative_box_err"] = paper_shaped(fr, a=900.0, b2=30.0), 10.0
    steady, cumulative = regime_cells(df, {"show": {"Fr_2 (μ = 0.5, D = 3)": "Fr₂"}})
    assert steady.startswith("regime III, steady drag (D = 3, Fr 1–15): c = ")
    assert "the paper's size excluded at" in steady and "shown" not in steady
    assert cumulative.startswith("regime III, cumulative drag") and cumulative.count("(shown, p = ") == 2
    only = regime_cells(df.drop(columns=["drag_cumulative_box", "drag_cumulative_box_err"]), {"show": {}})
    assert len(only) == 1 and only[0].startswith("regime III, steady drag")
