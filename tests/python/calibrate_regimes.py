"""Calibrate the bootstrap errors of the three-regime fit against known truth.

Draws N synthetic drag(Fr) series with crossovers at Fr = 1 and 5 and
relative Gaussian noise (as test_regimes.py does), fits each with
fit_regimes, and compares for every parameter the mean reported standard
error with the actual scatter of the estimates around the truth:

    nice -n 19 /usr/bin/python3 tests/python/calibrate_regimes.py [--sets N] [--mu 0.5]
        [--noise 0.02] [--n-boot N] [--grid synth|tests] [--sigma observed|true]
        [--discontinuous] [--seed S]

The defaults mimic one series of the synthetic pull table (tests/python/synth.py):
14 Fr values, 2 % noise, errors proportional to the measured drag.

A calibrated error has RMS deviation / mean error near 1 and a 2-sigma
coverage near 95 %. RMS/qerr divides by the quadratic mean of the errors
instead: it is ~1 when the bootstrap variance is right on average, and lies
below RMS/err by as much as the per-set errors scatter. Not a test (too
slow); run it by hand under nice. With N sets the ratios are uncertain by
~1/sqrt(2N) or more (the deviations have heavy tails).
"""
import argparse
import time

import numpy as np
import synth  # tests/python/synth.py, beside this script

from analysis.core.physics import froude
from analysis.core.result import N_BOOT
from analysis.core.table import YIELD_SPEED
from analysis.fits.regimes import fit_regimes, regime_curve

GRIDS = {
    # The grid of test_regimes.py: dense in regime I, uniform above.
    "tests": np.concatenate([np.geomspace(0.02, 0.8, 8), np.linspace(1.0, 10.0, 19)]),
    # One D- or h-series of the synthetic pull table, as run_fits fits it:
    # the yield pull (D = 4) and the pulls at speed.
    "synth": np.concatenate([[float(froude(YIELD_SPEED, 4.0))], synth.FR_GRID]),
}


def calibrate(n_sets, mu=0.5, noise=0.02, n_boot=N_BOOT, grid="synth", sigma="observed", seed0=0,
              continuous=True):
    """Per parameter: (truth, estimates, reported errors), arrays over the sets."""
    Fr = GRIDS[grid]
    true = synth.G_params(mu)
    truth = regime_curve(Fr, **true)
    est, err = [], []
    for i in range(n_sets):
        rng = np.random.default_rng(10_000 + seed0 + i)
        y = truth * (1.0 + noise * rng.standard_normal(len(Fr)))
        s = noise * (truth if sigma == "true" else np.abs(y))
        fit = fit_regimes(Fr, y, s, n_boot=n_boot, seed=seed0 + i,
                          regime1="power" if mu == 0 else "constant", continuous=continuous)
        est.append([fit[k].value for k in true])
        err.append([fit[k].err for k in true])
    return {k: (true[k], np.array(est)[:, j], np.array(err)[:, j]) for j, k in enumerate(true)}


def summary(res):
    """Rows (name, mean err, RMS deviation, RMS/mean err, RMS/quadratic-mean err,
    2-sigma coverage, bias/RMS)."""
    rows = []
    for k, (t, v, e) in res.items():
        ok = np.isfinite(e)
        d = v[ok] - t
        rms = float(np.sqrt(np.mean(d ** 2)))
        me = float(np.mean(e[ok]))
        qe = float(np.sqrt(np.mean(e[ok] ** 2)))
        rows.append((k, me, rms, rms / me, rms / qe, float(np.mean(np.abs(d) < 2 * e[ok])),
                     float(np.mean(d)) / rms if rms > 0 else 0.0))
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", type=int, default=200)
    ap.add_argument("--mu", type=float, default=0.5, help="0 fits the power-law regime I")
    ap.add_argument("--noise", type=float, default=0.02, help="relative noise per point")
    ap.add_argument("--n-boot", type=int, default=N_BOOT,
                    help="bootstrap refits per fit (default %(default)s, the analysis's N_BOOT)")
    ap.add_argument("--grid", choices=sorted(GRIDS), default="synth")
    ap.add_argument("--sigma", choices=("true", "observed"), default="observed",
                    help="weights from the true drag, or from the noisy one as in the pull table")
    ap.add_argument("--discontinuous", action="store_true")
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args(argv)
    t0 = time.time()
    res = calibrate(a.sets, a.mu, a.noise, a.n_boot, a.grid, a.sigma, a.seed,
                    continuous=not a.discontinuous)
    print(f"{a.sets} sets, mu={a.mu:g}, noise={a.noise:g}, n_boot={a.n_boot}, grid={a.grid}, "
          f"sigma={a.sigma}, {'dis' if a.discontinuous else ''}continuous, seed={a.seed} "
          f"({time.time() - t0:.0f} s)")
    print(f"{'param':>6} {'mean err':>10} {'RMS dev':>10} {'RMS/err':>8} {'RMS/qerr':>9} "
          f"{'cov 2s':>7} {'bias/RMS':>9}")
    for k, me, rms, ratio, qratio, cov, bias in summary(res):
        print(f"{k:>6} {me:10.4g} {rms:10.4g} {ratio:8.3f} {qratio:9.3f} {100 * cov:6.1f}% "
              f"{bias:9.2f}")


if __name__ == "__main__":
    main()
