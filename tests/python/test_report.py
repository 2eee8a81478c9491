"""The report: every figure, fitted numbers beside the paper's, verdicts."""
import math

import numpy as np
import pytest
import synth

from analysis.core.result import Param
from analysis.report.report import comparisons, run_fits, verdict

FIGURES = ["fig02_restitution", "fig04_force_trace", "fig05_drag_vs_Fr_mu0.5",
           "fig06_theta_vs_Fr", "fig07_coordination_distribution", "fig08_kappa_vs_Fr",
           "fig09_flow_field", "fig10_drag_vs_Fr_mu0",
           "table1_mu0_regime1", "fig11_quasistatic_vs_mu", "fig12_yield_vs_mu",
           "fig13_yield_vs_D", "fig14_phi_vs_mu", "fig15_scaled_drag_vs_Fr_D",
           "fig16_drag_vs_Fr_depth", "fig17_yield_vs_h", "fig18_alpha_and_sum_rule",
           "fig19_scaled_drag_vs_Fr_h", "fig20_kn_gamman"]


def test_verdict_rules():
    assert verdict(Param(1.05, 0.05), 1.0)[0] == "reproduced within error bars"
    assert verdict(Param(1.2, 0.01), 1.0)[0] == "reproduced qualitatively"
    assert verdict(Param(2.0, 0.1), 1.0)[0] == "not reproduced"
    assert verdict(None, 1.0)[0] == "not reproduced"
    # An error that could cover anything, or none at all, confirms nothing.
    assert verdict(Param(1.2, math.nan), 1.0)[0] == "inconclusive"
    assert verdict(Param(0.25, 0.39), 1.0) == ("inconclusive", "error 156% of the value, above 30%")
    assert verdict(Param(1.0, 2.6), 5.0)[0] == "inconclusive"
    assert verdict(Param(1.0, 0.31), 1.0)[0] == "inconclusive"
    assert verdict(Param(1.0, 0.29), 1.0)[0] == "reproduced within error bars"
    # A fit with drag falling in regime II is inconclusive whatever its numbers.
    v, why = verdict(Param(1.0, 0.05), 1.0, ["drag falls with Fr in regime II (b1 = -3)"])
    assert v == "inconclusive" and "regime II" in why


def test_a_number_at_a_bound_is_inconclusive_and_the_within_test_is_students_t():
    # On a bound, the fit's number and error say nothing about where the truth lies.
    v, why = verdict(Param(7.0, 0.4), 7.0, at_bounds=["Fr2 at its upper bound 7"])
    assert v == "inconclusive" and "bound" in why
    # 2.5 standard errors off: outside the normal 95 % interval (1.96), inside Student's t at
    # 3 dof (3.18), whose fits have few points to estimate their error from.
    assert verdict(Param(1.0, 0.1), 1.25)[0] == "reproduced qualitatively"
    v, why = verdict(Param(1.0, 0.1), 1.25, dof=3)
    assert v == "reproduced within error bars" and "Student-t at 3 dof" in why and "3.18" in why
    assert verdict(Param(1.0, 0.1), 1.25, dof=1000)[0] == "reproduced qualitatively"
    # A fit with as many parameters as points has no error to speak of.
    assert verdict(Param(1.0, 0.1), 1.0, dof=0)[0] == "inconclusive"


def test_falling_regime_ii_is_flagged_and_counted_apart():
    # The default study's D = 1, mu = 0.5 series: a plateau at 135, then down to 95 at Fr = 1,
    # then rising (the shape the issue reports). The fit must flag it; the report counts it
    # as inconclusive, apart from the other verdicts.
    from analysis.fits.fitset import Results
    from analysis.fits.regimes import fit_regimes
    from analysis.report.report import counts
    Fr = np.array([0.25, 0.5, 0.75, 1.0, 1.5, 2.5, 3.5, 4.5, 6.0, 8.0, 10.0])
    drag = np.array([135, 134, 136, 95, 100, 108, 117, 125, 160, 230, 330.0])
    fit = fit_regimes(Fr, drag, 0.03 * drag, n_boot=30)
    assert fit.meta["violations"] and "regime II" in fit.meta["violations"][0]
    rows = comparisons(Results(regimes={("D", 0.5, 1.0): fit}, phi=None, alpha=None, sums=None))
    assert [x.verdict for x in rows] == ["inconclusive", "inconclusive"]
    assert "drag falls with Fr" in rows[0].sentence
    assert counts(rows)["inconclusive"] == 2 and counts(rows)["not reproduced"] == 0


@pytest.mark.slow
def test_report_has_every_figure_and_file(report_dir):
    md = (report_dir / "report.md").read_text()
    html = (report_dir / "report.html").read_text()
    for name in FIGURES:
        assert f"]({name}.png)" in md, name
        assert f"src='{name}.png'" in html, name
        assert (report_dir / f"{name}.pdf").is_file(), name
    assert "not drawn" not in md
    where = [md.index(f"]({name}.png)") for name in FIGURES]
    assert where == sorted(where), "figures not in the paper's order"
    assert (report_dir / "fits.json").is_file()


@pytest.mark.slow
def test_report_compares_with_paper_values(report_dir):
    md = (report_dir / "report.md").read_text()
    for needle in ("Fr_1 (μ = 0.5, D = 4)", "Fr_2 (Eq. 12 collapse, μ = 0.5)", "θ(Fr) Υ2 (Eq. 7)",
                   "κ(Fr) slope (Fig. 8)", "Table I c'' (D = 2d)", "φ_0", "α_0",
                   "α_μ + φ_μ (α_μ from the yield force; μ = 0.5",
                   "α_μ + φ_μ (α_μ from the drag, averaged over speeds; μ = 0.5",
                   "F_Y saturating in μ (D = 4d)", "λ_1^II"):
        assert needle in md, needle
    # Synthetic data built on the paper's numbers must be judged reproduced.
    for line in md.splitlines():
        if line.startswith("- Fr_1 (Eq. 12") or line.startswith("- θ(Fr)") or line.startswith("- κ(Fr)"):
            assert "— reproduced" in line, line


def test_scale_is_stated_beside_the_papers(table):
    from analysis.report.report import _scale_text
    t = table.assign(lx=10.0, ly=np.where(table.system == "I", 10.0, 8.0), grains=1500.0, distance=5.0)
    text = _scale_text(t, 2e4)
    assert "system I: 10 × 10 d, 1500 grains" in text and "system II: 10 × 8 d" in text
    assert "paper: 40 × 40 d, 70,000 grains" in text and "paper: 80 × 40 d, 300,000 grains" in text
    assert "pulls of 5 d" in text and "K_n = 2e+04 (paper 2e+08)" in text
    assert "box not recorded" in _scale_text(table, 2e4)


def test_shifted_crossovers_are_reported_as_not_reproduced():
    df = synth.make_table(seed=4, mus=(0.0, 0.5), kn_variants=False, crossovers=(2.0, 7.0))
    rows = {r.quantity: r for r in comparisons(run_fits(df, n_boot=30))}
    for q in ("Fr_1 (Eq. 12 collapse, μ = 0.5)", "Fr_2 (Eq. 12 collapse, μ = 0.5)",
              "Fr_1 (μ = 0.5, D = 4)", "Fr_2 (μ = 0.5, h = 45)"):
        assert rows[q].verdict == "not reproduced", rows[q].sentence
    # ...while the other laws, which did not move, still are.
    assert rows["κ(Fr) slope (Fig. 8)"].verdict.startswith("reproduced")


def test_each_number_says_what_it_rests_on(table):
    # Replicate beds (column seed) and runs without a plateau (column plateau) are stated
    # beside every number whose fit uses them; without the columns, one bed per point.
    r = run_fits(table, n_boot=0)
    plain = {x.quantity: x for x in comparisons(r, table)}
    assert "1 bed per point (no replicates)" in plain["Fr_1 (μ = 0.5, D = 4)"].notes
    t = table.assign(seed=1, plateau=1)
    extra = t[(t.system == "I") & (t.D == 4.0) & (t.mu == 0.5) & (t.V > 0.02)].assign(seed=2)
    extra.loc[extra.index[0], "plateau"] = 0
    import pandas as pd
    both = pd.concat([t, extra], ignore_index=True)
    rows = {x.quantity: x for x in comparisons(r, both)}
    notes = rows["Fr_1 (μ = 0.5, D = 4)"].notes
    assert "2 replicate bed(s) per point" in notes
    assert f"1 of {2 * len(extra)} runs whose drag error reached no plateau (a conservative bound)" in notes
    assert "every run reached a plateau" in rows["Fr_1 (μ = 0.5, D = 2)"].notes


def test_the_point_table_counts_its_combined_beds(table):
    # The workflow's table.csv has one row per point (replicate beds combined, n_beds of
    # them) and the first bed's seed: the note counts n_beds, not the seeds in the rows.
    r = run_fits(table, n_boot=0)
    points = table.assign(seed=1, n_beds=3, plateau=1)
    rows = {x.quantity: x for x in comparisons(r, points)}
    assert "3 replicate bed(s) per point" in rows["Fr_1 (μ = 0.5, D = 4)"].notes


def test_the_report_leads_with_one_line_per_claim_and_states_a_shared_caveat_once():
    from analysis.report.report import Row, headline, shared_caveats
    from analysis.report.report_render import to_html as _html

    beds = "2 replicate bed(s) per point"
    rows = [Row("Fr_1 (μ = 0.5, D = 1)", "0.9 ± 0.1", "≈ 1", "reproduced within error bars", "", [beds], "a."),
            Row("Fr_2 (μ = 0.5, D = 1)", "2 ± 1", "≈ 5", "inconclusive", "", [beds, "c0 at its bound"], "b."),
            Row("φ_0 (K_n = 2e+04)", "2.1 ± 0.2", "≈ 2", "reproduced within error bars", "", [], "c.")]
    lines = headline(rows)
    assert len(lines) == 7 and lines[0].startswith("(a) three regimes")
    assert "✓ 1, ? 1 of 2 numbers" in lines[0] and "✓ 1 of 1 number." in lines[3]
    assert "no number of this study tests it" in lines[1]          # (b): no θ row here
    caveats, refs = shared_caveats(rows)
    assert caveats == [f"[1] {beds} (2 rows)"]                      # shared: once, numbered
    assert refs(rows[1].notes) == "c0 at its bound; [1]"             # its own note stays inline
    assert refs(rows[2].notes) == ""
    page = _html([("table", ["verdict"], [["✓ reproduced within error bars"], ["? inconclusive"]])])
    assert "<td class='v✓'>" in page and "<td class='v?'>" in page and ".v\\?{" in page


def test_a_rejected_model_is_reported_as_such_not_as_a_slope(table):
    # κ falling to a minimum and rising again (issue 30): a line through it is rejected, and the
    # report says "model rejected (χ²/dof = ..., residuals trend ...)" where the slope would be.
    from analysis.report.report import Row
    u = table.copy()
    u["kappa"] = 0.80 + 0.004 * (u.Fr - 5.0) ** 2
    u["kappa_err"] = 0.02
    rows = {x.quantity: x for x in comparisons(run_fits(u, n_boot=0), u)}
    slope = rows["κ(Fr) slope (Fig. 8)"]
    assert slope.verdict == "inconclusive" and slope.rejected.startswith("model rejected (χ²/dof = ")
    assert "residuals trend" in slope.rejected and slope.shown() == slope.rejected
    assert "the data reject the model" in slope.sentence and "not a finding" in slope.base
    # The linear κ of the synthetic table: the slope is quoted and judged.
    rows = {x.quantity: x for x in comparisons(run_fits(table, n_boot=0), table)}
    slope = rows["κ(Fr) slope (Fig. 8)"]
    assert not slope.rejected and slope.shown() == slope.fitted and slope.verdict != "inconclusive"
    assert Row("q", "1 ± 0.1", "1", "inconclusive", "s").shown() == "1 ± 0.1"


@pytest.mark.slow
def test_report_lists_the_goodness_of_every_fit(report_dir):
    md = (report_dir / "report.md").read_text()
    part = md[md.index("## Goodness of the fits"):]
    for name in ("regimes_mu0.5_D2", "theta", "kappa", "saturation_D2", "phi_mu0_kn2e+05"):
        assert f"| {name} | not rejected | χ²/dof = " in part, name


def test_a_sum_rule_built_on_a_rejected_fit_is_inconclusive(table):
    # α_μ + φ_μ is not fitted itself: it adds the φ_μ fit and an α_μ fit (from F_Y, or the
    # average of the drag's per-speed fits). When the data reject one of those (goodness.py),
    # the sum is no finding either, however close its number lands to 3.
    r = run_fits(table, n_boot=0)
    sums = lambda: {x.quantity: x for x in comparisons(r, table) if x.quantity.startswith("α_μ + φ_μ")}
    yield_sum = lambda rows: [x for q, x in rows.items() if "from the yield force" in q]
    drag_sum = lambda rows: [x for q, x in rows.items() if "from the drag" in q]
    rows = sums()
    assert yield_sum(rows) and drag_sum(rows) and not any(x.rejected for x in rows.values())
    # The φ_μ fit rejected: every sum that uses it says so.
    phi = r.phi.copy()
    r.phi = phi.assign(rejected=1.0, trend_p=0.0004, chi2_dof=2.5)
    for x in sums().values():
        assert x.verdict == "inconclusive" and x.rejected.startswith("model rejected (φ_μ fit: χ²/dof = 2.50")
        assert "the data reject the model: φ_μ fit" in x.sentence and x.shown() == x.rejected
    # One speed's α_μ fit rejected: the sum with the averaged α_μ, not the one from F_Y.
    r.phi = phi
    r.alpha_speeds = r.alpha_speeds.assign(rejected=[1.0] + [0.0] * (len(r.alpha_speeds) - 1), trend_p=0.002)
    rows = sums()
    assert all(x.rejected.startswith("model rejected (α_μ fit at V = ") for x in drag_sum(rows))
    assert not any(x.rejected for x in yield_sum(rows))


def test_a_continuous_regime_fits_dof_counts_its_free_parameters():
    # The continuous law lists b1 and b2 but derives them from continuity at Fr1 and Fr2: its
    # dof is 2 more than points minus listed parameters (which took Student's t at 4 dof for 6).
    from analysis.fits.regimes import fit_regimes
    from analysis.report.report import fit_dof
    Fr = np.array([0.25, 0.5, 0.75, 1, 1.5, 2.5, 3.5, 4.5, 6, 8, 10.0])
    drag = 100 + np.where(Fr > 1, 20 * (Fr - 1), 0) + np.where(Fr > 5, 30 * (Fr - 5), 0)
    for continuous, free in ((True, 5), (False, 7)):
        fit = fit_regimes(Fr, drag * (1 + 0.01 * np.sin(7 * Fr)), 0.02 * drag, n_boot=0, continuous=continuous)
        assert len(fit.params) == 7 and fit_dof(fit) == len(Fr) - free


def test_the_sum_rules_dof_is_welch_satterthwaites_of_its_parts():
    import pandas as pd

    from analysis.report.verdicts import sum_dof as _sum_dof
    key = dict(mu=0.5, kn=2e4, gamman=199.0)
    t = pd.Series({**key, "phi_err": 0.3, "alpha_err": 0.4, "n_min": 4})
    part = lambda chi2, n: pd.DataFrame([{**key, "n": n, "chi2_dof": chi2, "trend_p": 0.5, "rejected": 0.0}])
    # Both errors their points' own, unscaled (chi^2/dof <= 1): the normal quantile (was t at 2 dof).
    assert _sum_dof(t, part(0.8, 4), part(0.5, 5)) is None
    # Both scaled by their residuals: 0.09 and 0.16 at 2 and 3 dof -> 0.25^2 / (0.09^2/2 + 0.16^2/3).
    assert math.isclose(_sum_dof(t, part(2.0, 4), part(3.0, 5)), 0.0625 / (0.0081 / 2 + 0.0256 / 3))
    # Only phi scaled: its 2 dof alone, weighted by its share of the variance.
    assert math.isclose(_sum_dof(t, part(2.0, 4), part(0.5, 5)), 0.0625 / (0.0081 / 2))
    # The alpha averaged over speeds (no fitted row) rests on its points: the normal quantile.
    assert _sum_dof(t, part(0.5, 4), None) is None


def test_a_number_at_about_one_degree_of_freedom_is_untestable_not_reproduced():
    # The sum rule of the default's boxes with the yield pulls at V = 0.1 (scaling-k2e4-box10):
    # 2.26 ± 0.34 against 3, 2.2 standard errors away. Its φ_μ fit rests on its residuals at
    # 1 dof and its α_μ on its points: Welch–Satterthwaite gives about 1 dof, Student's t about 11,
    # and "within error bars" would hold for anything within ±4. Untestable at that rung.
    import pandas as pd

    from analysis.report.verdicts import MIN_DOF, sum_dof, within_quantile
    key = dict(mu=0.5, kn=2e4, gamman=199.0)
    t = pd.Series({**key, "phi_err": 0.33, "alpha_err": 0.06, "n_min": 3})
    part = lambda chi2, n: pd.DataFrame([{**key, "n": n, "chi2_dof": chi2, "trend_p": math.nan, "rejected": 0.0}])
    dof = sum_dof(t, part(2.0, 3), part(0.5, 4))
    assert 1.0 < dof < 1.1 and within_quantile(dof) > 10
    v, why = verdict(Param(2.26, 0.34), 3.0, dof=dof)
    assert v == "inconclusive" and "untestable" in why and "at 1.1 degrees of freedom" in why
    assert verdict(Param(2.26, 0.34), 3.0, dof=1.0)[1].endswith("spans ±12.7 standard errors (Student-t)")
    # From 2 dof on (t = 4.30) the comparison can fail, and is made.
    assert MIN_DOF == 2 and verdict(Param(2.26, 0.34), 3.0, dof=2.0)[0] == "reproduced within error bars"
    assert verdict(Param(2.26, 0.10), 3.0, dof=2.0)[0] == "reproduced qualitatively"
    # An error that is its points' own (the normal quantile) does not rest on the fit's dof.
    assert verdict(Param(2.78, 0.20), 3.0, dof=1.0, from_points=True)[0] == "reproduced within error bars"


def test_theta_and_kappa_from_yield_pulls_or_few_speeds_are_not_studied(table):
    # A yield and depth sweep (scaling-k2e4-box20) has system I at μ = 0.5 only in its yield
    # pulls: θ and κ fitted to those three points (a κ "slope" of 17 ± 4 against Fr 0.12-0.14)
    # test nothing, and the report lists no number for them.
    from analysis.core.table import is_yield
    from analysis.report.verdicts import OBSERVABLE_MIN_SPEEDS, observable_speeds
    sysI = (table.system == "I") & np.isclose(table.mu, 0.5)
    names = lambda t: {x.quantity for x in comparisons(run_fits(t, n_boot=0), t)}      # noqa: E731
    theta_kappa = lambda q: q.startswith(("θ(Fr)", "κ(Fr)"))                         # noqa: E731
    assert observable_speeds(table[sysI], "kappa") >= OBSERVABLE_MIN_SPEEDS
    assert sum(map(theta_kappa, names(table))) == 5                                   # Υ1-3, k0, k1
    yields_only = table[~sysI | is_yield(table)]
    assert observable_speeds(yields_only[(yields_only.system == "I") & np.isclose(yields_only.mu, 0.5)],
                             "kappa") == 0
    assert not any(map(theta_kappa, names(yields_only)))
    # Four speeds at speed (D = 2, 4, 6 each): still fewer than five, not studied; five are.
    moving = sysI & ~is_yield(table)
    speeds = sorted(table[moving].Fr.round(6).unique())
    for n, studied in ((4, False), (5, True)):
        keep = ~moving | table.Fr.round(6).isin(speeds[:n])
        assert any(map(theta_kappa, names(table[keep]))) == studied, n


def test_the_header_counts_pulls_behind_pooled_points_and_quotes_the_fits_own_error_method():
    # The header once said "184 pulls" of a table of 184 points pooled over 2 beds (368 pulls),
    # and "wild-bootstrap refits" where fits.json recorded Gaussian noise of each point's error.
    import pandas as pd

    from analysis.core.result import Fit
    from analysis.fits.fitset import Results
    from analysis.report.report import _pull_count, _regime_errors

    assert _pull_count(pd.DataFrame({"n_beds": [2, 2, 3]})) == "3 points from 7 pulls (each point the mean of its beds)"
    assert _pull_count(pd.DataFrame({"n_beds": [1, 1]})) == "2 pulls"
    assert _pull_count(pd.DataFrame({"drag": [1.0]})) == "1 pull"

    def fit(how):
        return Fit("regimes", {}, f"profile least squares; errors = {how}", 3, (0.5, 15.0))

    r = Results(regimes={("D", 0.5, 3.0): fit("200 refits (seed 0)"), ("D", 0.0, 3.0): fit("200 refits (seed 0)"),
                         ("h", 0.5, 6.0): fit("resampled beds")})
    assert _regime_errors(r) == "200 refits (seed 0) (2 fits); resampled beds (1 fit)"
    assert _regime_errors(Results()) == "no regime fits"


def test_the_header_names_the_collapses_error_method_apart_from_least_squares():
    # The header said "other fits: least-squares covariance" while Eq. 12's collapses, whose
    # crossovers the report judges, took their errors from refits resampling the beds.
    from analysis.core.result import Fit, Param
    from analysis.fits.fits import ScalingLaw
    from analysis.fits.fitset import Results
    from analysis.report.report import _law_errors

    def law(mu):
        reg = Fit("regimes", {}, "profile least squares; errors = 200 refits resampling the beds (seed 0)", 3,
                  (0.5, 15.0))
        return ScalingLaw(mu=mu, kn=2e4, gamman=199.0, alpha=Param(1.0, 0.1), phi=Param(2.0, 0.1), regimes=reg)

    assert _law_errors(Results(laws=[law(0.0), law(0.5)])) == (
        "; Eq. 12 collapses: errors the 200 refits resampling the beds (seed 0) (2 fits)")
    assert _law_errors(Results()) == ""
