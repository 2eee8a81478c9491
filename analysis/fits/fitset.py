"""Every fit of the report (run_fits) and its file, fits.json (save_results, load_results).

The workflow's `fits` rule fits once, bootstraps included, and writes fits.json; the figure
rules and the report read the fits back from it, so a figure is redrawn without refitting.
The file is the one `save_fits` describes (read by `analysis.predict` too), with each fit's
grouping in its meta and the fits that could not be made under "notes".
"""

import dataclasses
import sys
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..core import paper
from ..core.bed_shift import curve_errors
from ..core.result import N_BOOT
from ..core.table import (
    bed_labels,
    is_yield,
    observable_errors,
    pooled_bed_r2,
    pooled_drag_err,
    reference_params,
    select,
    validate_table,
    yield_rows,
)
from .alpha_drag import ALPHA_DRAG_COLUMNS, ALPHA_SPEED_COLUMNS, ALPHA_SPEEDS, fit_alpha_drag
from .fit_file import load_fits, save_fits
from .fits import (
    GOODNESS_COLUMNS,
    THETA_DEFINITIONS,
    fit_alpha,
    fit_kappa,
    fit_phi,
    fit_regimes,
    fit_saturation,
    fit_scaling_law,
    fit_theta,
    series_labels,
    sum_rule,
)
from .goodness import describe


@dataclass
class Options:
    """The choices of the fits that a study's config sets (report.* keys)."""

    n_boot: int = N_BOOT
    seed: int = 0
    h_min: float = 0.0                 # Eq. 12 and Fig. 19 use pulls at h >= h_min only (0: all)
    alpha_speeds: tuple = ALPHA_SPEEDS  # speeds of the averaged alpha_mu (Sec. III H)

    def to_dict(self):
        return {"n_boot": int(self.n_boot), "seed": int(self.seed), "h_min": float(self.h_min),
                "alpha_speeds": [float(v) for v in self.alpha_speeds]}

    @classmethod
    def from_dict(cls, d):
        d = d or {}
        return cls(n_boot=int(d.get("n_boot", N_BOOT)), seed=int(d.get("seed", 0)),
                   h_min=float(d.get("h_min") or 0.0),
                   alpha_speeds=tuple(float(v) for v in d.get("alpha_speeds", ALPHA_SPEEDS)))


@dataclass
class Results:
    regimes: dict = field(default_factory=dict)     # (label, mu, key) -> Fit
    theta: object = None          # Eq. 7 of θ per contact formation (table column theta)
    theta_present: object = None  # Eq. 7 of θ over the contacts present, time-weighted (theta_present)
    kappa: object = None
    phi: object = None
    alpha: object = None          # alpha_mu from the yield force (Fig. 17)
    sums: object = None           # phi + alpha (yield force)
    alpha_drag: object = None     # the paper's alpha_mu: drag at the speeds, averaged (Fig. 18)
    alpha_speeds: object = None   # its per-speed exponents
    sums_drag: object = None      # phi + the averaged alpha_mu (Fig. 18b)
    bed_scatter: float = 0.0      # relative between-bed scatter the regime bootstraps used
    saturation: dict = field(default_factory=dict)  # D -> Fit
    laws: list = field(default_factory=list)
    notes: list = field(default_factory=list)       # fits that could not be made
    options: Options = field(default_factory=Options)

    def by(self, label, mu):
        return {k[2]: f for k, f in self.regimes.items() if k[:2] == (label, mu)}


def _try(results, what, fn, *args, **kw):
    try:
        return fn(*args, **kw)
    except (ValueError, RuntimeError) as exc:
        results.notes.append(f"{what}: not fitted ({exc})")
        return None


def _yield_beside(g, pool):
    """The series' yield pull(s) (V = 0.01), reported beside its drag-vs-Fr fit, not in it;
    its error with the between-bed scatter pooled over the yield pulls `pool`
    (table.pooled_drag_err)."""
    y = yield_rows(g)
    if y.empty:
        return None
    err = np.asarray(pooled_drag_err(y, pool), float)
    return {"drag": float(y.drag.mean()),
            "drag_err": float(np.sqrt(np.sum(err ** 2)) / len(err)) if np.all(np.isfinite(err)) else None,
            "Fr": float(y.Fr.mean()), "n": int(len(y))}


def point_bed_scatter(points):
    """The pooled relative between-bed standard deviation of the drag, sqrt(r2) over the points
    with two or more beds, from a point table (r2: table.pooled_bed_r2, as pooled_drag_err's
    weights take it); when no point has replicate beds, the
    prior the points poured once took (column bed_scatter_r of the points whose
    bed_scatter_source is "prior": the config's table.bed_scatter); else 0 (the scatter is then
    not measured, and the fits say so)."""
    if not {"n_beds", "drag_err_between"} <= set(points.columns):
        return 0.0
    rep = points[points.n_beds.astype(float) >= 2]
    if rep.empty:
        if {"bed_scatter_source", "bed_scatter_r"} <= set(points.columns):
            prior = points.bed_scatter_r[points.bed_scatter_source == "prior"].astype(float)
            if len(prior) and np.isfinite(prior).all():
                return float(prior.max())
        return 0.0
    return float(np.sqrt(pooled_bed_r2(rep)))


def run_fits(df, n_boot=N_BOOT, seed=0, options=None):
    """Every fit of the report, on the reference contact law where it applies. options (an
    Options) overrides n_boot and seed."""
    validate_table(df)
    opt = options or Options(n_boot=n_boot, seed=seed)
    n_boot, seed = opt.n_boot, opt.seed
    r = Results(options=opt)
    kn, gn = reference_params(df)
    ref = select(df, kn=kn, gamman=gn)
    bed_scatter = point_bed_scatter(df[~is_yield(df)])   # the regime fits' points are at speed
    ref_yields = yield_rows(ref)   # the pool of a yield pull's error beside a regime fit
    r.bed_scatter = bed_scatter
    # Every friction with a drag-vs-Fr series, not only the paper's figures' (mu = 0.5 and 0),
    # so that "the crossovers do not depend on mu" can be tested; a series with too few speeds
    # for the three regimes is named in the notes (_try), a yield-only one has no series.
    for label, system, by in (("D", "I", "D"), ("h", "II", "h")):
        for mu in sorted(set(select(ref, system=system).mu), reverse=True):
            for key, g in select(ref, mu=mu, system=system).groupby(by):
                moving = g[~is_yield(g)]
                if moving.empty:
                    continue        # yield pulls only: no drag-vs-Fr series here
                # The paper fits the drag-vs-Fr data (Figs. 5, 10, 16); the yield pull is
                # reported beside the fit, not in it (at mu = 0 it alone would fix a'').
                fit = _try(r, f"regimes at mu={mu:g}, {by}={key:g}", fit_regimes, moving.Fr,
                           moving.drag, curve_errors(moving), regime1="power" if mu == 0 else "constant",
                           n_boot=n_boot, seed=seed, bed_scatter=bed_scatter,
                           beds=int(moving["n_beds"].min()) if "n_beds" in moving.columns else 1,
                           noise=moving["drag_err_within"] if "drag_err_within" in moving.columns else None)
                if fit is not None:
                    fit.meta["yield_pull"] = _yield_beside(g, ref_yields)
                    fit.meta["replicate_beds"] = _beds(moving)
                    r.regimes[(label, mu, key)] = fit
    fit_observables(r, select(ref, mu=0.5, system="I"), ref)
    r.phi, r.alpha = fit_phi(df), fit_alpha(df)
    r.sums = sum_rule(r.phi, r.alpha)
    r.alpha_drag, r.alpha_speeds = fit_alpha_drag(df, speeds=opt.alpha_speeds)
    r.sums_drag = sum_rule(r.phi, r.alpha_drag)
    # Weighted by the yield forces' own within-run errors and their bed scatter pooled over
    # every yield pull of system I: a point's own two beds give its scatter at 1 dof.
    yields = ref_yields.query("system == 'I'")
    for D, g in yields.groupby("D"):
        if g.mu.nunique() >= 4:
            fit = _try(r, f"F_Y(mu) saturation at D={D:g}", fit_saturation, g.mu, g.drag,
                       pooled_drag_err(g, yields))
            if fit is not None:
                r.saturation[D] = fit
    shallow_in = _shallow_pulls_note(df, opt.h_min)
    if shallow_in:
        r.notes.append(shallow_in)
        print(f"warning: {shallow_in}", file=sys.stderr)
    for mu in sorted(set(r.sums.mu[np.isclose(r.sums.kn, kn) & np.isclose(r.sums.gamman, gn)])):
        law = _try(r, f"scaling law at mu={mu:g}", fit_scaling_law, df, r.phi, r.alpha,
                   mu=mu, kn=kn, gamman=gn, h_min=opt.h_min, n_boot=n_boot, seed=seed)
        if law is not None:
            r.laws.append(law)
    return r


def fit_observables(r, obs, pool=None):
    """θ(Fr) (Eq. 7) and κ(Fr) (Fig. 8) of the rows obs (system I at mu = 0.5, the reference
    contact law) into the Results r, weighted by their errors (table.observable_errors: with
    replicate beds the between-bed part pooled over `pool`, which each bed shares, enters the
    covariance). θ twice, by THETA_DEFINITIONS: r.theta per contact formation, r.theta_present over
    the contacts present at each sample (None where the table has no such column or only NaN,
    as from run files before the engine recorded it)."""
    for col in THETA_DEFINITIONS:
        th = obs.dropna(subset=[col]) if col in obs.columns else obs.iloc[:0]
        err, shared = observable_errors(th, col, pool) if f"{col}_err" in th.columns else (None, None)
        fit = _try(r, f"{col}(Fr)", fit_theta, th.Fr, th[col], err, series_labels(th), shared,
                   bed_labels(th)) if len(th) else None
        setattr(r, col, None if fit is None else _with_meta(fit, definition=THETA_DEFINITIONS[col]))
    ka = obs.dropna(subset=["kappa"])
    r.kappa = _try(r, "kappa(Fr)", fit_kappa, ka, pool) if len(ka) else None


def _shallow_pulls_note(df, h_min):
    """A warning when Eq. 12 (and Fig. 19) would mix pulls shallower than the paper's deep
    limit with deeper ones: the paper's collapse holds only from DEEP_H on, so on a table that
    reaches that deep, h_min below it silently bends the fit toward the shallow beds."""
    h = df["h"].dropna()
    shallow = paper.at_least(h, h_min) & ~paper.at_least(h, paper.DEEP_H)
    if not shallow.any() or not paper.at_least(h, paper.DEEP_H).any():
        return ""
    n = int(shallow.sum())
    return (f"Eq. 12 and Fig. 19 include {n} pull(s) at {h_min:g} <= h < {paper.DEEP_H:g} d, though the table "
            f"has pulls at h >= {paper.DEEP_H:g} d, where the paper's collapse holds (Sec. III H): set "
            f"report.h_min: {paper.DEEP_H:g} in the config (or fit --h-min {paper.DEEP_H:g}) to leave them out")


def _beds(rows):
    """How many replicate beds (distinct seeds) a fit rests on, per point at most: the
    table's `seed` column when it has one, else 1."""
    if "seed" not in rows.columns:
        return 1
    return int(rows.groupby(["D", "h", "V"]).seed.nunique().max())


# --- the summary keys of fits.json ---------------------------------------

def _exponent_list(table, col):
    return [{"mu": float(t.mu), "kn": float(t.kn), "gamman": float(t.gamman),
             "value": _num(t[col]), "error": _num(t[col + "_err"])}
            | ({"n_speeds": int(t.n_speeds), "speeds": t.speeds, "spread": _num(t.spread)}
               if "n_speeds" in t else {})
            | ({"chi2_dof": _num(t.chi2_dof), "trend_p": _num(t.trend_p), "rejected": bool(t.rejected == 1)}
               if "chi2_dof" in t else {})
            for _, t in table.iterrows()]


def _num(v):
    v = float(v)
    return v if np.isfinite(v) else None


def crossover_list(r):
    """Every fitted Fr_1, Fr_2: one entry per drag-vs-Fr series and per Eq. 12 collapse."""
    out = []
    for (label, mu, key), f in sorted(r.regimes.items(), key=lambda kv: (kv[0][0], -kv[0][1], kv[0][2])):
        out.append({"series": f"{'I' if label == 'D' else 'II'}: drag vs Fr at {label} = {key:g}",
                    "mu": float(mu), "D": float(key) if label == "D" else None,
                    "h": float(key) if label == "h" else None,
                    "Fr1": _num(f["Fr1"].value), "Fr1_error": _num(f["Fr1"].err),
                    "Fr2": _num(f["Fr2"].value), "Fr2_error": _num(f["Fr2"].err),
                    "at_bounds": f.meta.get("at_bounds", []), "violations": f.meta.get("violations", [])})
    for law in r.laws:
        f = law.regimes
        out.append({"series": "Eq. 12 collapse", "mu": float(law.mu), "D": None, "h": None,
                    "Fr1": _num(f["Fr1"].value), "Fr1_error": _num(f["Fr1"].err),
                    "Fr2": _num(f["Fr2"].value), "Fr2_error": _num(f["Fr2"].err),
                    "at_bounds": f.meta.get("at_bounds", []), "violations": f.meta.get("violations", [])})
    return out


def named_fits(r):
    """name -> Fit of every fit in r, with its grouping in its meta (the keys of fits.json)."""
    fits = {
        f"regimes_mu{mu:g}_{by}{key:g}": _with_meta(f, group=by, mu=float(mu), group_value=float(key))
        for (by, mu, key), f in r.regimes.items()
    }
    fits.update({k: getattr(r, k) for k in (*THETA_DEFINITIONS, "kappa") if getattr(r, k) is not None})
    fits.update({f"saturation_D{D:g}": _with_meta(f, D=float(D)) for D, f in r.saturation.items()})
    fits.update({f"law_mu{law.mu:g}": law.regimes for law in r.laws})
    return fits


def summary(r):
    """The top-level keys of fits.json that name the paper's numbers (analysis/README.md)."""
    bounds, violated, rejected = [], [], []
    for name, f in named_fits(r).items():
        bounds += [{"fit": name, "what": w} for w in f.meta.get("at_bounds", [])]
        violated += [{"fit": name, "what": w} for w in f.meta.get("violations", [])]
        g = f.meta.get("goodness")
        rejected += [{"fit": name, "what": describe(g)}] if g and g.get("rejected") else []
    return {"phi": _exponent_list(r.phi, "phi"), "alpha": _exponent_list(r.alpha, "alpha"),
            "alpha_drag": _exponent_list(r.alpha_drag, "alpha"), "crossovers": crossover_list(r),
            "at_bounds": bounds, "violations": violated, "rejected": rejected, "options": r.options.to_dict(),
            "bed_scatter": float(r.bed_scatter)}


# Columns of the tables of fits.json (fits.fit_phi, fit_alpha, sum_rule), so that an empty
# table read back keeps them.
_EXPONENT = ["mu", "kn", "gamman", "{0}", "{0}_err", "{1}", "{1}_err", "n", "{2}_min", "{2}_max"] + GOODNESS_COLUMNS
TABLE_COLUMNS = {
    "phi": [c.format("phi", "f", "D") for c in _EXPONENT],
    "alpha": [c.format("alpha", "g", "h") for c in _EXPONENT],
    "sum_rule": ["mu", "kn", "gamman", "phi", "phi_err", "alpha", "alpha_err", "sum", "sum_err"],
    "alpha_drag": ALPHA_DRAG_COLUMNS,
    "alpha_speeds": ALPHA_SPEED_COLUMNS,
    "sum_rule_drag": ["mu", "kn", "gamman", "phi", "phi_err", "alpha", "alpha_err", "sum", "sum_err"],
}
TABLE_ATTR = {"phi": "phi", "alpha": "alpha", "sum_rule": "sums", "alpha_drag": "alpha_drag",
              "alpha_speeds": "alpha_speeds", "sum_rule_drag": "sums_drag"}


def _with_meta(fit, **meta):
    return dataclasses.replace(fit, meta={**fit.meta, **meta})


def save_results(path, r):
    """Write every fit of r to the fit file path (fits.json)."""
    fits = {k: v for k, v in named_fits(r).items() if not k.startswith("law_")}
    tables = {k: getattr(r, a) for k, a in TABLE_ATTR.items() if getattr(r, a) is not None}
    save_fits(path, laws=r.laws, fits=fits, tables=tables, notes=r.notes, summary=summary(r))


def _frame(records, columns):
    df = pd.DataFrame(records, columns=columns)
    if df.empty:
        return df.astype(float)
    num = [c for c in columns if c != "speeds"]
    df[num] = df[num].apply(pd.to_numeric)
    return df


def load_results(path):
    """The Results written by save_results (FitFileError if path is not such a file)."""
    ff = load_fits(path)
    r = Results(laws=ff.laws, notes=list(ff.notes), options=Options.from_dict(ff.summary.get("options")),
                bed_scatter=float(ff.summary.get("bed_scatter", 0.0)))
    for name, f in ff.fits.items():
        if name.startswith("regimes_"):
            r.regimes[(f.meta["group"], f.meta["mu"], f.meta["group_value"])] = f
        elif name.startswith("saturation_"):
            r.saturation[f.meta["D"]] = f
        elif name in (*THETA_DEFINITIONS, "kappa"):
            setattr(r, name, f)
    for k, cols in TABLE_COLUMNS.items():
        setattr(r, TABLE_ATTR[k], _frame(ff.tables.get(k, []), cols))
    return r
