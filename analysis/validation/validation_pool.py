"""Pooling one validation's comparisons over its studies: is there a shift too small for any one
study to see?

Each study (analysis.validation.validation) judges its points one by one, |z| < Z_AGREE, and a study of a
few beds per point cannot resolve a shift of a percent or two. The active region, for one, was
validated in several studies (sizes, frictions, speeds, travels) at the same radius in units of
D; every one of them agreed, and most of their drags came out a little higher. Pooling asks
whether that lean is real: per group of rows that share the variant in the study's units (the
active radius over D) and the settings (wake_force), the inverse-variance mean of the relative
differences,

    m = sum(r_i / e_i^2) / sum(1 / e_i^2),   e_m = sum(1 / e_i^2)^(-1/2),   z = m / e_m,

how many rows lie above zero, and chi^2 / dof of the rows about m (near 1: one common shift
explains them; well above: the shift depends on the point). Rows of one group come from
different points or studies; two points of one study may share beds (Fr = 5 and 10 pulled
through the same five), but each row is a paired difference, which the bed's own randomness
cancels from, so they are taken as independent. Rows that share a reference but differ in a
setting (two wake tests against one set of reference pulls) are correlated, hence never pooled
together.

    python -m analysis pool active_region results/validate/*/validate_active_region.csv --output-dir DIR

writes DIR/pool_<study>.csv (one row per group) and .md (the sentence). With --wake-relative the
wake test is taken relative to granudrag's default at each row's K_n (wake_force_over_default;
1: the default, which grows with K_n), so that rows at the default pool together across
stiffnesses.
"""

from pathlib import Path

import numpy as np
import pandas as pd

from ..core.physics import default_wake_force
from ..core.table import write_csv, write_text_atomic
from .agreement import Z_AGREE, ValidationError
from .validation import SETTINGS_BEFORE_RECORDED, STUDIES, settings_set, shown_settings

# What a study's variant is measured against, to put its studies on one scale: the active radius
# in units of D (R = 3 D is one radius whatever D is).
SCALE = {"active_region": ("D", "R_over_D")}


# The wake test relative to the default at the row's K_n (--wake-relative), a setting in its place.
WAKE_RELATIVE = "wake_force_over_default"


# How the sentence writes each observable's difference: (factor, unit).
UNITS = {"drag": (100, " %"), "theta": (1, " rad")}


def load(paths):
    """The comparison tables (validate_<study>.csv), one `study` column naming each file's
    directory (the study)."""
    frames = []
    for p in map(Path, paths):
        if not p.is_file():
            raise ValidationError(f"{p}: no such comparison table (written by `python -m analysis validate`)")
        frames.append(pd.read_csv(p).assign(study=p.parent.name))
    if not frames:
        raise ValidationError("no comparison table given")
    return pd.concat(frames, ignore_index=True)


def pool(cmp, study, wake_relative=False):
    """One row per group (variant in the study's units, settings): rows, studies, the pooled
    relative difference and its error, z, whether it agrees, rows above zero and chi^2/dof. With
    wake_relative, wake_force is grouped as its ratio to the default at each row's K_n."""
    if isinstance(study, str):
        study = STUDIES[study]
    need = {"variant", "rel_diff", "rel_diff_err"}   # the drag's; the others pool where present
    if missing := need - set(cmp.columns):
        raise ValidationError(f"pool: the comparison table lacks {', '.join(sorted(missing))}")
    cmp = cmp[cmp.rel_diff_err > 0].copy()
    if not len(cmp):
        raise ValidationError("pool: no row has a relative difference with an error")
    by, col = SCALE.get(study.name, (None, "variant"))
    if by:
        cmp[col] = (cmp.variant / cmp[by]).round(6)
    for c, default in SETTINGS_BEFORE_RECORDED.items():   # a table from before the setting was recorded
        if c in study.settings:
            cmp[c] = cmp[c].fillna(default) if c in cmp.columns else default
    settings = settings_set(cmp, study)
    if wake_relative and "wake_force" in settings:
        if "kn" not in cmp.columns:
            raise ValidationError("pool --wake-relative: the comparison table lacks kn, which the default "
                                  "wake test depends on")
        cmp[WAKE_RELATIVE] = (cmp.wake_force / cmp.kn.map(default_wake_force)).round(6)
        settings = [WAKE_RELATIVE if c == "wake_force" else c for c in settings]
    rows = []
    for key, g in cmp.groupby([col, *settings], sort=True):
        key = key if isinstance(key, tuple) else (key,)
        row = dict(zip([col, *settings], key)) | {
            "rows": len(g), "studies": g["study"].nunique() if "study" in g else 1}
        for name, (diff, err) in _observables(g, study).items():
            row |= _pooled(g[diff], g[err], name)
        row["agrees"] = bool(all(abs(row[f"{name}_z"]) < Z_AGREE for name in _observables(g, study)))
        rows.append(row)
    return pd.DataFrame(rows)


def _observables(cmp, study):
    """{name: (difference column, its error column)}: the drag's relative difference and the
    absolute difference of every other judged observable the table has."""
    out = {"drag": ("rel_diff", "rel_diff_err")}
    for col, _ in study.also_judged:
        if f"{col}_diff" in cmp.columns and cmp[f"{col}_diff_err"].notna().any():
            out[col] = (f"{col}_diff", f"{col}_diff_err")
    return out


def _pooled(d, e, name):
    """The inverse-variance mean of differences d with errors e, its error, z, the rows above zero,
    chi^2/dof about it, and the mean's error from the rows' own scatter with its Student t
    (rows - 1 dof): the runs' paired errors are upper bounds (analysis.validation.validation), and when the
    rows scatter less than they say (chi^2/dof < 1) a common shift shows in t before z."""
    ok = e.notna() & (e > 0) & d.notna()
    d, w = d[ok], 1.0 / e[ok] ** 2
    if not len(d):
        return {f"{name}_diff": np.nan, f"{name}_err": np.nan, f"{name}_z": np.nan}
    m, err = float((w * d).sum() / w.sum()), float(w.sum() ** -0.5)
    dof = len(d) - 1
    chi2_dof = float((w * (d - m) ** 2).sum()) / dof if dof else np.nan
    scatter = err * np.sqrt(chi2_dof) if dof >= 2 else np.nan
    return {f"{name}_diff": m, f"{name}_err": err, f"{name}_z": m / err, f"{name}_above": int((d > 0).sum()),
            f"{name}_chi2_dof": chi2_dof, f"{name}_scatter_err": scatter,
            f"{name}_t": m / scatter if scatter > 0 else np.nan}


def conclusion(pooled, study):
    """The sentence: per group, each observable's pooled shift with its error and z, the rows
    above zero, and the error and t from the rows' scatter; then the groups whose shift the scatter
    resolves (|t| beyond the two-sided 95 % Student quantile)."""
    from scipy.stats import t as student

    if isinstance(study, str):
        study = STUDIES[study]
    col = SCALE.get(study.name, (None, "variant"))[1]
    unit = " D" if col == "R_over_D" else ""
    names = ["drag"] + [c for c, _ in study.also_judged if f"{c}_diff" in pooled.columns]
    parts, resolved = [], []
    # A setting is named where it varies over the groups or leaves its default somewhere.
    shown = [c for c in study.settings if c in shown_settings(pooled, study)]
    if WAKE_RELATIVE in pooled.columns:
        shown = [WAKE_RELATIVE, *shown]
    for _, r in pooled.iterrows():
        label = f"{r[col]:g}{unit}" + "".join(f", {c} {r[c]:g}" for c in shown)
        obs = []
        for name in names:
            if np.isnan(r[f"{name}_diff"]):
                continue
            scale, u = UNITS.get(name, (1, ""))
            text = (f"{name} {scale * r[f'{name}_diff']:+.2g} ± {scale * r[f'{name}_err']:.2g}{u} "
                    f"(z {r[f'{name}_z']:.2f}, {int(r[f'{name}_above'])} of {r.rows} above")
            if not np.isnan(r[f"{name}_t"]):
                text += f"; rows' scatter ± {scale * r[f'{name}_scatter_err']:.2g}{u}, t {r[f'{name}_t']:.2f}"
                if abs(r[f"{name}_t"]) > student.ppf(0.975, r.rows - 1):
                    resolved.append(f"{name} at {label}")
            obs.append(text + ")")
        studies = f"{r.studies} stud{'y' if r.studies == 1 else 'ies'}"
        parts.append(f"{label} ({r.rows} rows, {studies}): " + ", ".join(obs))
    text = (f"Pooled over its studies, each {study.name.replace('_', ' ')} variant against the reference "
            f"protocol (drag relative, the others absolute): " + "; ".join(parts) + ".")
    if resolved:
        text += (" A common shift that the runs' errors call agreement but the rows' own scatter resolves "
                 "(|t| beyond the 95 % Student quantile): " + ", ".join(resolved) + ".")
    return text


def write(paths, study, outdir, wake_relative=False):
    """Load, pool and write pool_<study>.csv and .md; returns their paths."""
    if study not in STUDIES:
        raise ValidationError(f"unknown validation study '{study}': one of {', '.join(STUDIES)}")
    pooled = pool(load(paths), study, wake_relative)
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    csv, md = outdir / f"pool_{study}.csv", outdir / f"pool_{study}.md"
    write_csv(pooled, csv)
    write_text_atomic(md, f"### Validation pooled: {study.replace('_', ' ')}\n\n{conclusion(pooled, study)}\n")
    return [csv, md]
