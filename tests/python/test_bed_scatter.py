"""Where a point's scatter between beds comes from (issue 30, item 1): its own replicate beds, the
study's pooled scatter, a config's prior (table.bed_scatter) or none; the point table marks it
(bed_scatter_source) and the report names it, once when every point shares it."""
import numpy as np
import pandas as pd
import pytest
import synth

from analysis.core.table import (
    BedScatterPrior,
    bed_bootstrap,
    between_bed_scatter,
    combine_beds,
    froude,
    load_csv,
    save_csv,
    scatter_kind,
)
from analysis.fits.fitset import point_bed_scatter, run_fits
from analysis.report.report import comparisons
from analysis.report.report_notes import bed_scatter_sentence

FR = np.array([0.5, 1.0, 2.0, 4.0, 8.0])
PRIOR = {"relative": 0.05, "dof": 14, "source": "results/reproduction/some-rung"}


def runs(seeds_of, rng, rel_bed=0.06, rel_run=0.02):
    """A run table in the workflow's layout: for each D, its series poured with seeds_of[D]."""
    rows = []
    for D, seeds in seeds_of.items():
        for s in seeds:
            shift = rel_bed * rng.standard_normal()
            for fr in FR:
                y = (100.0 + 20.0 * fr) * D
                e = rel_run * y
                rows.append({"system": "I", "D": D, "h": 6.5, "mu": 0.5, "kn": 2e4, "gamman": 199.0,
                             "V": fr / float(froude(1.0, D)), "Fr": fr,
                             "drag": y * (1 + shift) + e * rng.standard_normal(),
                             "drag_err": e, "n_contacts": 9.0, "theta": 1.5, "Z": 3.5, "kappa": 1.0,
                             "run": f"pulls/system~I/D~{D:g}/h~6.5/mu~0.5/seed~{s}/Fr~{fr:g}",
                             "drag_dof": 20.0, "plateau": True, "seed": float(s)})
    df = pd.DataFrame(rows)
    df["Fr"] = froude(df.V, df.D)
    return df


def test_a_single_bed_point_takes_the_prior_and_says_so():
    # Mutation tried: single_bed_scatter ignoring the prior (returning none): the errors lose
    # the r2 F^2 term and the source reads "none", and this test fails.
    df = runs({2.0: [1], 3.0: [1]}, np.random.default_rng(0))
    pts = combine_beds(df, prior=PRIOR)
    W = df.drag_err.to_numpy() ** 2
    assert pts.drag_err.to_numpy() ** 2 == pytest.approx(W + 0.05 ** 2 * pts.drag.to_numpy() ** 2)
    assert (pts.bed_scatter_source == "prior").all()
    assert (pts.bed_scatter_r == 0.05).all() and (pts.bed_scatter_dof == 14).all()
    assert (pts.bed_scatter_study == PRIOR["source"]).all()
    # The prior's dof enter the point's (Satterthwaite): fewer than the within-run 20 alone.
    assert (pts.drag_dof < 20 + 14).all() and np.isfinite(pts.drag_dof).all()
    assert combine_beds(df, prior=BedScatterPrior.of(PRIOR)).drag_err.equals(pts.drag_err)


def test_the_studys_own_replicates_come_before_the_prior():
    # Mutation tried: single_bed_scatter consulting the prior first: the single-bed points read
    # "prior" with the prior's 5 % instead of the study's pooled scatter, and this test fails.
    rng = np.random.default_rng(1)
    df = runs({2.0: [1, 2, 3], 3.0: [1]}, rng)
    r2, dof = between_bed_scatter(df)
    pts = combine_beds(df, prior=PRIOR)
    rep, single = pts[pts.n_beds == 3], pts[pts.n_beds == 1]
    assert (rep.bed_scatter_source == "replicates").all() and rep.bed_scatter_r.isna().all()
    assert (single.bed_scatter_source == "pooled").all()
    assert single.bed_scatter_r.to_numpy() == pytest.approx(np.sqrt(r2)) and (single.bed_scatter_dof == dof).all()
    W = df[df.D == 3.0].drag_err.to_numpy() ** 2
    assert single.drag_err.to_numpy() ** 2 == pytest.approx(W + r2 * single.drag.to_numpy() ** 2)
    assert (single.bed_scatter_study == "").all()
    # The point table is what it was before priors existed.
    before = combine_beds(df)
    assert before.drag_err.equals(pts.drag_err) and before.drag_dof.equals(pts.drag_dof)


def test_without_replicates_or_prior_a_point_has_no_bed_scatter_and_the_report_says_so():
    # Mutation tried: labelling every single-bed point "pooled" whatever its r2: the
    # column and the report's sentence no longer say "none", and this test fails.
    df = runs({2.0: [1], 3.0: [1]}, np.random.default_rng(2))
    pts = combine_beds(df)
    assert (pts.bed_scatter_source == "none").all() and pts.bed_scatter_r.isna().all()
    assert pts.drag_err.to_numpy() == pytest.approx(df.drag_err.to_numpy())
    assert bed_scatter_sentence(pts) == ("Scatter between beds in the drags' errors, every fit: "
                                         "none (single beds, no prior).")
    assert point_bed_scatter(pts) == 0.0


@pytest.mark.slow
def test_the_regime_bootstrap_and_the_bed_bootstrap_use_the_prior():
    # Mutation tried: point_bed_scatter without its prior branch (0 with no replicated point):
    # the first assertion fails; bed_bootstrap without the prior (its r from the pooled scatter
    # alone, NaN here, so 0): the spread falls to the within-run 2 %/sqrt(5) and the second fails.
    df = runs({2.0: [1]}, np.random.default_rng(3))
    pts = combine_beds(df, prior={**PRIOR, "relative": 0.10})
    assert point_bed_scatter(pts) == pytest.approx(0.10)
    means = [t.drag.mean() for t in bed_bootstrap(df, 300, seed=4, prior={**PRIOR, "relative": 0.10})]
    spread = np.std(means) / np.mean(means)
    assert 0.08 < spread < 0.12
    assert all((t.bed_scatter_source == "prior").all() for t in bed_bootstrap(df, 2, prior=PRIOR))


def test_a_prior_without_its_source_or_dof_is_refused():
    for bad in ({"relative": 0.05, "dof": 14, "source": ""}, {"relative": -0.1, "dof": 14, "source": "x"},
                {"relative": 0.05, "dof": 0, "source": "x"}):
        with pytest.raises(ValueError, match="table.bed_scatter"):
            combine_beds(runs({2.0: [1]}, np.random.default_rng(5)), prior=bad)


def _point_table(prior=None, replicated_D=None):
    """The synthetic study's table as the workflow's point table (each pull its own point), with
    the system I mu = 0.5 series at replicated_D poured twice."""
    t = synth.make_table(seed=1)
    t = t.assign(run=[f"pulls/p{i}/seed~1/x" for i in range(len(t))], seed=1.0)
    if replicated_D is not None:
        twin = t[(t.system == "I") & (t.mu == 0.5) & np.isclose(t.D, replicated_D)]
        twin = twin.assign(seed=2.0, drag=twin.drag * 1.03, run=[r.replace("seed~1", "seed~2") for r in twin.run])
        t = pd.concat([t, twin], ignore_index=True)
    return combine_beds(t, prior=prior)


@pytest.fixture(scope="module")
def fits():
    return run_fits(synth.make_table(seed=1), n_boot=0)


def test_the_report_names_the_prior_once_when_every_point_shares_it(fits):
    # Mutation tried: bed_scatter_sentence dropping the prior's source (text "prior" alone): the
    # sentence's assertion fails. With every point on the prior, the rows carry no bed note (the
    # introduction states it), except θ and κ, whose errors take no prior and say so.
    pts = _point_table(prior=PRIOR)
    assert (pts.bed_scatter_source == "prior").all()
    assert bed_scatter_sentence(pts) == ("Scatter between beds in the drags' errors, every fit: prior r = 0.05 "
                                         "(dof 14) from results/reproduction/some-rung.")
    rows = {x.quantity: x for x in comparisons(fits, pts)}
    assert not any(n.startswith("bed scatter") for n in rows["Fr_1 (μ = 0.5, D = 4)"].notes)
    assert "θ and κ bed scatter: none (single beds: θ and κ take no pooled or prior scatter)" in \
        rows["θ(Fr) Υ1 (Eq. 7)"].notes


def test_with_mixed_sources_each_number_names_its_own(fits):
    # Mutation tried: comparisons stating the bed scatter beside no number (bed_scatter=False
    # always): the per-row assertions fail.
    pts = _point_table(prior=PRIOR, replicated_D=2.0)
    single_drag = pts[(pts.n_beds == 1) & (scatter_kind(pts) == "drag")]
    r2 = single_drag.bed_scatter_r.iloc[0] ** 2
    assert set(pts.bed_scatter_source) == {"replicates", "pooled"}
    rows = {x.quantity: x for x in comparisons(fits, pts)}
    assert "bed scatter: replicate beds" in rows["Fr_1 (μ = 0.5, D = 2)"].notes
    dof = int(single_drag.bed_scatter_dof.iloc[0])
    assert (f"bed scatter: pooled from this study's replicated points (r = {np.sqrt(r2):.3g}, dof {dof})"
            in rows["Fr_1 (μ = 0.5, D = 4)"].notes)
    assert "Each number's notes say which" in bed_scatter_sentence(pts)
    assert "replicate beds (" in bed_scatter_sentence(pts) and "points)" in bed_scatter_sentence(pts)


def test_the_ladder_refit_takes_the_rungs_prior(tmp_path):
    # Mutation tried: refit_table calling combine_beds without the rung config's prior: the
    # points read "none" and this test fails.
    from analysis.ladder_refit import refit_table
    df = runs({2.0: [1]}, np.random.default_rng(6))
    save_csv(df, tmp_path / "runs.csv")
    (tmp_path / "config.yaml").write_text(
        "table:\n  bed_scatter: {relative: 0.05, dof: 14, source: results/reproduction/some-rung}\n")
    assert (refit_table(tmp_path).bed_scatter_source == "prior").all()
    (tmp_path / "config.yaml").write_text("table: {allow_failed: false}\n")
    assert (refit_table(tmp_path).bed_scatter_source == "none").all()


def _with_yield_pulls(df, rng, rel_bed, seeds):
    """df plus, for each D, a yield pull (V = 0.01) in every bed of seeds[D], scattering rel_bed
    between beds."""
    rows = []
    for D, ss in seeds.items():
        for s in ss:
            y = 60.0 * D * (1 + rel_bed * rng.standard_normal())
            rows.append({**df.iloc[0].to_dict(), "D": D, "V": 0.01, "Fr": float(froude(0.01, D)),
                         "drag": y, "drag_err": 0.02 * y, "seed": float(s),
                         "run": f"pulls/system~I/D~{D:g}/h~6.5/mu~0.5/seed~{s}/V~0.01"})
    return pd.concat([df, pd.DataFrame(rows)], ignore_index=True)


def test_yield_forces_and_drags_at_speed_pool_their_own_scatter_and_take_their_own_prior():
    # A yield force's beds scatter ~5 times a drag's at speed (the default study: 18.8 % and
    # 3.7 %). Mutation tried: combine_beds pooling both kinds together (scatter_kind returning
    # "drag" for every row): the single-bed yield point takes the mixed r and the first
    # assertion fails; the prior per kind ignored (the flat prior for both): the second.
    rng = np.random.default_rng(7)
    df = runs({2.0: [1, 2, 3, 4], 3.0: [1]}, rng, rel_bed=0.03, rel_run=0.005)
    df = _with_yield_pulls(df, rng, 0.20, {2.0: [1, 2, 3, 4], 3.0: [1]})
    pts = combine_beds(df)
    kind = scatter_kind(pts)
    one = pts[pts.n_beds == 1]
    r_yield = one[kind[pts.n_beds == 1] == "yield"].bed_scatter_r
    r_drag = one[kind[pts.n_beds == 1] == "drag"].bed_scatter_r
    assert len(r_yield) == 1 and len(r_drag) == len(FR)
    assert np.sqrt(between_bed_scatter(df[scatter_kind(df) == "yield"])[0]) == pytest.approx(r_yield.iloc[0])
    assert r_yield.iloc[0] > 3 * r_drag.iloc[0]
    assert (one.bed_scatter_dof[kind[pts.n_beds == 1] == "yield"] == 3).all()
    # The point table keeps the runs' order of points whatever their kind.
    assert list(pts.run) == list(dict.fromkeys(r.replace("/seed~1/", "/").replace("/seed~2/", "/")
                                               .replace("/seed~3/", "/").replace("/seed~4/", "/")
                                               if d == 2.0 else r for r, d in zip(df.run, df.D)))
    # In a study poured once, each kind takes its own prior; a kind without one has none.
    single = _with_yield_pulls(runs({2.0: [1]}, rng), rng, 0.2, {2.0: [1]})
    per_kind = {"drag": PRIOR, "yield": {**PRIOR, "relative": 0.19, "source": "results/reproduction/config"}}
    pts = combine_beds(single, prior=per_kind)
    kind = scatter_kind(pts)
    assert (pts.bed_scatter_r[kind == "yield"] == 0.19).all() and (pts.bed_scatter_r[kind == "drag"] == 0.05).all()
    assert (pts.bed_scatter_study[kind == "yield"] == "results/reproduction/config").all()
    pts = combine_beds(single, prior={"drag": PRIOR})
    assert (pts.bed_scatter_source[scatter_kind(pts) == "yield"] == "none").all()
    with pytest.raises(ValueError, match="table.bed_scatter: unknown kind"):
        combine_beds(single, prior={"drag": PRIOR, "yeild": PRIOR})


def test_the_ladder_refit_takes_the_prior_the_rungs_config_declares_now(tmp_path):
    # A rung run before its config declared a prior: the refit (the table stage, redone with
    # today's analysis) takes the prior of the config named in its run.json. Mutation tried:
    # reading the recorded config.yaml only: the points read "none" and this test fails.
    import json

    from analysis.ladder_refit import refit_table
    rung = tmp_path / "results" / "rung"
    rung.mkdir(parents=True)
    save_csv(_with_yield_pulls(runs({2.0: [1]}, np.random.default_rng(8)), np.random.default_rng(9), 0.2,
                               {2.0: [1]}), rung / "runs.csv")
    (rung / "config.yaml").write_text("table: {allow_failed: false}\n")
    (rung / "run.json").write_text(json.dumps({"rung": "rung", "config": "config/ladder/rung.yaml"}))
    (tmp_path / "config" / "ladder").mkdir(parents=True)
    (tmp_path / "config" / "ladder" / "rung.yaml").write_text(
        "table:\n  bed_scatter:\n    drag: {relative: 0.04, dof: 158, source: results/reproduction/config}\n"
        "    yield: {relative: 0.19, dof: 26, source: results/reproduction/config}\n")
    import analysis.ladder_refit as lr
    pts = combine_beds(load_csv(rung / "runs.csv"), prior=lr._bed_scatter_prior(rung, root=tmp_path))
    kind = scatter_kind(pts)
    assert (pts.bed_scatter_source == "prior").all()
    assert (pts.bed_scatter_r[kind == "yield"] == 0.19).all() and (pts.bed_scatter_r[kind == "drag"] == 0.04).all()
    assert (refit_table(rung).bed_scatter_source == "none").all()   # root "." has no such config
