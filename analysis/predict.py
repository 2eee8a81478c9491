"""Drag from the fitted scaling law (paper Eq. 12), with its uncertainty.

    python -m analysis.predict --D 4 --h 50 --mu 0.5 --V 2 --fits fits.json

Between two fitted friction coefficients the drag and its error are
interpolated linearly in mu; outside them the nearest law is used. Either
way, and for D, h or Fr outside the data behind the law, a warning goes to
standard error: the law is then extrapolated.
"""
import argparse
import json
import sys
from dataclasses import dataclass, field

import numpy as np

from .core.table import froude
from .fits.fit_file import FitFileError, load_fits


@dataclass
class Prediction:
    drag: float
    err: float
    Fr: float
    warnings: list = field(default_factory=list)
    notes: list = field(default_factory=list)


def _outside(name, value, rng):
    lo, hi = rng
    if value < lo * (1 - 1e-9) or value > hi * (1 + 1e-9):
        return f"{name} = {value:g} is outside the fitted range [{lo:g}, {hi:g}]; extrapolating"
    return None


def predict(laws, D, h, mu, V, kn=None, gamman=None):
    """Predict the drag from a list of ScalingLaw (as read by load_fits)."""
    if D <= 0 or h <= 0 or V < 0 or mu < 0:
        raise ValueError("need D > 0, h > 0, V >= 0 and mu >= 0")
    if not laws:
        raise ValueError("the fit file holds no scaling law")
    pairs = [(law.kn, law.gamman) for law in laws]
    if kn is None or gamman is None:
        kn, gamman = max(set(pairs), key=pairs.count)
    laws = sorted((law for law in laws if np.isclose(law.kn, kn) and np.isclose(law.gamman, gamman)),
                  key=lambda law: law.mu)
    if not laws:
        raise ValueError(f"no law fitted for kn={kn:g}, gamman={gamman:g}")
    mus = np.array([law.mu for law in laws])
    out = Prediction(np.nan, np.nan, float(froude(V, D)))
    exact = np.isclose(mus, mu, rtol=0, atol=1e-9)
    if exact.any():
        use, weights = [laws[int(np.argmax(exact))]], [1.0]
    elif mu < mus[0] or mu > mus[-1]:
        use, weights = [laws[0] if mu < mus[0] else laws[-1]], [1.0]
        out.warnings.append(f"mu = {mu:g} is outside the fitted values {mus.min():g}..{mus.max():g}; "
                            f"using the law for mu = {use[0].mu:g}")
    else:
        i = int(np.searchsorted(mus, mu))
        t = (mu - mus[i - 1]) / (mus[i] - mus[i - 1])
        use, weights = [laws[i - 1], laws[i]], [1.0 - t, t]
        out.notes.append(f"interpolated linearly between mu = {mus[i - 1]:g} and {mus[i]:g}")
    drag = err = 0.0
    for law, wt in zip(use, weights):
        f, e = law.predict(D, h, V)
        drag, err = drag + wt * f, err + wt * e
        for name, value in (("D", D), ("h", h), ("Fr", out.Fr)):
            msg = name in law.ranges and _outside(name, value, law.ranges[name])
            if msg and msg not in out.warnings:
                out.warnings.append(msg)
    out.drag, out.err = drag, err
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m analysis.predict", description=__doc__.split("\n")[0])
    ap.add_argument("--D", type=float, required=True, help="intruder diameter [d]")
    ap.add_argument("--h", type=float, required=True, help="depth of the intruder centre [d]")
    ap.add_argument("--mu", type=float, required=True, help="grain friction coefficient")
    ap.add_argument("--V", type=float, required=True, help="pulling speed [sqrt(g d)]")
    ap.add_argument("--fits", required=True, help="fit file written by analysis.fits.fit_file.save_fits")
    ap.add_argument("--kn", type=float, help="contact stiffness of the law (default: the most fitted)")
    ap.add_argument("--gamman", type=float, help="normal damping of the law")
    ap.add_argument("--json", action="store_true", help="print the result as JSON")
    args = ap.parse_args(argv)
    try:
        laws = load_fits(args.fits).laws
        p = predict(laws, args.D, args.h, args.mu, args.V, args.kn, args.gamman)
    except (FitFileError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    for w in p.warnings:
        print(f"warning: {w}", file=sys.stderr)
    for n in p.notes:
        print(f"note: {n}", file=sys.stderr)
    if args.json:
        print(json.dumps({"drag": p.drag, "err": p.err, "Fr": p.Fr, "warnings": p.warnings}))
    else:
        print(f"F*_drag = {p.drag:.6g} ± {p.err:.2g}  [rho d^3 g]   (Fr = {p.Fr:.4g})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
