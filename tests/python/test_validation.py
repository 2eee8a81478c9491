"""analysis.validation.validation: comparisons of a cheaper protocol with the reference one."""
import numpy as np
import pandas as pd
import pytest

from analysis.validation import validation as val
from analysis.validation.validation_points import point_table


def yield_runs(shift, beds=3, noise=0.01, bed_scatter=0.06, seed=1):
    """Runs of a yield-speed study: 2 D x 2 mu, speeds 0.01/0.03/0.1, `beds` beds each.
    Each bed shifts all its pulls by the same factor (bed_scatter); each pull has its own
    within-run noise (relative `noise`, its error). The drag at V is F0 (1 + shift[V])."""
    rng = np.random.default_rng(seed)
    rows = []
    for D in (2.0, 3.0):
        for mu in (0.0, 0.5):
            F0 = 100 * D * (1 + mu)
            for b in range(1, beds + 1):
                bed = 1 + bed_scatter * rng.standard_normal()
                for V in (0.01, 0.03, 0.1):
                    F = F0 * bed * (1 + shift[V])
                    rows.append(dict(system="I", D=D, h_requested=6.5, mu=mu, kn=2e4, gamman=199.05, V=V,
                                     Fr=V / np.sqrt(D), seed=b, drag=F * (1 + noise * rng.standard_normal()),
                                     drag_err=noise * F, sanity="clean"))
    return pd.DataFrame(rows)


def test_paired_comparison_finds_a_small_shift_that_bed_scatter_would_hide():
    runs = yield_runs({0.01: 0.0, 0.03: 0.0, 0.1: 0.08})
    cmp = val.compare(runs, "yield_speed")
    assert set(cmp.variant) == {0.03, 0.1} and len(cmp) == 8 and cmp.paired.all()
    slow, fast = cmp[cmp.variant == 0.03], cmp[cmp.variant == 0.1]
    assert slow.agrees.all()                       # no shift: |z| < 2 at all four points
    assert not fast.agrees.any()                   # 8 % against 1 %/sqrt(3) errors: z ~ 10
    assert fast.rel_diff.mean() == pytest.approx(0.08, abs=0.02)
    # The paired error is the within-run one only: sqrt(2) x 1 % / sqrt(3) beds.
    assert slow.rel_diff_err.median() == pytest.approx(0.01 * np.sqrt(2 / 3), rel=0.2)
    text = val.conclusion(cmp, "yield_speed")
    assert "every point: V = 0.03 instead of 0.01" in text and "agrees at 4 of 4" in text and "agrees at 0 of 4" in text


def test_a_shift_at_the_middle_speed_keeps_the_slowest():
    runs = yield_runs({0.01: 0.0, 0.03: 0.1, 0.1: 0.0})
    text = val.conclusion(val.compare(runs, "yield_speed"), "yield_speed")
    assert "every point: no faster speed agrees with V = 0.01, keep it" in text


def box_runs(shift_small):
    rows = []
    for D in (2.0, 6.0):
        for lx in (20.0, 30.0, 40.0):
            for Fr in (1.0, 5.0):
                F = 100 * D * (1 + 0.1 * Fr) * (1 + (shift_small if (lx == 20 and D == 6) else 0.0))
                rows.append(dict(system=f"box{lx:g}", D=D, h_requested=10.0, mu=0.5, kn=2e4, gamman=199.05,
                                 Fr=Fr, V=Fr * np.sqrt(D), lx=lx, ly=lx, seed=1, n_beds=2, drag=F,
                                 drag_err=0.02 * F, sanity="clean"))
    return pd.DataFrame(rows)


def test_box_size_names_the_smallest_box_that_agrees_for_each_D():
    cmp = val.compare(box_runs(0.2), "box_size")
    assert not cmp.paired.any() and set(cmp.reference) == {40.0}
    text = val.conclusion(cmp, "box_size")
    assert "D = 2: lx = 20" in text and "D = 6: lx = 30" in text


def test_stiffness_states_the_drift_per_decade():
    rows = []
    for kn in (2e4, 2e5, 2e6):
        for Fr in (0.5, 2.0):
            F = 100 * (1 + 0.05 * np.log10(kn / 2e6))    # +5 % per decade of K_n
            rows.append(dict(system="I", D=2.0, h_requested=6.5, mu=0.5, kn=kn, gamman=1.0, Fr=Fr, V=Fr,
                             seed=1, n_beds=1, drag=F, drag_err=0.5, sanity="clean"))
    cmp = val.compare(pd.DataFrame(rows), "stiffness")
    assert set(cmp.reference) == {2e6} and len(cmp) == 4
    text = val.conclusion(cmp, "stiffness")
    # errors of 0.5 % against a 5-10 % change: every point disagrees, and says so
    assert "at Fr = 0.5: +5.0 % per decade (disagrees); at Fr = 2: +5.0 % per decade (disagrees)." in text, text


def region_runs(shift, theta_shift=0.0, beds=2, noise=0.01, bed_scatter=0.06, seed=3):
    """Paired runs of an active-region study: D = 2 and 6, Fr = 1 and 5, radii 0 (the
    reference), 4, 8 and 12 d through the same beds; the drag at radius R is F0 (1 + shift[R])
    and theta shifts by theta_shift at the smallest radius only."""
    rng = np.random.default_rng(seed)
    rows = []
    for D in (2.0, 6.0):
        for Fr in (1.0, 5.0):
            F0, th0 = 100 * D * (1 + 0.1 * Fr), 0.5
            for b in range(1, beds + 1):
                bed = 1 + bed_scatter * rng.standard_normal()
                for R in (0.0, 4.0, 8.0, 12.0):
                    F = F0 * bed * (1 + shift[R])
                    th = th0 + (theta_shift if R == 4.0 else 0.0)
                    rows.append(dict(system=f"R{R:g}", D=D, h_requested=7.0, mu=0.5, kn=2e4, gamman=199.05, Fr=Fr,
                                     V=Fr * np.sqrt(D), seed=b, active_radius=R,
                                     drag=F * (1 + noise * rng.standard_normal()), drag_err=noise * F,
                                     theta=th + 0.005 * rng.standard_normal(), theta_err=0.005,
                                     n_contacts=4.0 * (1 + shift[R]), Z=4.5, asleep=R / 20, sanity="clean"))
    return pd.DataFrame(rows)


def test_active_region_names_the_smallest_radius_that_agrees_for_each_D():
    cmp = val.compare(region_runs({0.0: 0.0, 4.0: 0.15, 8.0: 0.0, 12.0: 0.0}), "active_region")
    assert cmp.paired.all() and set(cmp.variant) == {4.0, 8.0, 12.0} and len(cmp) == 12
    assert not cmp[cmp.variant == 4].agrees.any() and cmp[cmp.variant > 4].agrees.all()
    assert cmp[cmp.variant == 4].n_contacts_rel_diff.to_numpy() == pytest.approx(0.15)
    text = val.conclusion(cmp, "active_region")
    assert "D = 2: 8 d (4 D)" in text and "D = 6: 8 d (1.33 D)" in text
    assert "asleep over a pull: 4 d: 20 %, 8 d: 40 %, 12 d: 60 %" in text
    # A radius whose drag agrees but whose theta does not is no agreement.
    cmp = val.compare(region_runs({R: 0.0 for R in (0.0, 4.0, 8.0, 12.0)}, theta_shift=0.05), "active_region")
    assert cmp[cmp.variant == 4].theta_z.abs().min() > 2 and not cmp[cmp.variant == 4].agrees.any()
    assert "D = 2: 8 d" in val.conclusion(cmp, "active_region")
    # Disagreement at the widest radius: none agrees, whatever the narrower ones say.
    cmp = val.compare(region_runs({0.0: 0.0, 4.0: 0.0, 8.0: 0.0, 12.0: 0.2}), "active_region")
    assert "D = 2: none agrees (below a wider radius that does not: 4 d, 8 d)" in val.conclusion(cmp, "active_region")
    # ... and one that agrees below a miss is named beside the smallest of the contiguous ones.
    cmp = val.compare(region_runs({0.0: 0.0, 4.0: 0.0, 8.0: 0.2, 12.0: 0.0}), "active_region")
    assert "D = 2: 12 d (6 D) (below a wider radius that does not: 4 d)" in val.conclusion(cmp, "active_region")


def test_a_study_through_beds_placed_by_height_compares_each_height_apart():
    # Beds placed by height (z~, as faithful.yaml's systems) have no requested depth: their points
    # are told apart by the requested height, and a NaN key is a value like any other.
    runs = region_runs({0.0: 0.0, 4.0: 0.15, 8.0: 0.0, 12.0: 0.0})
    runs = runs.assign(h_requested=np.nan, z_requested=np.where(runs.Fr == 1.0, 13.5, 20.0))
    cmp = val.compare(runs, "active_region")
    assert len(cmp) == 12 and set(cmp.z_requested) == {13.5, 20.0} and cmp.h_requested.isna().all()
    assert not cmp[cmp.variant == 4].agrees.any() and cmp[cmp.variant > 4].agrees.all()
    # One height only, as config/validate/active_region_40_deep.yaml: still one point per Fr and D.
    cmp = val.compare(runs.assign(z_requested=13.5), "active_region")
    assert len(cmp) == 12 and (cmp.z_requested == 13.5).all()


def test_active_region_tells_apart_regions_of_one_radius_with_other_wake_tests():
    """Two regions of one radius that wake their grains differently are two variants, each
    against the reference: a shift in one does not hide in a mean with the other."""
    runs = region_runs({0.0: 0.0, 4.0: 0.0, 8.0: 0.0, 12.0: 0.0}, beds=3)
    runs = runs[runs.active_radius.isin([0.0, 8.0])]
    runs = runs.assign(wake_force=np.where(runs.active_radius > 0, 0.5, np.nan))
    shifted = runs[runs.active_radius == 8.0].assign(wake_force=1.0, system="R8_w1")
    shifted = shifted.assign(drag=shifted.drag * 1.2)
    cmp = val.compare(pd.concat([runs, shifted], ignore_index=True), "active_region")
    assert len(cmp) == 8 and set(cmp.wake_force) == {0.5, 1.0} and (cmp.beds == 3).all()
    assert cmp[cmp.wake_force == 0.5].agrees.all() and not cmp[cmp.wake_force == 1.0].agrees.any()
    assert cmp[cmp.wake_force == 1.0].rel_diff.to_numpy() == pytest.approx(0.2, abs=0.03)
    text = val.conclusion(cmp, "active_region")
    assert "active_radius = 8 (wake_force 0.5) against 0: agrees at 4 of 4" in text, text
    assert "active_radius = 8 (wake_force 1) against 0: agrees at 0 of 4" in text, text
    assert "D = 2 (wake_force 0.5): 8 d (4 D)" in text and "D = 2 (wake_force 1): none agrees" in text, text
    # One wake test only: the sentences stay as they were.
    assert "wake_force" not in val.conclusion(val.compare(runs.drop(columns="wake_force"), "active_region"),
                                             "active_region")


def test_active_region_tells_apart_wake_tests_relative_to_the_load():
    """wake_load is a setting like wake_force: regions of one radius and wake_force that differ in
    it are two variants, each named by it."""
    runs = region_runs({0.0: 0.0, 4.0: 0.0, 8.0: 0.0, 12.0: 0.0}, beds=3)
    runs = runs[runs.active_radius.isin([0.0, 8.0])]
    on = runs.active_radius > 0
    runs = runs.assign(wake_force=np.where(on, 0.5, np.nan), wake_load=np.where(on, 0.0, np.nan))
    loaded = runs[on].assign(wake_load=0.1, system="R8_load", drag=runs[on].drag * 1.2)
    cmp = val.compare(pd.concat([runs, loaded], ignore_index=True), "active_region")
    assert set(cmp.wake_load) == {0.0, 0.1}
    assert cmp[cmp.wake_load == 0.0].agrees.all() and not cmp[cmp.wake_load == 0.1].agrees.any()
    text = val.conclusion(cmp, "active_region")
    assert "active_radius = 8 (wake_load 0.1) against 0" in text, text
    assert "active_radius = 8 (wake_load 0) against 0: agrees at 4 of 4" in text, text


def test_active_region_tells_apart_rest_tests_and_names_only_settings_off_their_default():
    runs = region_runs({0.0: 0.0, 4.0: 0.0, 8.0: 0.0, 12.0: 0.0}, beds=3)
    runs = runs[runs.active_radius.isin([0.0, 8.0])]
    on = runs.active_radius > 0
    runs = runs.assign(wake_force=np.where(on, 0.5, np.nan), sleep_speed=np.where(on, 0.01, np.nan))
    strict = runs[runs.active_radius == 8.0].assign(sleep_speed=0.001, system="R8_strict")
    strict = strict.assign(drag=strict.drag * 1.2)
    cmp = val.compare(pd.concat([runs, strict], ignore_index=True), "active_region")
    assert set(cmp.sleep_speed) == {0.01, 0.001} and set(cmp.wake_force) == {0.5}
    assert not cmp[cmp.sleep_speed == 0.001].agrees.any() and cmp[cmp.sleep_speed == 0.01].agrees.all()
    text = val.conclusion(cmp, "active_region")
    # sleep_speed varies: named; wake_force is 0.5, the default, everywhere: not named
    assert "active_radius = 8 (sleep_speed 0.001) against 0: agrees at 0 of 4" in text, text
    assert "active_radius = 8 (sleep_speed 0.01) against 0" in text and "wake_force" not in text, text


def damped_runs(shift, beds=3, bed_scatter=0.05, seed=2):
    """Runs of a settling-damping study: beds poured without (system I) and with the damping
    (I_damped, other beds), at a yield speed and Fr = 1; the damped beds' drag is F0 (1 + shift)."""
    rng = np.random.default_rng(seed)
    rows = []
    for sd in (0.0, 1.0):
        system = "I" if sd == 0 else "I_damped"
        for Fr in (0.03, 1.0):
            for b in range(1, beds + 1):
                F = 100 * (1 + Fr) * (1 + (shift if sd else 0.0)) * (1 + bed_scatter * rng.standard_normal())
                rows.append(dict(system=system, D=2.0, h=6.4, h_requested=6.5, mu=0.5, kn=2e4, gamman=199.05,
                                 Fr=Fr, V=Fr, seed=b, drag=F, drag_err=0.02 * F, theta=1.5, theta_err=0.01,
                                 n_contacts=4.0, Z=4.5, kappa=1.0, settle_damping=sd, sanity="clean",
                                 run=f"pulls/system~{system}/D~2/h~6.5/mu~0.5/kn~2e4/gn~199.05/seed~{b}/Fr~{Fr:g}"))
    return pd.DataFrame(rows)


def test_settle_damping_compares_other_beds_by_their_means_and_scatter():
    cmp = val.compare(damped_runs(0.0), "settle_damping")
    assert not cmp.paired.any() and set(cmp.reference) == {0.0} and set(cmp.variant) == {1.0}
    assert len(cmp) == 2 and (cmp.beds == 3).all() and cmp.agrees.all()
    assert "Settling damping whose beds give the paper's pour's drag at every point: 1." in \
        val.conclusion(cmp, "settle_damping")
    # A 30 % higher drag in the damped beds is far outside 5 % bed scatter over 3 beds.
    cmp = val.compare(damped_runs(0.3), "settle_damping")
    assert not cmp.agrees.any() and cmp.rel_diff.min() > 0.15
    assert "at every point: none." in val.conclusion(cmp, "settle_damping")


def test_placement_compares_placed_beds_with_poured_ones_and_says_where_they_differ():
    runs = damped_runs(0.0).rename(columns={"settle_damping": "placed"})
    cmp = val.compare(runs, "placement")
    assert not cmp.paired.any() and set(cmp.reference) == {0.0} and set(cmp.variant) == {1.0}
    assert cmp.agrees.all() and "pull as beds poured with the intruder in place" in val.conclusion(cmp, "placement")
    bad = val.conclusion(val.compare(damped_runs(0.3).rename(columns={"settle_damping": "placed"}), "placement"),
                         "placement")
    assert "disagree with the paper's pour (|z| >= 2) at 2 of 2 points: D = 2, h = 6.5, mu = 0.5" in bad, bad


def test_flagged_runs_and_missing_variants_are_named(tmp_path):
    runs = yield_runs({0.01: 0.0, 0.03: 0.0, 0.1: 0.0})
    runs.loc[runs.V != 0.01, "sanity"] = "overlap 0.3 d > max_overlap"
    with pytest.raises(val.ValidationError, match="no point was run at two or more values of V"):
        val.compare(runs, "yield_speed")
    with pytest.raises(val.ValidationError, match="unknown validation study 'speed'"):
        val.validate(runs, "speed", tmp_path)


def test_validate_writes_figure_table_and_sentence(tmp_path):
    paths = val.validate(yield_runs({0.01: 0.0, 0.03: 0.0, 0.1: 0.08}), "yield_speed", tmp_path)
    names = sorted(p.name for p in paths)
    assert names == ["validate_yield_speed.csv", "validate_yield_speed.md", "validate_yield_speed.pdf",
                     "validate_yield_speed.png"]
    assert (tmp_path / "validate_yield_speed.png").stat().st_size > 5000
    back = pd.read_csv(tmp_path / "validate_yield_speed.csv")
    assert len(back) == 8 and {"z", "rel_diff", "agrees"} <= set(back.columns)
    assert "V = 0.03 instead of 0.01" in (tmp_path / "validate_yield_speed.md").read_text()


def test_the_md_lists_every_point_with_its_difference_z_and_verdict(tmp_path):
    """The table under the sentence has one row per comparison, each row's z and difference as
    the csv has them, and marks the points that disagree (an 8 % shift at V = 0.1, 1 % noise)."""
    val.validate(yield_runs({0.01: 0.0, 0.03: 0.0, 0.1: 0.08}), "yield_speed", tmp_path)
    cmp = pd.read_csv(tmp_path / "validate_yield_speed.csv")
    md = (tmp_path / "validate_yield_speed.md").read_text()
    rows = [line for line in md.splitlines() if line.startswith("| ") and not line.startswith("| D ")]
    assert md.count("| D | μ | V |") == 1 and len(rows) == len(cmp) == 8
    for _, r in cmp.iterrows():
        cells = f"| {r.D:g} | {r.mu:g} | {r.variant:g} | {100 * r.rel_diff:+.1f} ± {100 * r.rel_diff_err:.1f} % | " \
                f"{r.z:+.2f} | " + ("yes" if r.agrees else "**no**") + " |"
        assert cells in rows, (cells, rows)
    assert sum("**no**" in line for line in rows) == int((~cmp.agrees).sum()) >= 1
    assert all("**no**" in line for line in rows if "| 0.1 |" in line)


def test_the_point_table_tells_apart_variants_that_differ_in_a_setting_alone():
    """Two regions of one radius, one with wake_force unset (NaN) and one at 1: the table shows
    the setting's column, so the rows that agree and disagree are told apart, and a judged
    observable shifted the same in every pull (error 0) shows its z as infinite, not missing."""
    runs = region_runs({0.0: 0.0, 4.0: 0.0, 8.0: 0.0, 12.0: 0.0}, beds=3)
    runs = runs[runs.active_radius.isin([0.0, 8.0])]
    shifted = runs[runs.active_radius == 8.0].assign(wake_force=1.0, system="R8_w1")
    shifted = shifted.assign(drag=shifted.drag * 1.2)
    runs = pd.concat([runs, shifted], ignore_index=True)
    cmp = val.compare(runs, "active_region")
    table = point_table(cmp, val.STUDIES["active_region"])
    head, _, *rows = [line for line in table.splitlines() if line.startswith("|")]
    assert table.startswith("\nEvery point (z: the difference over its error; |z| < 2 agrees):")
    assert "wake_force" in head.split(" | ") and len(rows) == len(cmp) == 8
    assert {r.split(" | ")[2] for r in rows} == {"–", "1"}                 # D | Fr | wake_force | active_radius
    assert all(("**no**" in r) == (r.split(" | ")[2] == "1") for r in rows)
    cmp = cmp.assign(theta_z=np.where(cmp.wake_force == 1.0, np.inf, cmp.theta_z))
    assert sum("+∞" in r for r in point_table(cmp, val.STUDIES["active_region"]).splitlines()) == 4


def test_paired_rows_report_the_scatter_of_the_per_bed_differences():
    """Pulls through one bed that share their fluctuations: a shift of 2 % the same in every
    bed hides inside the runs' 5 % errors (z < 2) but not inside the differences' own scatter."""
    rng = np.random.default_rng(5)
    rows = []
    for b in range(1, 6):
        common = 1 + 0.05 * rng.standard_normal()     # the bed's path: the same in both pulls
        for R, shift in ((0.0, 0.0), (12.0, 0.02)):
            F = 100 * common * (1 + shift) * (1 + 0.002 * rng.standard_normal())
            rows.append(dict(system=f"R{R:g}", D=6.0, h_requested=7.0, mu=0.5, kn=2e4, gamman=199.05, Fr=1.0,
                             V=1.0, seed=b, active_radius=R, drag=F, drag_err=5.0, theta=1.0 + shift,
                             theta_err=0.05, n_contacts=80.0, Z=4.5, sanity="clean"))
    cmp = val.compare(pd.DataFrame(rows), "active_region")
    row = cmp.iloc[0]
    assert abs(row.z) < 1 and row.agrees                               # 2 / (5 sqrt(2/5)) = 0.6
    d = np.array([r2["drag"] - r1["drag"] for r1, r2 in zip(rows[::2], rows[1::2])])
    assert row.drag_beds_err == pytest.approx(d.std(ddof=1) / np.sqrt(5))
    assert row.drag_beds_z > 5 and row.theta_beds_z == np.inf                # theta: +0.02 exactly
    # a shift the same in every bed to the last digit (t infinite) is resolved like any other
    assert "(theta: t inf, 4 dof)" in val.resolved_shifts(cmp, val.STUDIES["active_region"])
    two = val.compare(pd.DataFrame([r for r in rows if r["seed"] <= 2]), "active_region")
    assert np.isnan(two.iloc[0].drag_beds_z) and np.isnan(two.iloc[0].theta_beds_err)


def test_the_sentence_names_a_shift_the_beds_resolve_and_only_that():
    """A 3 % shift the same in every bed hides inside 5 % run errors (every point agrees) but the
    per-bed differences resolve it: the sentence names each such point with its size and t; with
    no shift it names none."""
    shifted = yield_runs({0.01: 0.0, 0.03: 0.0, 0.1: 0.03}, beds=5, noise=0.05, seed=3)
    # the pulls through one bed share their fluctuations: the runs' noise is common to both
    # speeds, so the per-bed differences carry the shift alone, plus a little noise of their own
    rng = np.random.default_rng(7)
    base = shifted[shifted.V == 0.01].set_index(["D", "mu", "seed"]).drag
    for V, f in ((0.03, 1.0), (0.1, 1.03)):
        rows = shifted.V == V
        keys = list(zip(shifted.loc[rows, "D"], shifted.loc[rows, "mu"], shifted.loc[rows, "seed"]))
        shifted.loc[rows, "drag"] = [base[k] * f * (1 + 0.002 * rng.standard_normal()) for k in keys]
    cmp = val.compare(shifted, "yield_speed")
    fast = cmp[cmp.variant == 0.1]
    assert fast.agrees.all() and (fast.drag_beds_z > 5).all()
    text = val.conclusion(cmp, "yield_speed")
    assert "The beds resolve a shift" in text
    named = text.split("The beds resolve a shift")[1]
    assert named.count("V = 0.1 at D = ") == 4 and "V = 0.03" not in named
    assert "(drag: +3.0 %, t " in named and "4 dof" in named
    # no shift: the per-bed differences are noise, whose t is Student's, so a point passes t's
    # 97.5 % point at 4 dof (2.776) by chance now and then: exactly those are named, over many draws
    limit = 2.776
    beyond_total = 0
    for seed in range(5):
        quiet = val.compare(yield_runs({0.01: 0.0, 0.03: 0.0, 0.1: 0.0}, beds=5, noise=0.05, seed=seed),
                            "yield_speed")
        beyond = quiet[quiet.drag_beds_z.abs() > limit]
        said = val.resolved_shifts(quiet, val.STUDIES["yield_speed"])
        assert said.count(" at D = ") == len(beyond)
        assert all(f"V = {r.variant:g} at D = {r.D:g}, mu = {r.mu:g} (drag: {100 * r.rel_diff:+.1f} %" in said
                   for r in beyond.itertuples())
        beyond_total += len(beyond)
    assert beyond_total <= 8   # of 40 points, 2 expected by chance


def test_a_reference_replica_widens_paired_errors_to_the_chaos_it_measures():
    """theta's run errors (0.01) are narrower than how far two pulls through one bed drift
    apart (chaos: 0.04 per run): a shift of 0.03 looks real against the errors (z > 2) and is
    not against the replicas; the reference is the mean of a bed's pull and its replica."""
    rng = np.random.default_rng(11)
    rows = []
    for b in range(1, 7):
        common = 1 + 0.05 * rng.standard_normal()
        for system, R, eps, shift in (("I", 0.0, 0.0, 0.0), ("I_replica", 0.0, 1e-9, 0.0), ("R18", 18.0, 0.0, 0.03)):
            theta = 2.0 + shift + 0.04 * rng.standard_normal()
            rows.append(dict(system=system, D=6.0, h_requested=7.0, mu=0.5, kn=2e4, gamman=199.05, Fr=0.05, V=0.03,
                             seed=b, active_radius=R, perturbation=eps, drag_err=5.0, theta=theta,
                             drag=100 * common * (1 + 0.001 * rng.standard_normal()),
                             theta_err=0.01, n_contacts=80.0 + 10 * shift, Z=4.5, sanity="clean"))
    runs = pd.DataFrame(rows)
    plain = val.compare(runs[runs.perturbation == 0], "active_region").iloc[0]
    row = val.compare(runs, "active_region").iloc[0]
    assert len(val.compare(runs, "active_region")) == 1 and row.variant == 18.0   # the replica is no variant
    assert row.replicas == 6 and "replicas" not in plain.index
    sd = runs.pivot(index="seed", columns="system", values="theta")
    assert row.theta_chaos_sd == pytest.approx(np.sqrt(((sd.I - sd.I_replica)**2).mean() / 2))
    assert 0.02 < row.theta_chaos_sd < 0.07
    ref = (sd.I + sd.I_replica) / 2
    assert row.theta_diff == pytest.approx((sd.R18 - ref).mean())
    # Per bed the chaos, sigma^2 (1 + 1/2), exceeds the errors' 0.01^2 + 0.01^2 / 2.
    assert row.theta_diff_err == pytest.approx(row.theta_chaos_sd * np.sqrt(1.5 / 6))
    assert abs(plain.theta_z) > 2 > abs(row.theta_z) and row.agrees and not plain.agrees
    # The drag's run errors (5 %) exceed its chaos (0.1 % here): they stay.
    assert row.drag_chaos_sd < 0.5
    assert row.rel_diff_err == pytest.approx(np.sqrt(5**2 + 5**2 / 2) / np.sqrt(6) / row.drag_ref)
    text = val.conclusion(val.compare(runs, "active_region"), "active_region")
    assert "differ by chaos alone by (per run, over the points) drag" in text


def test_two_replicas_of_a_bed_make_a_reference_of_three_pulls():
    rng = np.random.default_rng(12)
    rows = []
    for b in range(1, 5):
        for system, R, eps in (("I", 0.0, 0.0), ("I_r1", 0.0, 1e-9), ("I_r2", 0.0, 2e-9), ("R18", 18.0, 0.0)):
            rows.append(dict(system=system, D=6.0, h_requested=7.0, mu=0.5, kn=2e4, gamman=199.05, Fr=0.05,
                             V=0.03, seed=b, active_radius=R, perturbation=eps, drag=100 + rng.standard_normal(),
                             drag_err=5.0, theta=2.0 + 0.05 * rng.standard_normal(), theta_err=0.01,
                             n_contacts=80.0, Z=4.5, sanity="clean"))
    runs = pd.DataFrame(rows)
    row = val.compare(runs, "active_region").iloc[0]
    th = runs.pivot(index="seed", columns="system", values="theta")
    ref = (th.I + th.I_r1 + th.I_r2) / 3
    assert row.replicas == 4 and row.theta_diff == pytest.approx((th.R18 - ref).mean())
    # a bed's pull against its two replicas' mean: variance sigma^2 (1 + 1/2)
    gap2 = (th.I - (th.I_r1 + th.I_r2) / 2)**2 / 1.5
    assert row.theta_chaos_sd == pytest.approx(np.sqrt(gap2.mean()))
    # the reference's run error: three pulls of 0.01 averaged; the chaos: sigma^2 (1 + 1/3)
    per_bed = max(0.01**2 + 0.01**2 / 3, row.theta_chaos_sd**2 * (1 + 1 / 3))
    assert row.theta_diff_err == pytest.approx(np.sqrt(4 * per_bed) / 4)


def test_a_replica_whose_nudge_did_not_grow_is_left_out_and_named():
    """In a slow, deep pull a 1e-9 nudge stays with its pull (gaps far below the runs' errors):
    counted as chaos it would measure almost none and weigh the reference pull twice. It is left
    out and named; a harder nudge that parted measures the chaos; with none parted, the sentence
    says the chaos is not measured."""
    rng = np.random.default_rng(13)
    rows = []
    for b in range(1, 6):
        theta_ref = 2.0 + 0.1 * rng.standard_normal()
        for system, R, eps in (("I", 0.0, 0.0), ("I_replica", 0.0, 1e-9), ("I_nudge", 0.0, 1e-2), ("R6", 6.0, 0.0)):
            stuck = system == "I_replica"
            theta = theta_ref + (1e-4 if stuck else 0.0) if system in ("I", "I_replica") else \
                2.0 + 0.1 * rng.standard_normal()
            rows.append(dict(system=system, D=2.0, h_requested=np.nan, z_requested=13.5, mu=0.5, kn=2e4,
                             gamman=199.05, Fr=0.13, V=0.1, seed=b, active_radius=R, perturbation=eps,
                             drag=470 + (0.5 if stuck else 0.0) + (0 if system in ("I", "I_replica")
                                                                  else 15 * rng.standard_normal()),
                             drag_err=25.0, theta=theta, theta_err=0.08, n_contacts=40.0, Z=4.5, sanity="clean"))
    runs = pd.DataFrame(rows)
    th = runs.pivot(index="seed", columns="system", values="theta")
    row = val.compare(runs, "active_region").iloc[0]
    assert row.replicas_unparted == "1e-09" and row.replicas == 5
    # the reference is each bed's pull and the parted replica; the chaos their gaps alone
    assert row.theta_diff == pytest.approx((th.R6 - (th.I + th.I_nudge) / 2).mean())
    assert row.theta_chaos_sd == pytest.approx(np.sqrt(((th.I - th.I_nudge)**2).mean() / 2))
    text = val.conclusion(val.compare(runs, "active_region"), "active_region")
    assert "Replicas nudged by 1e-09 stayed with their pull" in text and "not measured" not in text
    # Only the stuck replica: nothing is folded, and the sentence says the chaos went unmeasured.
    alone = runs[runs.system != "I_nudge"]
    row = val.compare(alone, "active_region").iloc[0]
    assert row.replicas_unparted == "1e-09" and "replicas" not in row.index
    assert row.theta_diff == pytest.approx((th.R6 - th.I).mean())
    assert "the chaos between pulls is not measured" in val.conclusion(val.compare(alone, "active_region"),
                                                                      "active_region")
    # A replica that parted is kept whatever its nudge (the first study's 1e-9 replicas did).
    parted = runs[runs.system != "I_replica"].replace({"perturbation": {1e-2: 1e-9}})
    assert val.compare(parted, "active_region").iloc[0].replicas_unparted == ""


def test_active_region_tells_apart_dwell_times():
    # Two regions of one radius and wake and rest tests that hold grains after other dwell times
    # (sleep_time) are other variants: each compared with the reference on its own, and named
    runs = region_runs({0.0: 0.0, 4.0: 0.0, 8.0: 0.0, 12.0: 0.0}, beds=3)
    runs = runs[runs.active_radius.isin([0.0, 8.0])]
    on = runs.active_radius > 0
    runs = runs.assign(wake_force=np.where(on, 0.5, np.nan), sleep_speed=np.where(on, 0.003, np.nan),
                       sleep_time=np.where(on, 1.0, np.nan))
    short = runs[runs.active_radius == 8.0].assign(sleep_time=0.5, system="R8_short")
    short = short.assign(drag=short.drag * 1.2)
    cmp = val.compare(pd.concat([runs, short], ignore_index=True), "active_region")
    assert set(cmp.sleep_time) == {1.0, 0.5}
    assert not cmp[cmp.sleep_time == 0.5].agrees.any() and cmp[cmp.sleep_time == 1.0].agrees.all()
    text = val.conclusion(cmp, "active_region")
    assert "active_radius = 8 (sleep_time 0.5) against 0: agrees at 0 of" in text, text
    # it varies, so the default is named too; the wake and rest tests at their defaults are not
    assert "active_radius = 8 (sleep_time 1) against 0: agrees at 4 of 4" in text, text
    assert "wake_force" not in text and "sleep_speed" not in text, text


def test_a_study_over_named_systems_labels_them_by_name(tmp_path):
    """The smoke study pulls two systems (I, II): the figure's series and the sentence name them,
    where a %g format of the name once stopped `validate yield_speed` with a format error."""
    runs = pd.concat([yield_runs({0.01: 0.0, 0.03: 0.0, 0.1: 0.0}).assign(system=s, seed=lambda d, k=k: d.seed + k)
                      for k, s in ((0, "I"), (10, "II"))], ignore_index=True)
    paths = val.validate(runs, "yield_speed", tmp_path)
    assert (tmp_path / "validate_yield_speed.png").stat().st_size > 5000 and len(paths) == 4
    assert val.label_value("II") == "II" and val.label_value(np.float64(0.03)) == "0.03"


def test_a_variant_equal_to_its_reference_to_the_last_digit_agrees():
    """Identical numbers with no error (a setting that changes nothing, bit for bit): z is 0, not
    the NaN of inf * sign(0), and the point agrees; a difference without error stays infinite."""
    from analysis.validation.agreement import z_score
    assert z_score(0.0, 0.0) == 0.0 and z_score(-1.0, 0.0) == -np.inf and z_score(1.0, 2.0) == 0.5
    rows = [dict(system=f"R{R:g}", D=6.0, h_requested=7.0, mu=0.5, kn=2e4, gamman=199.05, Fr=1.0, V=1.0, seed=b,
                 active_radius=R, drag=100.0 + b, drag_err=0.0, theta=1.0, theta_err=0.0, n_contacts=80.0, Z=4.5,
                 sanity="clean") for b in range(1, 4) for R in (0.0, 12.0)]
    row = val.compare(pd.DataFrame(rows), "active_region").iloc[0]
    assert row.z == 0 and row.theta_z == 0 and row.drag_beds_z == 0 and row.agrees
