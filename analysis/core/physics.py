"""The engine's formulas that the analysis and the workflow need, each written once here.

Each one is the C++ engine's, not a variant: tests/python/test_physics.py compares them with
`granudrag info`, which prints the engine's own values.

    froude          Froude number of a pull, paper Eq. 4 (src/protocol/pull.cpp)
    froude_speed    the speed of a Froude number (its inverse)
    gamman_for      gamma_n ∝ K_n^0.6: the damping with the paper's restitution curve
                    (ContactParams::with_stiffness, src/contact/contact_params.cpp)
    collision_time  Hertz collision time of two grains (hertz_collision_time)
    default_dt      granudrag's time step when none is given (default_time_step)
    max_dt          the largest time step granudrag accepts (check_time_step)
    default_wake_force  the active region's wake test when a pull leaves it unset
                    (src/engine/active_region.cpp)

Units: lengths in d, speeds in sqrt(g d), times in sqrt(d/g), K_n in rho d g, gamma_n in
sqrt(g/d^3).
"""

import math

import numpy as np

# The paper's contact law (K_n, gamma_n) and its gamma_n / K_n^0.6, which fixes the
# restitution curve e(v_n) (paper Sec. II).
PAPER_KN, PAPER_GAMMAN = 2e8, 5e4
PAPER_RATIO = PAPER_GAMMAN / PAPER_KN**0.6

# The time-step policy (TimeStepPolicy in src/contact/contact_params.hpp): the shortest
# collision is of two of the smallest grains (0.9 d) at the study's fastest speed, and the
# default step resolves it with 64 steps, the largest allowed with 16.
REFERENCE_SPEED = 10.0
STEPS_PER_COLLISION_DEFAULT = 64.0
STEPS_PER_COLLISION_MIN = 16.0
SMALLEST_GRAIN = 0.9

# The contact keys' ranges, as the engine's key table states them (src/contact/contact_keys.cpp;
# tests/python/test_engine_defaults.py compares): key -> (lower bound, exclusive).
CONTACT_RANGES = {"mu": (0.0, False), "kn": (0.0, True), "gamman": (0.0, False)}


def in_contact_range(key, values):
    """Whether each value lies in the contact key's range (CONTACT_RANGES)."""
    low, exclusive = CONTACT_RANGES[key]
    values = np.asarray(values, dtype=float)
    return values > low if exclusive else values >= low


def froude(V, D, d=1.0, g=1.0):
    """Froude number of paper Eq. 4: t2/t1 = 2 V sqrt(2 D / g) / (D + d)."""
    V, D = np.asarray(V, dtype=float), np.asarray(D, dtype=float)
    return 2.0 * V * np.sqrt(2.0 * D / g) / (D + d)


def froude_speed(Fr, D):
    """Speed V of Froude number Fr (paper Eq. 4) for intruder diameter D."""
    return Fr * (D + 1.0) / (2.0 * math.sqrt(2.0 * D))


def active_radius(pull, D):
    """The active region's radius, d, of a pull's settings (a dict of `granudrag pull` keys):
    `active_radius`, or `active_diameters` times the intruder diameter D, as the pull command
    reads them (src/app/command.cpp, pull_active_radius); 0: off."""
    return float(pull.get("active_radius", 0.0) or 0.0) or float(pull.get("active_diameters", 0.0) or 0.0) * D


def default_wake_force(kn):
    """granudrag pull's wake_force when none is given, in grain weights: 0.5 up to K_n = 2e5,
    four times more per decade above (2 at 2e6, 8 at 2e7); why: its C++ twin's comment."""
    kn = float(kn)
    return 0.5 if kn <= 2e5 else 0.5 * 4.0 ** math.log10(kn / 2e5)


def gamman_for(kn, ratio=PAPER_RATIO):
    """gamma_n that keeps gamma_n / K_n^0.6 at ratio (the same restitution curve; by default
    the paper's, as granudrag's default gamma_n for a given K_n)."""
    return ratio * float(kn) ** 0.6


def gamman_ratio(kn, gamman):
    """gamma_n / K_n^0.6: equal ratios, equal restitution curves."""
    return gamman / kn**0.6


def collision_time(kn, diameter=SMALLEST_GRAIN, speed=REFERENCE_SPEED):
    """Duration of an undamped Hertz collision of two grains of this diameter meeting at speed:
    t_c = 2.9432 (5 m_eff / (4 K_n sqrt(R_eff)))^(2/5) v^(-1/5)."""
    r = 0.5 * diameter
    meff, reff = 0.5 * (4.0 / 3.0 * math.pi * r**3), 0.5 * r
    k = float(kn) * math.sqrt(reff)
    return 2.9432 * (5.0 * meff / (4.0 * k)) ** 0.4 * speed**-0.2


def default_dt(kn, diameter=SMALLEST_GRAIN):
    """granudrag's time step when none is given: the shortest collision over 64 (it scales as
    K_n^-0.4; 4.196e-4 at K_n = 2e4, 1.05e-5 at the paper's 2e8)."""
    return collision_time(kn, diameter) / STEPS_PER_COLLISION_DEFAULT


def max_dt(kn, diameter=SMALLEST_GRAIN):
    """The largest time step granudrag accepts: the shortest collision over 16."""
    return collision_time(kn, diameter) / STEPS_PER_COLLISION_MIN
