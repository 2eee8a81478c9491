"""The tidy pull table: schema, validation and CSV loading (the Froude number: analysis.core.physics).

One row per pull. All quantities are dimensionless in grain density rho,
mean grain diameter d and gravity g.
"""
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from . import path_scheme
from .bed_shift import bed_shift
from .physics import CONTACT_RANGES, froude, in_contact_range
from .point_errors import (  # noqa: F401  (re-exported: the point table's errors for fits)
    observable_errors,
    pooled_bed_r2,
    pooled_drag_err,
    shared_bed_variance,
)

# name -> (kind, meaning). "text" columns identify; "number" columns are data.
COLUMNS = {
    "system": ("text", "geometry family of the paper: 'I' (vary D) or 'II' (vary h)"),
    "D": ("number", "intruder diameter [d]"),
    "h": ("number", "depth of the intruder centre below the bed's free surface [d]"),
    "mu": ("number", "grain friction coefficient"),
    "kn": ("number", "normal stiffness K_n [rho d g]"),
    "gamman": ("number", "normal damping gamma_n [sqrt(g/d^3)]"),
    "V": ("number", "pulling speed [sqrt(g d)]"),
    "Fr": ("number", "Froude number, paper Eq. 4"),
    "drag": ("number", "time-averaged drag <F_x> [rho d^3 g]"),
    "drag_err": ("number", "standard error of the drag, from its force series: a flat-top lag window through the "
                 "autocorrelation's first negative lobe (analysis.runs.series_error; the engine's: drag_err_engine)"),
    "n_contacts": ("number", "mean intruder coordination number n"),
    "theta": ("number", "mean contact angle at contact formation, Eq. 6 [rad]"),
    "Z": ("number", "mean bulk coordination number near the intruder"),
    "kappa": ("number", "normalised coordination number, Eq. 8"),
    "run": ("text", "identifier of the pull (its run directory)"),
}
TEXT_COLUMNS = [c for c, (kind, _) in COLUMNS.items() if kind == "text"]
NUMBER_COLUMNS = [c for c, (kind, _) in COLUMNS.items() if kind == "number"]

# Every pull has these; the observables after them may be NaN (a yield pull
# that made too few contacts has no meaningful theta, for instance).
REQUIRED_FINITE = ["D", "h", "mu", "kn", "gamman", "V", "Fr", "drag"]

# The paper's zero-speed limit: the yield force is the drag at this speed.
YIELD_SPEED = 0.01


class TableError(ValueError):
    """A file or frame that is not a usable pull table."""


def validate_table(df):
    """Raise ValueError naming every missing, ill-typed or invalid column.

    Extra columns are allowed. Returns df unchanged so calls can chain.
    """
    if not isinstance(df, pd.DataFrame):
        raise ValueError(f"expected a pandas DataFrame, got {type(df).__name__}")
    missing = [c for c in COLUMNS if c not in df.columns]
    if missing:
        found = ", ".join(map(str, df.columns[:8])) + (", ..." if df.shape[1] > 8 else "")
        raise ValueError(f"missing columns: {', '.join(missing)} (found: {found or 'none'})")
    problems = []
    for c in NUMBER_COLUMNS:
        kind = df[c].dtype.kind
        if kind not in "iuf":
            problems.append(f"{c} must be numeric (has dtype {df[c].dtype})")
    for c in TEXT_COLUMNS:
        if not (pd.api.types.is_object_dtype(df[c]) or pd.api.types.is_string_dtype(df[c])):
            problems.append(f"{c} must be text (has dtype {df[c].dtype})")
    if problems:
        raise ValueError("ill-typed columns: " + "; ".join(problems))
    for c in REQUIRED_FINITE:
        bad = ~np.isfinite(df[c].to_numpy(dtype=float))
        if bad.any():
            problems.append(f"{c} is missing or not finite in {bad.sum()} row(s)")
    if problems:
        raise ValueError("invalid values: " + "; ".join(problems))
    for c, ok in [("D", df.D > 0), ("h", df.h > 0), *[(k, in_contact_range(k, df[k])) for k in CONTACT_RANGES],
                  ("V", df.V >= 0)]:
        if not ok.all():
            problems.append(f"{c} out of range in {(~ok).sum()} row(s)")
    # Fr is stored for convenience but must be Eq. 4 of the stored V and D,
    # otherwise a table mixing conventions (e.g. Eq. 5) would fit silently.
    off = ~np.isclose(df.Fr, froude(df.V, df.D), rtol=1e-4, atol=1e-9)
    if off.any():
        problems.append(f"Fr differs from froude(V, D) (paper Eq. 4) in {off.sum()} row(s)")
    if problems:
        raise ValueError("invalid values: " + "; ".join(problems))
    return df


# pandas < 3 parses floats with its own fast routine, an ulp off for about one value in ten: Debian's
# 1.5 read a rung's Fr 0.25000000000000006 as 0.25, and the fits moved (issue 76). round_trip is
# Python's correctly rounded parser; pandas 3 parses so by default and deprecates the option.
EXACT_FLOATS = {} if int(pd.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}


def load_csv(path):
    """Read a pull table from CSV; raise TableError saying what is wrong."""
    path = Path(path)
    if not path.is_file():
        raise TableError(f"{path}: no such file")
    with open(path, "rb") as fh:
        head = fh.read(4096)
    if head.startswith(b"\x89HDF"):
        raise TableError(f"{path}: is an HDF5 file, not a CSV pull table "
                         "(run files are collected into a table by the run loader)")
    if b"\x00" in head:
        raise TableError(f"{path}: is a binary file, not a CSV pull table")
    try:
        df = pd.read_csv(path, dtype={c: str for c in TEXT_COLUMNS}, **EXACT_FLOATS)
    except (UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise TableError(f"{path}: not a readable CSV file ({exc})") from None
    try:
        return validate_table(df)
    except ValueError as exc:
        raise TableError(f"{path}: not a granudrag pull table: {exc}") from None


def write_csv(df, path, float_format="%.10g"):
    """Write df as CSV atomically: a temporary file beside path, then a rename, so that an
    interrupted write never leaves a truncated file under the final name."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    df.to_csv(tmp, index=False, float_format=float_format)
    tmp.replace(path)


def write_text_atomic(path, text):
    """Write text to path as write_csv writes a table: a temporary file beside it, then a rename."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    tmp.replace(path)


def save_csv(df, path):
    """Write a validated table so that load_csv reads it back unchanged."""
    validate_table(df)
    extra = [c for c in df.columns if c not in COLUMNS]
    write_csv(df[list(COLUMNS) + extra], path, float_format="%.17g")


# --- Run files (HDF5) ---------------------------------------------------
# The engine's per-pull HDF5 files are read into this table by
# `analysis.runs.runs.load_runs(paths)`.


def is_yield(df, speed=None):
    """Which rows are yield pulls (their drag is the yield force F_Y, the zero-speed limit):
    those pulled at `speed` if one is given; else the table's `yield_pull` column when it has
    one (the workflow sets it from the config's report.yield_speed: a study may pull its yield
    pulls faster than the paper's 0.01 once validated); else those at YIELD_SPEED."""
    if speed is None and "yield_pull" in df.columns:
        return df["yield_pull"].astype(bool).to_numpy()
    return np.isclose(df.V, YIELD_SPEED if speed is None else speed, rtol=1e-6, atol=1e-12)


def yield_speeds(speed, mu):
    """The yield pulls' speed at each friction `mu` (array): `speed` is one number, or a list of
    {mu, V} steps (report.yield_speed), each entry's V applying from its mu up to the next
    entry's: friction lets the yield force reach its zero-speed limit at a faster pull
    (config/validate/yield_speed.yaml: V = 0.1 agrees with 0.01 at mu = 0.5, not at 0)."""
    mu = np.asarray(mu, dtype=float)
    if np.isscalar(speed):
        return np.full(mu.shape, float(speed))
    steps = sorted((float(s["mu"]), float(s["V"])) for s in speed)
    if not steps or steps[0][0] > 0:
        raise ValueError(f"report.yield_speed {speed!r}: the first step must start at mu = 0 "
                         "(every friction needs a yield speed)")
    out = np.full(mu.shape, steps[0][1])
    for start, v in steps[1:]:
        out[mu >= start - 1e-12] = v
    return out


def mark_yield(df, speed):
    """The table with its `yield_pull` column set: pulled at `speed` (yield_speeds: a number,
    or per friction)."""
    v = yield_speeds(speed, df.mu) if len(df) else np.zeros(0)
    return df.assign(yield_pull=np.isclose(df.V, v, rtol=1e-6, atol=1e-12))


def yield_rows(df, speed=None):
    """Rows pulled at the zero-speed limit (is_yield)."""
    return df[is_yield(df, speed)]


def reference_params(df):
    """The (kn, gamman) pair with the most pulls: the study's default contact law."""
    counts = df.groupby(["kn", "gamman"]).size()
    if counts.empty:
        raise ValueError("empty table has no reference contact parameters")
    return tuple(float(v) for v in counts.idxmax())


def select(df, *, atol=1e-9, **equal):
    """Rows whose columns equal the given values (floats compared with atol)."""
    keep = np.ones(len(df), dtype=bool)
    for col, value in equal.items():
        if isinstance(value, str):
            keep &= (df[col] == value).to_numpy()
        else:
            keep &= np.isclose(df[col].to_numpy(dtype=float), value, rtol=1e-9, atol=atol)
    return df[keep]


# --- Replicate beds ------------------------------------------------------
# A sweep with `seed: [1, 2, 3]` pours one bed per seed; every speed of the sweep is pulled
# through each. The run table (one row per pull) then has several rows per point, told apart
# by `seed`; `combine_beds` makes the point table (one row per point) the fits read, and
# `bed_bootstrap` its resamples that keep the beds' correlations. A point poured once cannot
# measure the scatter between beds: it takes the study's own, pooled over its replicated points,
# or, in a study without any, a prior the config declares (table.bed_scatter: measured by a
# named study, with its degrees of freedom); each point says which (column bed_scatter_source).

# A point's kind for pooling and for priors: a yield force's beds scatter about five times as much
# as a drag's at speed (the default study, results/reproduction/config: 18.8 % against 3.7 %
# between beds), so pooling them together gives neither its own.
BED_SCATTER_KINDS = ("drag", "yield")

BED_SCATTER_SOURCES = {   # the point table's bed_scatter_source -> the report's words
    "replicates": "replicate beds",
    "pooled": "pooled from this study's replicated points",
    "prior": "prior",
    "none": "none (single beds, no prior)",
}


@dataclass(frozen=True)
class BedScatterPrior:
    """The relative between-bed scatter sigma_B/drag of a study poured once per point, measured
    by another study (`source`, e.g. a ladder rung's directory) on `dof` degrees of freedom
    (between_bed_scatter's sum(k - 1)): the config's table.bed_scatter."""
    relative: float
    dof: int
    source: str

    def __post_init__(self):
        if not (np.isfinite(self.relative) and self.relative >= 0 and self.dof >= 1 and self.source):
            raise ValueError(f"table.bed_scatter {self!r}: needs relative >= 0, dof >= 1 and a source")

    @classmethod
    def of(cls, value):
        """A prior from the config's table.bed_scatter mapping ({relative, dof, source}), an
        instance, or None (no prior)."""
        if value is None or isinstance(value, cls):
            return value
        return cls(float(value["relative"]), int(value["dof"]), str(value["source"]))


def bed_scatter_priors(value):
    """{kind: BedScatterPrior or None} (BED_SCATTER_KINDS) from the config's table.bed_scatter:
    {drag: {relative, dof, source}, yield: {...}} gives each kind its own (a kind left out has
    none); a flat {relative, dof, source} (or an instance) applies to both; None to neither."""
    if isinstance(value, dict) and set(value) & set(BED_SCATTER_KINDS):
        unknown = sorted(set(value) - set(BED_SCATTER_KINDS))
        if unknown:
            raise ValueError(f"table.bed_scatter: unknown kind(s) {unknown}; a prior per kind is "
                             f"keyed {' and '.join(BED_SCATTER_KINDS)}")
        return {k: BedScatterPrior.of(value.get(k)) for k in BED_SCATTER_KINDS}
    prior = BedScatterPrior.of(value)
    return {k: prior for k in BED_SCATTER_KINDS}


def scatter_kind(runs):
    """Each row's kind for its bed scatter: "yield" for a yield pull (is_yield), else "drag"."""
    if not len(runs):
        return np.array([], dtype=object)
    return np.where(is_yield(runs), "yield", "drag")


def _point_and_series(run):
    """(point, series) identifiers of a run directory: the directory without its `seed~`
    component, and its parent (the bed) likewise. Runs outside the workflow's layout (no
    `seed~` component) are each their own point and their own series."""
    parts = Path(str(run)).parts
    kept = [p for p in parts if path_scheme.name_of(p) != path_scheme.SEED.field]
    if len(kept) == len(parts):
        return str(run), str(run)
    return "/".join(kept), "/".join(kept[:-1])


def _with_ids(runs):
    ids = [_point_and_series(r) for r in runs["run"]]
    return runs.assign(_point=[i[0] for i in ids], _series=[i[1] for i in ids])


def _by_point(runs):
    """(runs with ids, codes, k, first): each row's point index, beds per point, and the
    first row of each point, in first-seen order."""
    runs = _with_ids(runs).reset_index(drop=True)
    codes, _ = pd.factorize(runs["_point"])
    k = np.bincount(codes)
    first = np.unique(codes, return_index=True)[1]
    return runs, codes, k, first


def _moments(codes, k, y, e):
    """Per point: mean of y, var of y (ddof 1, NaN for one bed), W = mean(e^2)."""
    m = np.bincount(codes, y) / k
    with np.errstate(invalid="ignore", divide="ignore"):
        s2 = np.bincount(codes, (y - m[codes]) ** 2) / (k - 1)
    return m, np.where(k >= 2, s2, np.nan), np.bincount(codes, e ** 2) / k


def bed_mean(values, errors):
    """One point's value over its beds and its error, by combine_beds's rule: the mean, and
    sqrt(max(s^2, W) / k) with s^2 the beds' variance (none for one bed) and W their mean squared
    error."""
    y, e = np.asarray(values, float), np.asarray(errors, float)
    k = np.array([len(y)])
    m, s2, W = _moments(np.zeros(len(y), int), k, y, e)
    return float(m[0]), float(np.sqrt(max(np.nan_to_num(s2[0]), W[0]) / k[0]))


def between_bed_scatter(runs):
    """(r2, dof): the pooled relative between-bed variance sigma_B^2/drag^2 over the points
    with two or more beds, and its degrees of freedom sum(k - 1); (NaN, 0) if none has."""
    runs, codes, k, _ = _by_point(runs)
    m, s2, W = _moments(codes, k, runs.drag.to_numpy(float), runs.drag_err.to_numpy(float))
    rep = k >= 2
    dof = int(np.sum(k[rep] - 1))
    if not dof:
        return np.nan, 0
    sb2 = np.maximum(0.0, s2[rep] - W[rep])
    return float(np.sum((k[rep] - 1) * sb2 / m[rep] ** 2) / dof), dof


def single_bed_scatter(runs, prior=None):
    """(r2, dof, source): the relative between-bed variance a point poured once takes, by the
    rule: the study's own replicates first (between_bed_scatter pooled over its points with two
    or more beds: "pooled"), else the config's prior (a BedScatterPrior or its mapping: "prior"),
    else none (NaN, 0, "none": such a point's error is its run's alone)."""
    r2, dof = between_bed_scatter(runs)
    if dof:
        return r2, dof, "pooled"
    prior = BedScatterPrior.of(prior)
    if prior is not None:
        return prior.relative ** 2, prior.dof, "prior"
    return np.nan, 0, "none"


def combine_beds(runs, r2=None, prior=None):
    """The point table: one row per point of a run table, combining its replicate beds; yield
    pulls and pulls at speed apart (scatter_kind: each pools its own scatter and takes its own
    prior, bed_scatter_priors; r2 may be a {kind: r2} too), rows in the runs' order of points.
    """
    priors = bed_scatter_priors(prior)
    kind = scatter_kind(runs)
    runs = runs.assign(_pos=np.arange(len(runs)))
    parts = [_combine_kind(runs[kind == k], r2.get(k) if isinstance(r2, dict) else r2, priors[k])
             for k in BED_SCATTER_KINDS if (kind == k).any()]
    if not parts:
        return _combine_kind(runs, None, None).drop(columns="_pos")
    out = pd.concat(parts, ignore_index=True).sort_values("_pos", kind="stable")
    return out.drop(columns="_pos").reset_index(drop=True)


def _combine_kind(runs, r2=None, prior=None):
    """combine_beds on runs of one kind.

    For a point with beds b = 1..k, drags y_b and within-run standard errors e_b:
        drag = mean(y_b),  W = mean(e_b^2)  (within-run variance of one bed's drag),
        s^2 = var(y_b) (k >= 2, ddof 1), sigma_B^2 = max(0, s^2 - W)  (between-bed variance),
        drag_err^2 = (sigma_B^2 + W)/k = max(s^2, W)/k,
    with drag_err_within = sqrt(W/k), drag_err_between = sqrt(sigma_B^2/k) and drag_var_excess =
    (s^2 - W)/k (k >= 2; not held at 0: pooled over points, unbiased where max(0, ...) is not,
    shared_bed_variance). A point with one
    bed cannot measure sigma_B; it takes sigma_B^2 = r2 drag^2, r2 by `single_bed_scatter`: the
    pooled relative scatter of the study's replicated points, else the `prior` (the config's
    table.bed_scatter), else none; or the r2 given (counted as pooled). drag_dof: k - 1
    when the bed scatter dominates (s^2 > W), else the within-run dof combined (Satterthwaite,
    with the pooled or prior r2's dof for one bed);
    n_beds: k; plateau: every bed's error converged (plateau_engine: the engine's); seeds: the beds' seeds, ';'-joined;
    drag_shift_r2 (drag_cumulative_box_shift_r2): the variance of a bed's shift its series shares (bed_shift);
    drag_cumulative (the cumulative average from t = 0; _box: over one box length) with its error as the
    drag's, drag_err_engine the engine's errors by the same rule; drag_bed_sd: the beds' standard deviation of the drag
    (NaN for one bed), drag_bed_sd_ratio (_engine): over the beds' mean drag_err (drag_err_engine);
    theta_err_within, _between, _var_excess, theta_present's and kappa's likewise split their errors;
    bed_scatter_source: where the point's bed scatter came from (BED_SCATTER_SOURCES: replicates,
    pooled, prior, none), bed_scatter_r and bed_scatter_dof: sqrt(r2) and its dof for a point
    poured once (NaN otherwise), bed_scatter_study: the prior's source (empty otherwise).
    Other observables are means over the beds (theta_err, theta_present_err, kappa_err as drag_err,
    without the pooled term). Rows without a seed (runs outside the workflow's layout) pass unchanged.
    """
    if r2 is None:
        r2, r2_dof, single = single_bed_scatter(runs, prior)
    else:
        r2_dof, single = np.inf, "pooled"
    runs, codes, k, first = _by_point(runs)
    y, e = runs.drag.to_numpy(float), runs.drag_err.to_numpy(float)
    nu = runs.drag_dof.to_numpy(float) if "drag_dof" in runs else np.full(len(runs), np.nan)
    m, s2, W = _moments(codes, k, y, e)
    with np.errstate(invalid="ignore", divide="ignore"):
        within_dof = k * k * W ** 2 / np.bincount(codes, e ** 4 / nu)
        within_dof = np.where(np.isfinite(within_dof) & (W > 0), within_dof, np.nan)
        y1 = m  # one bed: its drag
        pooled = r2 * y1 ** 2 if np.isfinite(r2) else np.full(len(k), np.nan)
        single_dof = (W + pooled) ** 2 / (W ** 2 / within_dof + pooled ** 2 / r2_dof)
    rep = k >= 2
    sb2 = np.where(rep, np.maximum(0.0, s2 - W), pooled)
    dof = np.where(rep, np.where(s2 > W, k - 1.0, within_dof),
                   np.where(np.isfinite(pooled), single_dof, within_dof))
    out = runs.iloc[first].reset_index(drop=True).copy()
    out["drag"] = m
    out["drag_err"] = np.sqrt((np.nan_to_num(sb2) + W) / k)
    out["drag_err_within"] = np.sqrt(W / k)
    out["drag_err_between"] = np.sqrt(sb2 / k)
    out["drag_var_excess"] = np.where(rep, (s2 - W) / k, np.nan)
    out["drag_dof"] = dof
    out["n_beds"] = k
    known = np.isfinite(r2) and single != "none"
    out["bed_scatter_source"] = np.where(rep, "replicates", single if known else "none").astype(object)
    out["bed_scatter_r"] = np.where(~rep & known, np.sqrt(r2) if known else np.nan, np.nan)
    out["bed_scatter_dof"] = np.where(~rep & known, float(r2_dof), np.nan)
    study = BedScatterPrior.of(prior).source if single == "prior" else ""
    out["bed_scatter_study"] = np.where(~rep & (single == "prior"), study, "").astype(object)
    texts = [[] for _ in k]
    for c, v in zip(codes, runs.seed.to_numpy(float) if "seed" in runs else []):
        texts[c].append(f"{v:g}")
    out["seeds"] = [";".join(t) for t in texts]
    out["run"] = np.where(rep, out["_point"], out["run"].astype(str))
    for c in ("plateau", "plateau_engine"):
        if c in runs:
            out[c] = np.bincount(codes, ~runs[c].astype(bool).to_numpy()) == 0
    from .bed_spread import bed_spread
    bed_spread(out, runs, codes, k, r2 if np.isfinite(r2) and single != "none" else np.nan)
    bed_shift(out, runs, codes)
    for c in [c for c in ("h", "n_contacts", "Z", "kappa", "theta", "theta_present") if c in runs]:
        out[c] = np.bincount(codes, runs[c].to_numpy(float)) / k
    for c in ("theta", "theta_present", "kappa"):     # each bed's error and the beds' scatter, as drag_err
        if {c, f"{c}_err"} <= set(runs.columns):
            _, s2c, Wc = _moments(codes, k, runs[c].to_numpy(float), runs[f"{c}_err"].to_numpy(float))
            out[f"{c}_err"] = np.sqrt(np.maximum(np.nan_to_num(s2c), Wc) / k)
            out[f"{c}_err_within"] = np.sqrt(Wc / k)
            out[f"{c}_err_between"] = np.sqrt(np.maximum(0.0, np.nan_to_num(s2c) - Wc) / k)
            out[f"{c}_var_excess"] = np.where(k >= 2, (s2c - Wc) / k, np.nan)
    out = out.drop(columns=["_point", "_series"])
    return out.astype({"system": object, "run": object})


def bed_labels(points):
    """The beds each point was pulled in, named by its series (the run directory without its seed
    and its last part, _point_and_series; combine_beds names a replicated point by its directory
    without the seed), as a Series of labels; a run outside the workflow's layout, or a row
    without a run, is its own bed."""
    if "run" not in points.columns:
        return pd.Series([f"row {i}" for i in range(len(points))], index=points.index)
    k = points["n_beds"].to_numpy(float) if "n_beds" in points.columns else np.ones(len(points))
    return pd.Series([str(Path(str(r)).parent) if n >= 2 else _point_and_series(r)[1]
                      for r, n in zip(points["run"], k)], index=points.index)


def bed_bootstrap(runs, n_boot, seed=0, prior=None):
    """Yield n_boot point tables (combine_beds) resampled by bed, not by point.

    A series is the set of points pulled through the same beds (one bed per seed). In each
    resample, a series with k >= 2 beds draws k of its seeds with replacement and takes all
    of their pulls (so a bed's points move together); a series with one bed keeps it and is
    perturbed parametrically: drag_i + e_i z_i + sqrt(r2) drag_i z (z_i, z standard normal,
    z shared by the series' points: a bed shifts every point it carries), r2 the pooled
    between-bed scatter of the point's kind, else its prior's (single_bed_scatter on each
    scatter_kind; 0 with neither). The resamples'
    spread of any fitted quantity is then its error including bed-to-bed scatter and its
    correlations.
    """
    rng = np.random.default_rng(seed)
    priors, kind = bed_scatter_priors(prior), scatter_kind(runs)
    pooled, r_of = {}, {}
    for k in BED_SCATTER_KINDS:       # each kind its own scatter (combine_beds)
        r2, _, single = single_bed_scatter(runs[kind == k], priors[k])
        r_of[k] = float(np.sqrt(r2)) if np.isfinite(r2) else 0.0
        pooled[k] = r2 if single == "pooled" else None
    runs = _with_ids(runs).reset_index(drop=True)
    runs["_r"] = [r_of[k] for k in kind]
    series = list(runs.groupby("_series", sort=False))
    for _ in range(n_boot):
        parts = []
        for _, g in series:
            seeds = pd.unique(g.seed) if "seed" in g else np.array([np.nan])
            if len(seeds) >= 2:
                drawn = rng.choice(len(seeds), size=len(seeds), replace=True)
                for j, i in enumerate(drawn):
                    part = g[g.seed == seeds[i]].copy()
                    part["seed"] = float(j)  # a bed drawn twice counts as two beds
                    part["run"] = [f"{p}/{path_scheme.part(path_scheme.SEED.field, j)}" for p in part["_point"]]
                    parts.append(part)
            else:
                part = g.copy()
                y, e = part.drag.to_numpy(float), part.drag_err.to_numpy(float)
                part["drag"] = y + e * rng.standard_normal(len(y)) + part["_r"] * y * rng.standard_normal()
                parts.append(part)
        sample = pd.concat(parts, ignore_index=True).drop(columns=["_point", "_series", "_r"])
        yield combine_beds(sample, r2=pooled, prior=prior)
