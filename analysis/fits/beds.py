"""The beds' shared errors in the fits: a bed shifts every pull poured in it the same way, so
the points' errors are correlated within a bed (tests/python/test_calibration.py measures what
ignoring it did).

    bed_covariance   a weighted least-squares fit's parameter covariance when part of each
                     point's error is shared by its bed's points (θ and κ: fits.fit_theta,
                     fits.fit_kappa)
    slope_weights    the weights of a weighted straight line's slope (alpha_drag's per-speed
                     exponents' covariance; the Eq. 12 bed bootstrap's phi and alpha)
    BedDraws         the Eq. 12 bootstrap that resamples beds (fits.fit_scaling_law)
"""
import numpy as np
import pandas as pd

from ..core.table import bed_labels, pooled_drag_err, select, shared_bed_variance, yield_rows
from .least_squares import jacobian
from .regimes import regime_curve


def slope_weights(x, rel):
    """c with the weighted least-squares slope of ln y on x equal to sum(c ln y), for relative
    errors rel (fits.fit_power_law's weights); its variance from the errors is sum(c^2 rel^2)."""
    u = 1.0 / np.asarray(rel, float) ** 2
    dx = np.asarray(x, float) - np.sum(u * x) / np.sum(u)
    return u * dx / np.sum(u * dx * dx)


def bed_covariance(model, x, popt, s, shared, beds):
    """The parameters' covariance of a fit weighted by 1/s^2 when the points' errors s hold a part
    `shared` by every point of the same bed (labels `beds`): the sandwich A J'W S W J A, S the
    points' covariance (s^2 on the diagonal, shared_i shared_j between two points of one bed),
    A = (J'WJ)^-1, J the model's Jacobian at popt (least_squares.jacobian)."""
    J = jacobian(model, x, popt)
    W = 1.0 / s ** 2
    A = np.linalg.pinv(J.T @ (W[:, None] * J))
    S = np.outer(shared, shared) * (beds[:, None] == beds[None, :])
    np.fill_diagonal(S, s ** 2)
    B = (J * W[:, None]).T @ S @ (J * W[:, None])
    return A @ B @ A



class BedDraws:
    """The bed bootstrap of fit_scaling_law: relative deviations of the pulls at speed (in the
    fit's order) and the phi, alpha of the yield pulls they share their beds with."""

    def __init__(self, speed, parts, labels, bed_sd, own_sd, scaled):
        self.speed, self.parts, self.scaled = speed, parts, scaled
        self.codes, n = pd.factorize(labels)
        self.n_beds = len(n)
        self.bed_sd, self.own_sd = bed_sd, own_sd

    @classmethod
    def of(cls, df, rows, key, fitted, fitter, x, y, w, best):
        """None when the table does not know its beds or the exponents' errors."""
        if "drag_err_within" not in df.columns or len(x) != len(rows):
            return None
        mu, kn, gamman = key
        yl = select(yield_rows(df), mu=mu, kn=kn, gamman=gamman)
        parts, blocks = [], [rows]
        for (t, name, system, col) in ((fitted[0], "phi", "I", "D"), (fitted[1], "alpha", "II", "h")):
            g = yl[yl.system == system]
            rel = (pooled_drag_err(g) / g.drag).to_numpy(float)
            xs = np.log(g[col].to_numpy(float) + (1.0 if col == "D" else 0.0))
            if g[col].nunique() < 2 or not np.all(np.isfinite(rel) & (rel > 0)) or not np.isfinite(t[name + "_err"]):
                return None
            c = slope_weights(xs, rel)
            # The fit's error over the errors' own, sqrt(sum(c^2 rel^2)): its chi^2 scaling (1 when unscaled).
            parts.append((float(t[name]), c, max(1.0, float(t[name + "_err"]) / np.sqrt(np.sum(c * c * rel * rel)))))
            blocks.append(g)
        pts = pd.concat(blocks)
        # The pulls at speed: their own noise scaled up by sqrt(chi^2/dof) of the collapsed fit
        # (against the pooled errors it is weighted by) when above 1.
        dof = len(x) - fitter.n_free(x, best)
        chi2 = float(np.sum(w * (y - regime_curve(x, **best)) ** 2))
        scaled = dof > 0 and chi2 > dof
        own = (pts.drag_err_within / pts.drag).to_numpy(float, copy=True)
        own[:len(rows)] *= np.sqrt(chi2 / dof) if scaled else 1.0
        return cls(len(rows), parts, bed_labels(pts).to_numpy(), np.sqrt(shared_bed_variance(pts).to_numpy(float)),
                   np.nan_to_num(own), scaled)

    def draw(self, rng):
        """(relative deviations of the pulls at speed, phi, alpha) of one refit."""
        z = rng.standard_normal(self.n_beds)
        dev = self.bed_sd * z[self.codes] + self.own_sd * rng.standard_normal(len(self.codes))
        out, start = [dev[:self.speed]], self.speed
        for value, c, s in self.parts:
            out.append(value + s * float(np.sum(c * dev[start:start + len(c)])))
            start += len(c)
        return out
