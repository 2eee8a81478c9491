"""Synthetic pull tables that obey the paper's laws with known parameters.

F*_drag = C(mu) h^alpha_mu (D*+1)^phi_mu G(Fr), G three-regime and continuous
with crossovers at Fr = 1 and 5, multiplied by Gaussian noise of relative
size `noise`. theta and kappa follow Eq. 7 and the Fig. 8 line.
"""
import numpy as np
import pandas as pd

from analysis.core.physics import froude, gamman_for, gamman_ratio
from analysis.core.table import YIELD_SPEED
from analysis.fits.regimes import regime_curve

KN, GAMMAN = 2e5, 500.0          # a softer reference law, as a reduced config would use
H_SYSTEM_I = 25.0
FR1, FR2 = 1.0, 5.0


def phi_true(mu):
    return 2.0 - 0.5 * (1.0 - np.exp(-mu / 0.15))


def alpha_true(mu):
    return 3.0 - phi_true(mu)    # the sum rule holds exactly here


def prefactor(mu):
    # Saturates in mu with scale 0.12: 95 % of the rise by mu = 0.36.
    return 0.01 * (1.0 + 3.0 * (1.0 - np.exp(-mu / 0.12)))


def G_params(mu, Fr1=FR1, Fr2=FR2):
    """Continuous three-regime G with G(0+) ~ 1 (explicit-form parameters)."""
    if mu == 0:
        a0, b0, c0, b1, b2 = 0.6, 0.4, 0.6, 0.6, 0.2
    else:
        a0, b0, c0, b1, b2 = 1.0, 0.0, 1.0, 0.3, 0.12
    y1 = a0 + b0 * Fr1 ** c0
    a1 = y1 - b1 * Fr1
    a2 = a1 + b1 * Fr2 - b2 * Fr2 ** 2
    p = dict(a0=a0, a1=a1, b1=b1, a2=a2, b2=b2, Fr1=Fr1, Fr2=Fr2)
    if mu == 0:
        p.update(b0=b0, c0=c0)
    return p


def drag_true(D, h, mu, Fr, **G_kw):
    """Noise-free drag; G_kw may move the crossovers (Fr1=..., Fr2=...)."""
    return (prefactor(mu) * h ** alpha_true(mu) * (D + 1.0) ** phi_true(mu)
            * regime_curve(Fr, **G_params(mu, **G_kw)))


def speed_for(Fr, D):
    return Fr * (D + 1.0) / (2.0 * np.sqrt(2.0 * D))


FR_GRID = np.array([0.1, 0.3, 0.6, 0.8, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 9.0, 10.0])


def make_table(seed=0, noise=0.02, mus=(0.0, 0.1, 0.3, 0.5, 0.9), kn_variants=True,
               crossovers=(FR1, FR2)):
    G_kw = dict(Fr1=crossovers[0], Fr2=crossovers[1])
    rng = np.random.default_rng(seed)
    rows = []

    def add(system, D, h, mu, V, kn=KN, gamman=GAMMAN, tag=""):
        Fr = float(froude(V, D))
        F = drag_true(D, h, mu, Fr, **G_kw) * (1.0 + noise * rng.standard_normal())
        if kn != KN:                      # stiffer contacts: less drag below Fr2 (Fig. 20)
            F *= 1.0 - 0.05 * np.log10(kn / KN) * (Fr < FR2)
        n = 0.5 * (D + 1.0) ** 2 / (1.0 + 0.2 * Fr)
        kappa = 0.887 + 0.185 * Fr + 0.01 * rng.standard_normal()
        rows.append(dict(system=system, D=float(D), h=float(h), mu=float(mu), kn=kn,
                         gamman=gamman, V=float(V), Fr=Fr, drag=F, drag_err=noise * abs(F),
                         n_contacts=n,
                         theta=-0.15 * Fr ** 0.38 + np.pi / 2.45 + 0.005 * rng.standard_normal(),
                         theta_err=0.005,
                         Z=kappa * n * 2 * np.sqrt(3) / (D + 1.0) ** 2, kappa=kappa, kappa_err=0.01,
                         run=f"{system}/mu{mu:g}/D{D:g}/h{h:g}/V{V:.4g}{tag}"))

    for mu in mus:                                   # yield forces, Figs. 12-14
        for D in (1, 2, 3, 4, 5, 6, 8, 10):
            add("I", D, H_SYSTEM_I, mu, YIELD_SPEED)
        for h in (10, 25, 45, 55, 65):               # Figs. 17-18
            add("II", 4, h, mu, YIELD_SPEED)
    for mu in (0.0, 0.5):                            # Figs. 5, 10, 15
        for D in (2, 4, 6):
            for Fr in FR_GRID:
                add("I", D, H_SYSTEM_I, mu, speed_for(Fr, D))
    for mu in (0.1, 0.3):                            # Fig. 11: D = 2, Fr <= 1
        for Fr in FR_GRID[FR_GRID <= 1]:
            add("I", 2, H_SYSTEM_I, mu, speed_for(Fr, 2))
    for h in (25, 45, 65):                           # Figs. 16, 19
        for Fr in FR_GRID:
            add("II", 4, h, 0.5, speed_for(Fr, 4))
    if kn_variants:                                  # Fig. 20 at h = 45
        for kn in (2e6, 2e7):
            for Fr in FR_GRID[::2]:
                add("II", 4, 45, 0.5, speed_for(Fr, 4), kn=kn, gamman=gamman_for(kn, gamman_ratio(KN, GAMMAN)))
        for gn in (GAMMAN / 4, GAMMAN * 4):
            for Fr in FR_GRID[::2]:
                add("II", 4, 45, 0.5, speed_for(Fr, 4), gamman=gn)
    return pd.DataFrame(rows)


def pz_table(table):
    """P(Z) per run of a table: Poisson, the mean coordination falling with speed (as in
    Fig. 7), the last bin holding Z >= 15."""
    from scipy.stats import poisson
    runs = table[["system", "D", "mu", "kn", "gamman", "V", "Fr"]].drop_duplicates()
    z = np.arange(16)
    rows = []
    for r in runs.itertuples(index=False):
        p = poisson.pmf(z, 4.0 / (1 + r.V))
        p[-1] += 1 - p.sum()
        rows += [r._asdict() | {"Z": k, "P": pk} for k, pk in zip(z, p)]
    return pd.DataFrame(rows)


def flow_panels(seed=1):
    """Fig. 9 panels (D, V, snapshot) as the paper's: grains ahead of the intruder carried
    along, the rest at rest (velocities in the intruder's frame, as the run files store them)."""
    rng = np.random.default_rng(seed)
    panels = []
    for D, V in ((2, 0.1), (3, 1.0), (4, 3.0)):
        x, z = rng.uniform(-8, 8, (2, 400))
        ahead = (x > 0) & (np.hypot(x, z) < D)
        snap = pd.DataFrame({"dx": x, "dz": z, "vx": np.where(ahead, 0.0, -V), "vz": 0.1 * V * z / 8})
        panels.append((D, V, snap))
    return panels
