"""Validation studies: does a cheaper protocol give the paper's numbers within errors?

Each study varies one thing of the protocol — the yield pull's speed, the box, the stiffness,
the active region's radius — and compares the drag of every point (same D, μ, depth and, for pulls at speed, Fr)
with its value under the reference protocol (the slowest yield speed, the largest box, the stiffest K_n). A
variant agrees at a point when

    z = (F - F_ref) / sqrt(e^2 + e_ref^2),  |z| < Z_AGREE,

with e the drag's error. Where the variants were pulled through the same beds (the yield speed: one bed,
several speeds; replicate beds by `seeds`), the comparison is paired, bed by bed: the bed's own randomness
is common to both pulls and cancels, so the difference carries only the pulls' within-run errors. That error
is an upper bound: two pulls through one bed meet the same grains, so their fluctuations are correlated too
(in the 40 d box's D = 6 yield pulls the per-bed drag differences scattered 3-6x less than it). With three
or more beds the scatter of the per-bed differences measures the paired error directly, and each paired row
reports it (`<obs>_beds_err`, `<obs>_beds_z`, for the drag and every judged observable; a Student t with
beds - 1 dof): a shift smaller than the runs' errors but the same in every bed shows there. The verdict
stays on z. Elsewhere (other boxes and stiffnesses need their own beds) the point table's errors, which
include the scatter between beds, are used.

The runs' errors can also be too narrow: theta's misses part of how far two pulls through one bed drift apart by
chaos. A reference system pulled a second time with a perturbation (`granudrag pull --perturbation 1e-9`, a
replica; its `perturbation` column > 0) measures that: the reference becomes the mean of each bed's pull and its
replica, and no paired error is taken below the chaos the replicas show (`_fold_replicas`). A nudge that does
not grow over the pull (1e-9 in a slow, deep yield pull) leaves the replica on its reference: such replicas are
left out and named (`_parted`), and a harder nudge (1e-3, 1e-2) measures the chaos there.

    python -m analysis validate yield_speed results/validate/runs.csv --output-dir DIR

writes DIR/validate_<study>.png, .pdf, .csv (every comparison) and .md (the sentence, every point).
"""

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..core.table import combine_beds, write_csv, write_text_atomic
from . import pull_length
from .agreement import Z_AGREE, ValidationError, label_value, z_score
from .validation_beds import placement_answer, settle_damping_answer
from .validation_points import point_table
from .validation_shifts import resolved_shifts


@dataclass(frozen=True)
class Study:
    name: str
    variant: str        # the column that varies
    reference: str      # "min" or "max": which value is the reference protocol
    keys: tuple         # what must be equal for two runs to be the same point
    label: str          # the variant, as text
    paired: bool        # variants share beds: compare bed by bed
    question: str       # what the sentence answers
    # Observables judged besides the drag (each with its error column), and those only
    # reported as a relative difference (the run table gives them no error).
    also_judged: tuple = ()
    also_reported: tuple = ()
    # A variant's own settings (columns) that tell apart variants of the same value, each compared
    # with the reference on its own; the reference has none (the active region's wake_force and
    # rest tests, sleep_speed and sleep_time: two regions of one radius may wake or rest their
    # grains differently).
    settings: tuple = ()

    @property
    def judged(self):
        """Every judged observable with its error column, the drag first."""
        return (("drag", "drag_err"), *self.also_judged)


# Where the intruder was asked to be: a depth (h~) or a height (z~), the other NaN (analysis.runs.runs).
PLACEMENT = ("h_requested", "z_requested")

STUDIES = {
    "yield_speed": Study("yield_speed", "V", "min", ("system", "D", *PLACEMENT, "mu", "kn", "gamman"),
                         "V", True, "the fastest yield speed that agrees with the slowest at every point"),
    "box_size": Study("box_size", "lx", "max", ("D", *PLACEMENT, "mu", "kn", "gamman", "Fr"),
                      "box length lx (d)", False, "the smallest box that agrees with the largest, for each D"),
    "stiffness": Study("stiffness", "kn", "max", ("system", "D", *PLACEMENT, "mu", "Fr"),
                       "K_n", False, "how much the drag moves per decade of K_n"),
    # Pulls through the same beds with and without the active region (systems with beds_from):
    # the reference is active_radius = 0, every grain integrated.
    "active_region": Study("active_region", "active_radius", "min",
                           ("D", *PLACEMENT, "mu", "kn", "gamman", "Fr"), "active radius (d)", True,
                           "the smallest active radius that agrees with every grain integrated, for each D",
                           also_judged=(("theta", "theta_err"),), also_reported=("n_contacts", "Z"),
                           settings=("wake_force", "wake_load", "sleep_speed", "sleep_time")),
    # Beds poured with and without the settling damping (granudrag pour --settle_damping, systems
    # that differ in it alone): the reference is 0, the paper's pour. Other beds, so the drags are
    # compared as the points' means over their beds, with the bed scatter in their errors.
    "settle_damping": Study("settle_damping", "settle_damping", "min",
                            ("D", *PLACEMENT, "mu", "kn", "gamman", "Fr"), "settle_damping (sqrt(g/d))", False,
                            "whether beds poured with the settling damping pull as the paper's pour does"),
    # Beds placed into settled columns (granudrag place) against beds poured with the intruder in
    # place (the paper's protocol, placed = 0): other beds, compared as settle_damping's are.
    "placement": Study("placement", "placed", "min", ("D", *PLACEMENT, "mu", "kn", "gamman", "Fr"),
                       "placed (0: poured with the intruder, 1: placed)", False,
                       "whether beds with a placed intruder pull as the paper's pour does"),
    # The same beds pulled at coarser steps (granudrag pull --collision_steps; systems with
    # beds_from): the reference is the finest, 64 steps per collision time.
    "time_step": Study("time_step", "collision_steps", "max",
                       ("D", *PLACEMENT, "mu", "kn", "gamman", "Fr"), "steps per collision time", True,
                       "the fewest steps per collision time that agree with the finest at every point",
                       also_judged=(("theta", "theta_err"),), also_reported=("n_contacts", "Z")),
}


# granudrag pull's defaults of the settings a study tells variants apart by (its --help;
# tests/python/test_runs.py reads them back from a run): a label leaves out a setting at its
# default everywhere. wake_force's is that of K_n <= 2e5; a stiffer bed's default (2 at 2e6) is
# named like any other value.
SETTING_DEFAULTS = {"wake_force": 0.5, "wake_load": 0.0, "sleep_speed": 0.003, "sleep_time": 1.0}
# What studies run before a setting was recorded ran at, the defaults of then (sleep_speed was
# 0.01 until 2026-11-27): their comparison tables lack the column.
SETTINGS_BEFORE_RECORDED = {"wake_force": 0.5, "wake_load": 0.0, "sleep_speed": 0.01, "sleep_time": 1.0}


# Every study `validate` runs: the comparisons above, and the pull length (analysis.validation.pull_length),
# which asks how long one protocol's pulls must be rather than comparing two protocols.
NAMES = (*STUDIES, "pull_length")


# A replica of a reference pull (`granudrag pull --perturbation`, the runs table's column): not a
# variant, but a second pull through the same bed that differs by chaos alone.
REPLICA = "perturbation"


def _keys(df, study):
    keys = [k for k in study.keys if k in df.columns]
    if study.variant not in df.columns:
        raise ValidationError(f"{study.name}: the table has no column '{study.variant}'")
    return keys


def _rounded(df, keys):
    return df.assign(**{f"_{k}": df[k].round(6) if df[k].dtype.kind == "f" else df[k] for k in keys})


def compare(runs, study):
    """One row per (point, variant value other than the reference): the drags, the relative
    difference (F - F_ref) / F_ref with its error, z and whether they agree.

    `runs`: the run table (runs.csv; one row per pull, `seed` telling beds apart) or a point
    table (table.csv). Paired comparison for studies whose variants share beds."""
    if isinstance(study, str):
        study = STUDIES[study]
    keys = _keys(runs, study)
    if "sanity" in runs.columns:
        runs = runs[runs.sanity.fillna("clean") == "clean"]
    table = runs if (study.paired or "seed" not in runs.columns or "n_beds" in runs.columns) else combine_beds(runs)
    table = _rounded(table, keys + [study.variant])
    is_replica = table[REPLICA].fillna(0) > 0 if REPLICA in table.columns else pd.Series(False, table.index)
    gkeys = [f"_{k}" for k in keys]
    rows = []
    for _, g in _grouped(table, gkeys):  # NaN keys: the other placement
        replicas, g = g[is_replica.loc[g.index]], g[~is_replica.loc[g.index]]
        values = np.sort(g[f"_{study.variant}"].unique())
        if len(values) < 2:
            continue
        ref = values[0] if study.reference == "min" else values[-1]
        base = g[g[f"_{study.variant}"] == ref]
        replicas, unparted = _parted(base, replicas[replicas[f"_{study.variant}"] == ref], study)
        for v in values[values != ref]:
            other = g[g[f"_{study.variant}"] == v]
            for setting, variant in _by_settings(other, study):
                rows.append(_difference(base, variant, study, keys, ref, v, replicas) | setting
                            | {"replicas_unparted": unparted})
    if not rows:
        raise ValidationError(
            f"{study.name}: no point was run at two or more values of {study.variant} "
            f"(points are told apart by {', '.join(keys)})")
    return pd.DataFrame(rows)


def settings_set(df, study):
    """The study's settings columns that the table has and that are set somewhere."""
    return [c for c in study.settings if c in df.columns and df[c].notna().any()]


def _by_settings(other, study):
    """(settings as a dict, runs) for each combination of the study's settings among one
    variant's runs; ({}, all of them) for a study without settings."""
    cols = settings_set(other, study)
    if not cols:
        return [({}, other)]
    return [(dict(zip(cols, key)), g) for key, g in _grouped(other, cols)]


def _grouped(df, cols):
    """(key as a tuple, rows) per combination of `cols`, NaN a value like any other."""
    for key, g in df.groupby(cols if len(cols) > 1 else cols[0], dropna=False, sort=True):
        yield (key if isinstance(key, tuple) else (key,)), g


def shown_settings(cmp, study):
    """The settings a label names: those that vary in the comparison or differ from granudrag's
    default somewhere (a setting at its default everywhere says nothing)."""
    return {c for c in settings_set(cmp, study)
            if cmp[c].nunique() > 1 or (cmp[c].dropna() != SETTING_DEFAULTS.get(c, np.nan)).any()}


def _setting_label(cols, values, shown=None):
    """" (wake_force 1)" for the settings that are set (and in `shown`, if given), "" for none."""
    text = ", ".join(f"{c} {label_value(v)}" for c, v in zip(cols, values)
                     if pd.notna(v) and (shown is None or c in shown))
    return f" ({text})" if text else ""


def _variants(cmp, study, unit=""):
    """The comparison's rows grouped by variant, as (label, rows): the value with `unit`, and the
    settings that tell variants of one value apart ("6 d (wake_force 1)")."""
    cols, shown = settings_set(cmp, study), shown_settings(cmp, study)
    out = []
    for key, g in _grouped(cmp, ["variant", *cols]):
        out.append((f"{key[0]:g}{unit}" + _setting_label(cols, key[1:], shown), g))
    return out


def _difference(base, other, study, keys, ref, v, replicas=None):
    first = base.iloc[0]
    row = {k: first[k] for k in keys} | {"reference": ref, "variant": v}
    if study.paired and "seed" in base.columns:
        pairs = base.merge(other, on="seed", suffixes=("_ref", ""))
        if len(pairs):
            if replicas is not None and len(replicas):
                pairs, row = _fold_replicas(pairs, replicas, study, row)
            d = pairs.drag - pairs.drag_ref
            de2 = _paired_variance(pairs, "drag", "drag_err")
            f_ref, f = pairs.drag_ref.mean(), pairs.drag.mean()
            diff, diff_err = d.mean(), np.sqrt(de2.sum()) / len(pairs)
            row |= {"drag_ref": f_ref, "drag": f, "beds": len(pairs), "paired": True,
                    "drag_err_ref": np.sqrt((pairs.drag_err_ref**2).sum()) / len(pairs),
                    "drag_err": np.sqrt((pairs.drag_err**2).sum()) / len(pairs)}
            if "asleep" in pairs.columns:
                row["asleep"] = pairs.asleep.mean()
            return _also(_verdict(row, diff, diff_err) | _beds("drag", d), pairs, study)
    f_ref, e_ref = base.drag.mean(), np.sqrt((base.drag_err**2).sum()) / len(base)
    f, e = other.drag.mean(), np.sqrt((other.drag_err**2).sum()) / len(other)
    row |= {"drag_ref": f_ref, "drag": f, "drag_err_ref": e_ref, "drag_err": e,
            "beds": int(other.get("n_beds", pd.Series([len(other)])).iloc[0]), "paired": False}
    return _verdict(row, f - f_ref, np.hypot(e, e_ref))


def _also(row, pairs, study):
    """The paired comparison of the study's other observables: z and agreement for those with
    an error (the row agrees only if they all do), the relative difference for the rest."""
    for col, err in study.also_judged:
        diffs = pairs[col] - pairs[f"{col}_ref"]
        d = diffs.mean()
        de = np.sqrt(_paired_variance(pairs, col, err).sum()) / len(pairs)
        z = z_score(d, de)
        row |= {f"{col}_diff": d, f"{col}_diff_err": de, f"{col}_z": z} | _beds(col, diffs)
        row["agrees"] = bool(row["agrees"] and abs(z) < Z_AGREE)
    for col in study.also_reported:
        ref = pairs[f"{col}_ref"].mean()
        row[f"{col}_rel_diff"] = (pairs[col].mean() - ref) / ref if ref else np.nan
    return row


# A replica counts as parted from its reference pull when, in some judged observable, its gaps
# from it (RMS over the beds) reach this fraction of the two runs' own errors. Pulls parted by
# chaos differ by about their errors (0.5-1.5x in the studies so far); a nudge that has not grown
# leaves them 10-1000x closer (1e-9 in the deep yield pulls of active_region_40_deep.yaml: 0.02x
# in the drag and 0.13x in theta, while nudges of 1e-3 and 1e-2 reached 0.5-1.5x). Counted as
# chaos, such a replica measures almost none and weighs the reference pull twice.
PARTED = 0.25


def _parted(base, replicas, study):
    """The replicas that parted from their bed's reference pull, and the nudges (perturbation
    values, as text) of those that did not: each set of one nudge is judged over its beds."""
    if not len(replicas) or "seed" not in base.columns:
        return replicas, ""
    keep, unparted = [], []
    for nudge, reps in replicas.groupby(REPLICA):
        pairs = base.merge(reps, on="seed", suffixes=("_ref", ""))
        ratios = [np.sqrt(((pairs[c] - pairs[f"{c}_ref"])**2).mean()
                          / (pairs[e]**2 + pairs[f"{e}_ref"]**2).mean())
                  for c, e in study.judged if c in pairs.columns and len(pairs)]
        ratios = [r for r in ratios if np.isfinite(r)]
        if ratios and max(ratios) < PARTED:
            unparted.append(f"{nudge:g}")
        else:
            keep.append(reps)
    return (pd.concat(keep) if keep else replicas.iloc[:0]), ", ".join(unparted)


def _fold_replicas(pairs, replicas, study, row):
    """The reference of each bed with replicas (pulls of it parted by chaos alone: `granudrag
    pull --perturbation`) becomes the mean of its m pulls, and the replicas measure the chaos:
    sigma^2 per run from the gaps between a bed's pull and its k = m - 1 replicas' mean,
    <gap^2 / (1 + 1/k)> over two or more beds. Against a reference of m pulls a variant then
    differs by chaos alone with variance sigma^2 (1 + 1/m), which `_paired_variance` takes when it
    exceeds the runs' own errors (theta's error misses part of it: in the 40 d box's D = 6 yield
    pulls two replicas differed 1.4x and 2.6x more than it said, in two sets of five beds)."""
    judged = study.judged
    errs = [e for _, e in judged]
    cols = [c for c, _ in judged] + [c for c in study.also_reported if c in replicas]
    by_seed = replicas.groupby("seed")
    rep = by_seed[cols].mean().join(by_seed[errs].agg(lambda e: float((e**2).sum())).add_suffix("_sq"))
    rep = rep.assign(k=by_seed.size()).add_suffix("_rep").reset_index()
    pairs = pairs.merge(rep, on="seed", how="left")
    has = pairs["drag_rep"].notna()
    k = pairs["k_rep"].fillna(0).to_numpy()
    m = 1.0 + k
    row = row | {"replicas": int(has.sum())}
    for col, err in judged:
        gap2 = ((pairs[f"{col}_ref"] - pairs[f"{col}_rep"])**2 / (1 + 1 / np.where(has, k, 1)))[has]
        sigma2 = float(gap2.mean()) if len(gap2) >= 2 else np.nan
        row[f"{col}_chaos_sd"] = np.sqrt(sigma2)
        pairs[f"{col}_chaos_var"] = sigma2 * (1 + 1 / m)
        pairs[f"{err}_ref"] = np.where(has, np.sqrt(pairs[f"{err}_ref"]**2 + pairs[f"{err}_sq_rep"].fillna(0)) / m,
                                       pairs[f"{err}_ref"])
    for col in cols:
        pairs[f"{col}_ref"] = np.where(has, (pairs[f"{col}_ref"] + k * pairs[f"{col}_rep"]) / m, pairs[f"{col}_ref"])
    return pairs, row


def _paired_variance(pairs, col, err):
    """Per bed, the variance of the variant's difference from the reference: the runs' errors,
    or the chaos the reference's replicas measured, whichever is larger."""
    within = pairs[err]**2 + pairs[f"{err}_ref"]**2
    chaos = pairs.get(f"{col}_chaos_var")
    return within if chaos is None or chaos.isna().all() else np.maximum(within, chaos.fillna(0))


def _beds(col, d):
    """The per-bed differences' own error of their mean, sd / sqrt(beds), and the mean over it
    (NaN below three beds: one degree of freedom says nothing)."""
    if len(d) < 3:
        return {f"{col}_beds_err": np.nan, f"{col}_beds_z": np.nan}
    err = d.std(ddof=1) / np.sqrt(len(d))
    return {f"{col}_beds_err": err, f"{col}_beds_z": z_score(d.mean(), err)}


def _verdict(row, diff, diff_err):
    z = z_score(diff, diff_err)
    return row | {"rel_diff": diff / row["drag_ref"], "rel_diff_err": diff_err / abs(row["drag_ref"]),
                  "z": z, "agrees": bool(abs(z) < Z_AGREE)}


def conclusion(cmp, study):
    """The sentence: per variant value, how many points agree, the largest |z| and the mean
    relative difference; then the study's answer."""
    if isinstance(study, str):
        study = STUDIES[study]
    parts = []
    for v, g in _variants(cmp, study):
        ref = g.reference.iloc[0]
        parts.append(f"{study.variant} = {v} against {ref:g}: agrees at {int(g.agrees.sum())} of {len(g)} "
                     f"points (largest |z| {np.abs(g.z).max():.2g}; relative difference "
                     f"{100 * g.rel_diff.mean():+.1f} % on average, "
                     f"{100 * g.rel_diff.min():+.1f} % to {100 * g.rel_diff.max():+.1f} %)")
    answer = _answer(cmp, study)
    return "; ".join(parts) + f". {answer}" + resolved_shifts(cmp, study)


def _farthest(c, reverse=False):
    """The variant farthest from the reference up to which every variant agrees at every point
    (contiguous from the reference: ascending, or descending with reverse), None if the nearest fails."""
    best = None
    for v in sorted(c.variant.unique(), reverse=reverse):
        if not c[c.variant == v].agrees.all():
            break
        best = v
    return best


def _answer(cmp, study):
    if study.name == "time_step":
        def say(c, who):
            best = _farthest(c, reverse=True)
            return f"{who}: " + ("no coarser step agrees, keep 64" if best is None
                                 else f"{best:g} steps per collision time ({64 / best:.3g}x fewer steps)")
        parts = [say(cmp, "Every point")] + [say(g, f"K_n = {kn:g}") for kn, g in cmp.groupby("kn")]
        return "Fewest steps per collision time that agree with 64: " + "; ".join(parts) + "."
    if study.name == "yield_speed":
        fastest = _farthest

        def say(best, ref, who):
            if best is None:
                return f"{who}: no faster speed agrees with V = {ref:g}, keep it"
            return f"{who}: V = {best:g} instead of {ref:g} ({best / ref:.3g}x fewer steps)"

        ref = cmp.reference.iloc[0]
        parts = [say(fastest(cmp), ref, "Yield pulls at every point")]
        if "mu" in cmp.columns and cmp.mu.nunique() > 1:
            parts += [say(fastest(g), ref, f"at mu = {mu:g}") for mu, g in cmp.groupby("mu")]
        return "; ".join(parts) + "."
    if study.name == "box_size":
        out = []
        for D, g in cmp.groupby("D"):
            smallest = _farthest(g, reverse=True)   # contiguous from the largest box
            out.append(f"D = {D:g}: lx = {g.reference.iloc[0] if smallest is None else smallest:g}")
        return "Smallest box that agrees: " + ", ".join(out) + "."
    if study.name == "active_region":
        out = []
        cols, shown = settings_set(cmp, study), shown_settings(cmp, study)
        for key, g in _grouped(cmp, ["D", *cols]):
            smallest = _farthest(g, reverse=True)   # agreeing radii: contiguous from the widest
            # Radii below a miss are named on their own: a chance miss of a wide radius (a shift
            # that does not shrink with R) must not hide that narrower ones agreed.
            alone = [v for v in sorted(g.variant.unique())
                     if (smallest is None or v < smallest) and g[g.variant == v].agrees.all()]
            out.append(f"D = {key[0]:g}" + _setting_label(cols, key[1:], shown) + ": "
                       + ("none agrees" if smallest is None else f"{smallest:g} d ({smallest / key[0]:.3g} D)")
                       + (" (below a wider radius that does not: " + ", ".join(f"{v:g} d" for v in alone) + ")"
                          if alone else ""))
        judged = ", ".join(c for c, _ in study.judged)
        text = (f"Smallest active radius at which {judged} agree with every grain integrated at every "
                f"point: " + ", ".join(out) + ".")
        folded = cmp["replicas"].fillna(0).gt(0) if "replicas" in cmp.columns else pd.Series(False, cmp.index)
        if folded.any():
            chaos = [f"{c} {cmp[f'{c}_chaos_sd'].min():.3g} to {cmp[f'{c}_chaos_sd'].max():.3g}"
                     for c, _ in study.judged
                     if f"{c}_chaos_sd" in cmp.columns and cmp[f"{c}_chaos_sd"].notna().any()]
            text += (" The reference is the mean of each bed's pull and its replicas; pulls through one bed "
                     "differ by chaos alone by (per run, over the points) " + ", ".join(chaos) +
                     ", and a paired error is never taken below that.")
        unparted = sorted({n for u in cmp.get("replicas_unparted", pd.Series(dtype=object)).fillna("")
                           for n in str(u).split(", ") if n})
        if unparted:
            text += (f" Replicas nudged by {', '.join(unparted)} stayed with their pull (gaps below {PARTED:g} of the "
                     "runs' own errors: the nudge did not grow over the pull) and are left out, as they measure "
                     "no chaos" + ("" if folded.all()
                                   else "; where no other replica parted, the chaos between pulls is not measured")
                     + ".")
        if "asleep" in cmp.columns:      # what each radius saves: the grains it holds asleep
            saved = ", ".join(f"{v}: {100 * g.asleep.mean():.0f} %" for v, g in _variants(cmp, study, " d"))
            text += f" Mean fraction of the grains asleep over a pull: {saved}."
        return text
    if study.name in ("settle_damping", "placement"):
        return (settle_damping_answer if study.name == "settle_damping" else placement_answer)(cmp)
    # stiffness: the drag's change per decade of K_n, at each speed (regimes differ)
    cmp = cmp.assign(_per_decade=cmp.rel_diff / np.log10(cmp.variant / cmp.reference))
    by = "Fr" if "Fr" in cmp.columns and cmp.Fr.nunique() > 1 else None
    groups = cmp.groupby(by) if by else [(None, cmp)]
    parts = []
    for key, g in groups:
        where = f"at Fr = {key:g}: " if by else ""
        parts.append(f"{where}{100 * g._per_decade.mean():+.1f} % per decade"
                     f"{'' if g.agrees.all() else ' (disagrees)'}")
    return ("Change of the drag per decade of K_n toward the reference (positive: the drag grows "
            "with K_n, so a softer study underestimates it): " + "; ".join(parts) + ".")


def draw(cmp, study, outdir):
    """validate_<name>.png/.pdf: F/F_ref against the variant, one series per point."""
    import matplotlib.pyplot as plt

    if isinstance(study, str):
        study = STUDIES[study]
    plt.switch_backend("Agg")
    fig, ax = plt.subplots(figsize=(5.5, 3.8), layout="constrained")
    keys = [k for k in study.keys if k in cmp.columns and cmp[k].nunique() > 1]
    keys += [c for c in settings_set(cmp, study) if cmp[c].nunique() > 1]   # one series per setting
    groups = _grouped(cmp, keys) if keys else [((), cmp)]
    for i, (key, g) in enumerate(groups):
        label = ", ".join(f"{k.replace('_requested', '')} = {label_value(v)}" for k, v in zip(keys, key))
        x = np.concatenate([[g.reference.iloc[0]], g.variant])
        y = np.concatenate([[1.0], 1.0 + g.rel_diff])
        err = np.concatenate([[0.0], g.rel_diff_err])
        order = np.argsort(x)
        x, y, err = x[order], y[order], err[order]
        ax.errorbar(x, y, yerr=err, fmt="os^vD<>p"[i % 8] + "-", ms=4, mfc="none", capsize=2, lw=0.8,
                    label=label or None)
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    if study.variant in ("V", "kn"):
        ax.set_xscale("log")
    ax.set_xlabel(study.label)
    ax.set_ylabel(r"$F / F_{\rm ref}$ (reference protocol: 1)")
    if keys:
        ax.legend(fontsize=7)
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    paths = [outdir / f"validate_{study.name}.png", outdir / f"validate_{study.name}.pdf"]
    for p in paths:
        fig.savefig(p, dpi=150)
    plt.close(fig)
    return paths


def validate(runs, study, outdir):
    """Compare, draw, and write the comparison table and the sentence; returns the paths."""
    if isinstance(study, str):
        if study not in NAMES:
            raise ValidationError(f"unknown validation study '{study}': one of {', '.join(NAMES)}")
        if study == "pull_length":
            return pull_length.validate(runs, outdir)
        study = STUDIES[study]
    cmp = compare(runs, study)
    outdir = Path(outdir)
    paths = draw(cmp, study, outdir)
    write_csv(cmp, outdir / f"validate_{study.name}.csv")
    md = outdir / f"validate_{study.name}.md"
    write_text_atomic(md, f"### Validation: {study.name.replace('_', ' ')}\n\n"
                          f"![{study.question}](validate_{study.name}.png)\n\n{conclusion(cmp, study)}\n"
                          f"{point_table(cmp, study)}")
    return paths + [outdir / f"validate_{study.name}.csv", md]
