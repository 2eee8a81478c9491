"""Fit results: parameters with one-standard-error uncertainties."""
import math
from dataclasses import dataclass, field

import numpy as np

# Bootstrap refits behind a fit's errors (the regime fits', Eq. 12's) unless told otherwise: the
# analysis's one default for it (Options, run_fits, fit_regimes, fit_scaling_law, build_report). A
# study's config states its own (report.n_boot).
N_BOOT = 200
# The ladder's own refits (Fr_2 over Fr ranges, the start's refit: `ladder table`), fewer since
# they repeat over every rung.
LADDER_N_BOOT = 100


def format_pm(value, err):
    """'1.23 ± 0.05' with the value rounded to the error's second digit."""
    if not math.isfinite(value):
        return "n/a"
    if not (math.isfinite(err) and err > 0):
        return f"{value:.4g}"
    digits = max(0, 1 - int(math.floor(math.log10(err))))
    return f"{value:.{digits}f} ± {err:.{digits}f}"


@dataclass(frozen=True)
class Param:
    """A fitted number and its standard error (NaN when not estimable)."""
    value: float
    err: float = math.nan

    def __str__(self):
        return format_pm(self.value, self.err)

    def to_dict(self):
        return {"value": _num(self.value), "err": _num(self.err)}

    @classmethod
    def from_dict(cls, d):
        return cls(_float(d["value"]), _float(d.get("err")))


@dataclass
class Fit:
    """One fitted model.

    model      name of the model function (see fits.MODELS)
    params     name -> Param, in the model function's argument order
    method     how the errors were obtained, in words
    replicates bootstrap refits (one row per refit, columns = params), kept
               so a prediction can carry correlated uncertainties
    covariance the parameters' covariance of a least-squares fit (fits._covariance_fit), for a
               derived quantity's error; not written to a fit file
    """
    model: str
    params: dict
    method: str
    n_points: int
    x_range: tuple
    meta: dict = field(default_factory=dict)
    replicates: np.ndarray = None
    covariance: np.ndarray = None

    def __getitem__(self, name):
        return self.params[name]

    def values(self):
        return {k: p.value for k, p in self.params.items()}

    def to_dict(self):
        d = {"model": self.model,
             "params": {k: p.to_dict() for k, p in self.params.items()},
             "method": self.method, "n_points": int(self.n_points),
             "x_range": [_num(v) for v in self.x_range], "meta": self.meta}
        if self.replicates is not None:
            d["replicates"] = [[_num(v) for v in row] for row in self.replicates]
        return d

    @classmethod
    def from_dict(cls, d):
        reps = d.get("replicates")
        return cls(model=d["model"],
                   params={k: Param.from_dict(v) for k, v in d["params"].items()},
                   method=d["method"], n_points=int(d["n_points"]),
                   x_range=tuple(_float(v) for v in d["x_range"]),
                   meta=dict(d.get("meta", {})),
                   replicates=None if reps is None else np.array(reps, dtype=float))


def _num(v):
    # JSON has no NaN; null stands for "not estimable".
    v = float(v)
    return v if math.isfinite(v) else None


def _float(v):
    return math.nan if v is None else float(v)
