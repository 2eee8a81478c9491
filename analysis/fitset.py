"""Every fit of the report (run_fits) and its file, fits.json (save_results, load_results).

The workflow's `fits` rule fits once, bootstraps included, and writes fits.json; the figure
rules and the report read the fits back from it, so a figure is redrawn without refitting.
The file is the one `save_fits` describes (read by `analysis.predict` too), with each fit's
grouping in its meta and the fits that could not be made under "notes".
"""

import dataclasses
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from .fits import (
    fit_alpha,
    fit_kappa,
    fit_phi,
    fit_regimes,
    fit_saturation,
    fit_scaling_law,
    fit_theta,
    load_fits,
    save_fits,
    sum_rule,
)
from .table import YIELD_SPEED, reference_params, select, validate_table, yield_rows


@dataclass
class Results:
    regimes: dict = field(default_factory=dict)     # (label, mu, key) -> Fit
    theta: object = None
    kappa: object = None
    phi: object = None
    alpha: object = None
    sums: object = None
    saturation: dict = field(default_factory=dict)  # D -> Fit
    laws: list = field(default_factory=list)
    notes: list = field(default_factory=list)       # fits that could not be made

    def by(self, label, mu):
        return {k[2]: f for k, f in self.regimes.items() if k[:2] == (label, mu)}


def _try(results, what, fn, *args, **kw):
    try:
        return fn(*args, **kw)
    except (ValueError, RuntimeError) as exc:
        results.notes.append(f"{what}: not fitted ({exc})")
        return None


def run_fits(df, n_boot=200, seed=0):
    """Every fit of the report, on the reference contact law where it applies."""
    validate_table(df)
    r = Results()
    kn, gn = reference_params(df)
    ref = select(df, kn=kn, gamman=gn)
    for label, system, by, mus in (("D", "I", "D", (0.5, 0.0)), ("h", "II", "h", (0.5,))):
        for mu in mus:
            for key, g in select(ref, mu=mu, system=system).groupby(by):
                if (~np.isclose(g.V, YIELD_SPEED)).sum() == 0:
                    continue        # yield pulls only: no drag-vs-Fr series here
                fit = _try(r, f"regimes at mu={mu:g}, {by}={key:g}", fit_regimes, g.Fr, g.drag,
                           g.drag_err, regime1="power" if mu == 0 else "constant",
                           n_boot=n_boot, seed=seed)
                if fit is not None:
                    r.regimes[(label, mu, key)] = fit
    obs = select(ref, mu=0.5, system="I")
    th = obs.dropna(subset=["theta"])
    r.theta = _try(r, "theta(Fr)", fit_theta, th.Fr, th.theta) if len(th) else None
    ka = obs.dropna(subset=["kappa"])
    r.kappa = _try(r, "kappa(Fr)", fit_kappa, ka) if len(ka) else None
    r.phi, r.alpha = fit_phi(df), fit_alpha(df)
    r.sums = sum_rule(r.phi, r.alpha)
    for D, g in yield_rows(ref).query("system == 'I'").groupby("D"):
        if g.mu.nunique() >= 4:
            fit = _try(r, f"F_Y(mu) saturation at D={D:g}", fit_saturation, g.mu, g.drag)
            if fit is not None:
                r.saturation[D] = fit
    for mu in sorted(set(r.sums.mu[np.isclose(r.sums.kn, kn) & np.isclose(r.sums.gamman, gn)])):
        law = _try(r, f"scaling law at mu={mu:g}", fit_scaling_law, df, r.phi, r.alpha,
                   mu=mu, kn=kn, gamman=gn, n_boot=n_boot, seed=seed)
        if law is not None:
            r.laws.append(law)
    return r




# Columns of the tables of fits.json (fits.fit_phi, fit_alpha, sum_rule), so that an empty
# table read back keeps them.
_EXPONENT = ["mu", "kn", "gamman", "{0}", "{0}_err", "{1}", "{1}_err", "n", "{2}_min", "{2}_max"]
TABLE_COLUMNS = {
    "phi": [c.format("phi", "f", "D") for c in _EXPONENT],
    "alpha": [c.format("alpha", "g", "h") for c in _EXPONENT],
    "sum_rule": ["mu", "kn", "gamman", "phi", "phi_err", "alpha", "alpha_err", "sum", "sum_err"],
}


def _with_meta(fit, **meta):
    return dataclasses.replace(fit, meta={**fit.meta, **meta})


def save_results(path, r):
    """Write every fit of r to the fit file path (fits.json)."""
    fits = {
        f"regimes_mu{mu:g}_{by}{key:g}": _with_meta(f, group=by, mu=float(mu), group_value=float(key))
        for (by, mu, key), f in r.regimes.items()
    }
    fits.update({k: v for k, v in (("theta", r.theta), ("kappa", r.kappa)) if v is not None})
    fits.update({f"saturation_D{D:g}": _with_meta(f, D=float(D)) for D, f in r.saturation.items()})
    save_fits(path, laws=r.laws, fits=fits, tables={"phi": r.phi, "alpha": r.alpha, "sum_rule": r.sums},
              notes=r.notes)


def _frame(records, columns):
    df = pd.DataFrame(records, columns=columns)
    return df.astype(float) if df.empty else df.apply(pd.to_numeric)


def load_results(path):
    """The Results written by save_results (FitFileError if path is not such a file)."""
    ff = load_fits(path)
    r = Results(laws=ff.laws, notes=list(ff.notes))
    for name, f in ff.fits.items():
        if name.startswith("regimes_"):
            r.regimes[(f.meta["group"], f.meta["mu"], f.meta["group_value"])] = f
        elif name.startswith("saturation_"):
            r.saturation[f.meta["D"]] = f
        elif name in ("theta", "kappa"):
            setattr(r, name, f)
    tables = {k: _frame(ff.tables.get(k, []), cols) for k, cols in TABLE_COLUMNS.items()}
    r.phi, r.alpha, r.sums = tables["phi"], tables["alpha"], tables["sum_rule"]
    return r
