"""Numbers published by Kumar et al. 2022, which the report compares against.

The paper gives no error bars; "approximately" values are stored as printed.
"""
from .physics import PAPER_KN

CROSSOVER_FR1 = 1.0     # quasistatic -> linear (Secs. III A, III G, III I)
CROSSOVER_FR2 = 5.0     # linear -> quadratic

# Eq. 7: theta = U1 Fr^U2 + pi/U3
THETA = {"U1": -0.15, "U2": 0.38, "U3": 2.45}
# Fig. 8: kappa = k0 + k1 Fr
KAPPA = {"k0": 0.887, "k1": 0.185}

# Table I: mu = 0, regime I fitted by a'' + b'' Fr^c'' for each D/d.
TABLE1 = {
    1: (17.294, 102.832, 0.220),
    2: (182.943, 104.124, 0.773),
    3: (304.399, 192.047, 0.662),
    4: (442.263, 312.832, 0.591),
    5: (663.476, 358.956, 0.728),
    6: (802.574, 584.300, 0.549),
}

PHI_0 = 2.0             # phi at mu = 0 (Sec. III E: cross-section argument)
ALPHA_0 = 1.0           # alpha at mu = 0 (Sec. III H: hydrostatic pressure)
SUM_RULE = 3.0          # alpha_mu + phi_mu (Sec. III G, Eq. 12)
DEEP_H = 45.0           # the depth (d) from which Eq. 12's collapse holds, h >~ 45 d (Sec. III H)
# How far below a depth cut (DEEP_H, a config's report.h_min) a measured depth still counts as at
# it, d: the cut is one of the paper's sampled depths, and an intruder placed there sits 0.02 d
# above it once its neighbourhood has settled (granudrag place), a poured one a few hundredths off
# its request. A grain's tenth keeps them in and no other sampled depth (10 d apart) near the cut.
DEPTH_SLACK = 0.1


def at_least(h, h_min):
    """Whether depths h (a number, array or Series, d) count as h >= h_min, within DEPTH_SLACK."""
    return h >= h_min - DEPTH_SLACK

# The paper's scale (Sec. II): box lx x ly (d), grains, K_n; pulls over one box length.
SYSTEMS = {"I": (40.0, 40.0, 70000), "II": (80.0, 40.0, 300000)}
KN = PAPER_KN           # declared with the paper's gamma_n in analysis.core.physics
