"""Calibration of every fitted number's error against known truth (issue 30, item 4).

Synthetic run tables in the workflow's layout (synth.py's laws, every point poured in `beds`
beds): each bed shifts every pull it carries the same way (the drag by a relative factor, θ and
κ by an offset), each pull adds its own noise, of the size its reported error says. The point
table (combine_beds) is fitted as the workflow fits it (run_fits), and each number's error is
judged by z = (estimate - truth) / error: its RMS (1 when the error is right) and how often the
report's 95 % interval (report.within_quantile at the number's dof) holds the truth.

    nice -n 19 .venv/bin/python tests/python/calibration.py [--sets N] [--n-boot B] [--beds K]

Not a test (test_calibration.py is, on fewer sets): the figures of the issue and of the
calibrated estimators' comments come from here.
"""
import argparse
import math
import sys
import time
from collections import defaultdict
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
import synth  # noqa: E402  tests/python/synth.py, beside this file

from analysis.core.physics import froude  # noqa: E402
from analysis.core.table import YIELD_SPEED, combine_beds  # noqa: E402
from analysis.fits.fitset import Options, run_fits  # noqa: E402
from analysis.report.report import errors_from_points, fit_dof, within_quantile  # noqa: E402

THETA_TRUE = {"U1": -0.15, "U2": 0.38, "U3": 2.45}     # synth.py's theta(Fr)
KAPPA_TRUE = {"k0": 0.887, "k1": 0.185}                # synth.py's kappa(Fr)
REL_BED, REL_RUN = 0.03, 0.02       # drag: a bed's relative shift, a pull's relative noise
THETA_BED, THETA_RUN = 0.005, 0.005  # theta: a bed's offset, a pull's noise [rad]
KAPPA_BED, KAPPA_RUN = 0.01, 0.01    # kappa likewise


def bed_runs(seed, beds=2, rel_bed=REL_BED, rel_run=REL_RUN, theta_bed=THETA_BED, kappa_bed=KAPPA_BED,
             mus=(0.0, 0.1, 0.3, 0.5, 0.9)):
    """A run table (one row per pull) with synth.make_table's points, each poured in `beds`
    beds. A bed is a (system, D, h, mu) with its seed: its yield pull and every speed pulled in
    it share its shift."""
    rng = np.random.default_rng(seed)
    points = defaultdict(list)   # (system, D, h, mu) -> speeds

    for mu in mus:
        for D in (1, 2, 3, 4, 5, 6, 8, 10):
            points[("I", float(D), synth.H_SYSTEM_I, mu)].append(YIELD_SPEED)
        for h in (10.0, 25.0, 45.0, 55.0, 65.0):
            points[("II", 4.0, h, mu)].append(YIELD_SPEED)
    for mu in (0.0, 0.5):
        for D in (2.0, 4.0, 6.0):
            points[("I", D, synth.H_SYSTEM_I, mu)] += list(synth.speed_for(synth.FR_GRID, D))
    for mu in (0.1, 0.3):
        points[("I", 2.0, synth.H_SYSTEM_I, mu)] += list(synth.speed_for(synth.FR_GRID[synth.FR_GRID <= 1], 2.0))
    for h in (25.0, 45.0, 65.0):
        points[("II", 4.0, h, 0.5)] += list(synth.speed_for(synth.FR_GRID, 4.0))
    rows = []
    for (system, D, h, mu), speeds in points.items():
        for s in range(1, beds + 1):
            shift = 1.0 + rel_bed * rng.standard_normal()
            dtheta, dkappa = theta_bed * rng.standard_normal(), kappa_bed * rng.standard_normal()
            for V in speeds:
                Fr = float(froude(V, D))
                F = synth.drag_true(D, h, mu, Fr) * shift * (1.0 + rel_run * rng.standard_normal())
                kappa = KAPPA_TRUE["k0"] + KAPPA_TRUE["k1"] * Fr + dkappa + KAPPA_RUN * rng.standard_normal()
                theta = (THETA_TRUE["U1"] * Fr ** THETA_TRUE["U2"] + np.pi / THETA_TRUE["U3"] + dtheta
                         + THETA_RUN * rng.standard_normal())
                n = 0.5 * (D + 1.0) ** 2 / (1.0 + 0.2 * Fr)
                rows.append(dict(system=system, D=D, h=h, mu=mu, kn=synth.KN, gamman=synth.GAMMAN, V=float(V),
                                 Fr=Fr, drag=F, drag_err=rel_run * abs(F), n_contacts=n, theta=theta,
                                 theta_err=THETA_RUN, Z=kappa * n * 2 * np.sqrt(3) / (D + 1.0) ** 2,
                                 kappa=kappa, kappa_err=KAPPA_RUN, drag_dof=50.0, plateau=True, seed=float(s),
                                 run=f"pulls/system~{system}/D~{D:g}/h~{h:g}/mu~{mu:g}/seed~{s}/V~{V:.6g}"))
    return pd.DataFrame(rows)


def lambda_truth(mu):
    """Eq. 12's collapsed G: synth's prefactor times its three-regime G."""
    g = synth.G_params(mu)
    c = synth.prefactor(mu)
    return {k: (v * c if k in ("a0", "b0", "a1", "b1", "a2", "b2") else v) for k, v in g.items()}


def zscores(r):
    """kind -> list of (z, q): z = (estimate - truth)/error, q the report's 95 % quantile."""
    out = defaultdict(list)

    def add(kind, value, err, truth, dof, fit=None, chi2_dof=None):
        if err is None or not (math.isfinite(err) and err > 0 and math.isfinite(value)):
            out[kind + " (no error)"].append((np.nan, np.nan))
            return
        known = errors_from_points(fit, {"chi2_dof": chi2_dof})   # the report's quantile
        out[kind].append(((value - truth) / err, within_quantile(None if known else dof)))

    for f in r.regimes.values():
        for k, truth in (("Fr1", synth.FR1), ("Fr2", synth.FR2)):
            add(k, f[k].value, f[k].err, truth, fit_dof(f), f)
    if r.theta is not None:
        for k, truth in THETA_TRUE.items():
            add(f"theta {k}", r.theta[k].value, r.theta[k].err, truth, fit_dof(r.theta), r.theta)
    if r.kappa is not None:
        for k, truth in KAPPA_TRUE.items():
            add(f"kappa {k}", r.kappa[k].value, r.kappa[k].err, truth, fit_dof(r.kappa), r.kappa)
    for _, t in r.phi.iterrows():
        add("phi", t.phi, t.phi_err, synth.phi_true(t.mu), t.n - 2, chi2_dof=t.chi2_dof)
    for _, t in r.alpha.iterrows():
        add("alpha (yield)", t.alpha, t.alpha_err, synth.alpha_true(t.mu), t.n - 2, chi2_dof=t.chi2_dof)
    for _, t in r.alpha_drag.iterrows():
        add("alpha (drag, averaged)", t.alpha, t.alpha_err, synth.alpha_true(t.mu), None)
    for _, t in r.alpha_speeds.iterrows():
        add("alpha (drag, per speed)", t.alpha, t.alpha_err, synth.alpha_true(t.mu), t.n - 2, chi2_dof=t.chi2_dof)
    for law in r.laws:
        truth = lambda_truth(law.mu)
        for k, v in law.regimes.params.items():
            kind = "law " + (k if k in ("Fr1", "Fr2") else "lambda")
            if k in ("c0",):
                kind = "law c0"
            add(kind if k not in ("a0", "a1", "b1", "a2", "b2", "b0") else "law lambda", v.value, v.err,
                truth[k], fit_dof(law.regimes), law.regimes)
    return out


def measure(sets, n_boot=50, beds=2, seed0=0, **kw):
    """kind -> array of (z, q) over `sets` synthetic studies."""
    acc = defaultdict(list)
    for i in range(sets):
        pts = combine_beds(bed_runs(seed0 + i, beds=beds, **kw))
        r = run_fits(pts, options=Options(n_boot=n_boot, seed=seed0 + i))
        for k, v in zscores(r).items():
            acc[k] += v
    return {k: np.array(v) for k, v in acc.items()}


def figures(zq):
    """(RMS of z, share of |z| <= q, count) of an array of (z, q)."""
    z, q = zq[:, 0], zq[:, 1]
    ok = np.isfinite(z)
    return float(np.sqrt(np.mean(z[ok] ** 2))), float(np.mean(np.abs(z[ok]) <= q[ok])), int(ok.sum())


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", type=int, default=40)
    ap.add_argument("--n-boot", type=int, default=50)
    ap.add_argument("--beds", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args(argv)
    import warnings
    warnings.simplefilter("ignore")
    t0 = time.time()
    res = measure(a.sets, a.n_boot, a.beds, a.seed)
    print(f"{a.sets} sets, {a.beds} beds, n_boot {a.n_boot}, seed {a.seed} ({time.time() - t0:.0f} s)")
    print(f"{'kind':>26} {'n':>5} {'RMS z':>7} {'cover95':>8} {'max|z|':>7}")
    for k in sorted(res):
        if "no error" in k:
            print(f"{k:>26} {len(res[k]):5d}")
            continue
        rms, cov, n = figures(res[k])
        print(f"{k:>26} {n:5d} {rms:7.3f} {100 * cov:7.1f}% {np.nanmax(np.abs(res[k][:, 0])):7.2f}")


if __name__ == "__main__":
    import contextlib
    import io
    with contextlib.redirect_stderr(io.StringIO()):
        main()
