"""What the active region saves a pull (`granudrag pull --active_radius R`): a cost model from
measured sleeping fractions.

A pull with the region integrates every grain within R of the intruder and every grain that has
not come to rest; a grain asleep still costs a little (its contacts with awake grains, the
lists, the checks). A pull's expected cost is then its particle-steps (cost.pull_cost) times

    factor = 1 + overhead - (1 - c) * asleep,
    asleep = share(Fr, mu) * outside(R) * reach(R) * max(0, 1 - sleep_time / T),

where outside(R) is the fraction of the bed's grains farther than R from the intruder (a sphere
of radius R about it, cut by the bed's surface and base), T = travel / V the pull's duration (no
grain falls asleep before it has rested sleep_time), and share(Fr, mu) the fraction of those
grains that do fall asleep, measured: the intruder's disturbance reaches farther the faster it
goes, and a frictionless bed hardly comes to rest; c is what a sleeping grain still costs
(sleeping_cost: less in a bed poured with settling damping, at rest), reach(R) the part of the
grains beyond R that also lie beyond REACH of the intruder against the same in the bed the shares
were measured in (reach_factor), and overhead the region's bookkeeping (REGION_OVERHEAD); in
cost.region_factor, which scales both the pull's steps and the CPU model's per-time term
(cost.pull_work). The scheduler's limits (cost.job_resources) keep the whole cost: a
pull through a bed that does not sleep must not be killed for it.
"""

import functools
import math

import numpy as np

from analysis.core.physics import active_radius, default_wake_force, froude

from .config import SETTLE_DAMPING_DEFAULT, pour_settings

# Grains per d^3 in a poured bed: a packing fraction of 0.6 of grains 0.9-1.1 d in diameter
# (mean volume pi/6 <d^3> = 0.529 d^3); only the depth of the bed below the intruder comes from
# it, and the estimate is no finer than that.
GRAINS_PER_VOLUME = 1.13

# The region's settings when a config gives none: granudrag pull's defaults (its --help; its
# wake_force follows K_n: analysis.core.physics.default_wake_force).
SLEEP_TIME_DEFAULT = 1.0
WAKE_LOAD_DEFAULT = 0.0   # off

# share(Fr, mu): of the grains outside the region, the fraction asleep on average once the first
# sleep_time has passed, per friction at these Froude numbers (linear in log Fr between them,
# constant beyond; linear in mu between the measured frictions, constant beyond). Measured with
# `estimate_cost.py --asleep-from RUNS.csv` on the active region's validation runs at the default
# rest test (sleep_speed 0.003 V, at most sleep_speed_max), in the 40 d x 40 d box. A bed poured
# with settle_damping is at rest, and more of it sleeps (ASLEEP_SHARE_DAMPED) than of the paper's
# pour (ASLEEP_SHARE). The paper's pour:
#  config/validate/active_region_40_d6.yaml (D = 6, R = 18 d, 5 beds): mu = 0.5 0.505 in the yield
#    pull (V = 0.03, Fr 0.03), 0.365 at Fr = 1; mu = 0 2e-5 and 0.042 (a frictionless bed creeps
#    faster than 0.3 % of V). The rest test of before (0.01) held 1.4-1.8x as many at mu = 0.5
#    (0.68-0.70 for D = 2 and 6 in active_region_40_quick.yaml) and 7x at mu = 0, Fr = 1.
#  Fr = 5 and 10, config/validate/active_region_40_fast.yaml (R = 3 D, D = 2 and 6, 5 beds, 30 and
#    40 d of travel; the mean over both D, whose shares differ 3-20x: D = 6's region is most of the
#    box): mu = 0.5 0.24 and 0.052, mu = 0 0.067 and 0.008 (above V = 4.7 sleep_speed_max sets the
#    rest test, so only D = 2 at Fr = 5 was re-measured at 0.003: 0.418 and 0.126).
ASLEEP_SHARE = {
    0.0: ((0.03, 0.00002), (1.0, 0.042), (5.0, 0.067), (10.0, 0.008)),
    0.5: ((0.03, 0.50), (1.0, 0.37), (5.0, 0.24), (10.0, 0.052)),
}


def asleep_share(Fr, mu, table=None):
    """share(Fr, mu): in the measured table (default ASLEEP_SHARE, as it is at the call:
    estimate_cost.py --asleep-from replaces it; {mu: ((Fr, share), ...)}), interpolated linearly in
    log Fr at each friction and then linearly in mu, constant beyond the measured points."""
    table = table or ASLEEP_SHARE
    frictions = sorted(table)
    at = [float(np.interp(math.log(max(float(Fr), 1e-12)), np.log([f for f, _ in table[m]]),
                          [s for _, s in table[m]])) for m in frictions]
    return float(np.interp(float(mu), frictions, at))


def _paper_pour_at_speed(mu):
    """The paper's pour's shares at Fr = 5 and 10 at this friction, which damped beds take."""
    return tuple((Fr, asleep_share(Fr, mu, ASLEEP_SHARE)) for Fr in (5.0, 10.0))


# Beds poured with settle_damping 1, R = 3 D, the default rest test (sleep_speed 0.003):
#  mu = 0.25 and 0.8, config/validate/active_region_40_mu.yaml (D = 2, 4 beds): 0.823 in the
#    mu = 0.25 yield pull (V = 0.03, Fr 0.04), 0.762 at Fr = 1; 0.650 in the mu = 0.8 yield pull
#    (V = 0.1, Fr 0.13), 0.650 at Fr = 1.
#  mu = 0.5: active_region_40_long.yaml (D = 2, 5 d at V = 0.03, 5 beds) 0.774;
#    active_region_40_sizes.yaml (D = 1 and 4, 4 beds, V = 0.1) 0.790 and 0.664 in the yield
#    pulls (Fr 0.14 and 0.11), 0.779 and 0.650 at Fr = 1: 0.77 and 0.71 are taken.
#  The rest test of before, 0.01, held 5-20 % more (0.80-0.89 at Fr <= 1), and read the drag high.
#  mu = 0 (a frictionless bed creeps, damped or not), and every friction at Fr = 5 and 10 (where
#    sleep_speed_max sets the rest test): not measured in damped beds; the paper's pour's shares
#    are taken (the lower of what is known).
#  All of these at K_n = 2e4; for stiffer beds see STIFF_SHARE_RATIO below.
ASLEEP_SHARE_DAMPED = {
    0.0: ASLEEP_SHARE[0.0],
    0.25: ((0.04, 0.823), (1.0, 0.762), *_paper_pour_at_speed(0.25)),
    0.5: ((0.04, 0.77), (1.0, 0.71), *_paper_pour_at_speed(0.5)),
    0.8: ((0.13, 0.650), (1.0, 0.650), *_paper_pour_at_speed(0.8)),
}

# A grain asleep costs this fraction of an awake one: c = 1 - (1 - t_region / t_without) / asleep.
# In beds poured without settling damping (the paper's pour), measured from the CPU times of the
# 40 d validation's yield pulls, each against the same bed's pull without the region (Snakemake's
# benchmark files, 1 thread): median 0.22 over the 8 pairs (0.10-0.18 for D = 2, 0.26-0.41 for
# D = 6, whose wider disturbance leaves more sleeping grains with an awake partner); in a bed
# still creeping (the 70,001-body bed of docs/log/benchmark.md, settled to 1e-4 only) awake grains are
# scattered through the sleeping ones and c was 0.49. What a sleeping grain still costs: the scan
# of its pairs when a partner is awake, and the integration's, lists' and checks' passes over
# every body. In beds poured with settle_damping, at rest, a held grain none of whose partners is
# awake is quiet and costs nothing until a list build (docs/pour-and-pull.md): c was 0.03 over the
# second half of a yield pull through a 70,001-body bed (docs/log/benchmark.md), and over whole yield
# pulls through the 40 d beds (D = 2, R = 3 and 6 D) median -0.01 over 10 pairs (-0.04 to +0.05;
# active_region_40_long.yaml, 5 d at V = 0.03, 69-84 % asleep, 3.0-7.6x faster) and -0.04 over 8
# (-0.21 to +0.00; active_region_40_mu.yaml, mu = 0.25 and 0.8, 72-84 % asleep, 5.0-7.7x): the
# bench's 0.03 is taken. (Their Fr = 1 pulls, 10-23 s each, are too short to time.)
SLEEPING_COST = 0.22
SLEEPING_COST_DAMPED = 0.03

# Stiffness. The tables above hold at K_n = 2e5 too (Fr = 1, R = 3 and 5 D: shares 0.72 and 0.78
# against 0.71 at 2e4; active_region_40_kn_radius.yaml). At config/faithful.yaml's 2e6 a wake test
# fixed in units of a grain's weight wakes far more grains (the force of a given creep grows as
# K_n^(2/3)): at wake_force 0.5, the soft beds' default, the pulls of active_region_30_stiff.yaml
# saved no CPU (0.32 and 0.37 asleep, woken as fast as they slept). At wake_force 2, the engine's
# default at 2e6 (analysis.core.physics.default_wake_force), a share STIFF_SHARE_RATIO of the table's
# sleeps, and a sleeping grain costs STIFF_SLEEPING_COST (woken and put back to sleep more often),
# both measured on D = 2, mu = 0.5, 30 d x 30 d damped beds at 2e6:
#  active_region_30_stiff.yaml (Fr = 1, 7 d deep, 4 beds): shares 0.48 and 0.56 at R = 3 and 5 D
#    against the table's 0.71 (0.68 and 0.79 of it); CPU per pull 1.7x less, c about 0 (short
#    pulls, 45 s against 75 s);
#  active_region_30_stiff_deep.yaml (the yield pull, V = 0.1 over 2 d, 24 d deep, 3 beds): shares
#    0.55 and 0.60 at 3 and 5 D against the table's 0.77 (0.71 and 0.78 of it); CPU per pull, each
#    against the mean of its bed's pull and replica, 1.20-1.50x less (median 1.37x over the 6
#    pairs; 51 % and 50 % asleep: c about 0.5), a sleeping grain's cost being its wake-ups.
# STIFF_SHARE_RATIO is these four ratios' middle (0.745), rounded; STIFF_SLEEPING_COST the yield
# pull's (most of a study's cost). Both held over a yield pull of faithful.yaml's length (5 d at
# V = 0.1 through one of the deep study's beds, docs/log/benchmark.md, 2026-11-28): 0.82 of the table's
# share asleep, a sleeping grain 0.48 of an awake one, the pull 1.38x cheaper in CPU; at twice the
# default wake test (4) 0.30 and 1.81x, not priced here (not the default).
# Half the dwell (sleep_time 0.5, faithful.yaml's) puts a grain woken for a load it only carries
# back to sleep twice as soon, which a stiff bed, woken often, feels: in the same 5 d yield pull
# 1.2x as many asleep (0.99 of the table's share) and a sleeping grain 0.27 of an awake one (1.86x
# cheaper in CPU); over the deep study's 4 beds (2 d) 1.22x as many (61 % against 50 %) and 0.28
# (CPU 553 s against 816 s, the reference 983 s), 0.95 of the table's share (0.78 x 1.22).
# STIFF_AT_DWELL keeps (share ratio, sleeping cost) per dwell, at 0.5 the lower ratio and the
# rounded cost, linear in sleep_time between and constant beyond; at the tables' stiffness the
# halved dwell slept 1.0-1.16x as much and saved no measurable CPU (active_region_40_deep.yaml,
# 40_kn_radius.yaml: docs/study-outcomes.md), so only the stiff end moves.
# Between 2e5 and 2e6 both are interpolated in log K_n; beyond 2e6 (faithful.yaml's kappa_stiff
# sweep at 2e7, pulls at speed, which sleep little anyway) 2e6's are taken: at 2e7, with the
# default wake test (8), a Fr = 1 pull slept 0.76 of what the geometry allows, 1.07 of the table's
# share (active_region_30_stiffer.yaml, 2 beds), so they err low there. A pull
# whose wake test is more sensitive than the engine's default at its K_n is priced as saving
# nothing there, as measured at 0.5 at 2e6.
KN_TABLES = 2e5
KN_STIFF = 2e6
STIFF_SHARE_RATIO = 0.75
STIFF_SLEEPING_COST = 0.5
STIFF_AT_DWELL = {0.5: (0.95, 0.3), SLEEP_TIME_DEFAULT: (STIFF_SHARE_RATIO, STIFF_SLEEPING_COST)}
# The wake test relative to the load (`wake_load` f: a held grain wakes only when its force moves
# by f times its mean contact force, if that is more than wake_force m g) puts back to sleep less
# of what a stiff bed's ripples wake. Measured at KN_STIFF and the halved dwell, f = 0.1, beside
# R5D_sleep05 on the same beds (active_region_30_stiff_deep.yaml, the deep yield pull, 4 beds:
# 61.5 % asleep against 60.6 %, CPU 393-540 s (mean 450) against 523-634 s (555), the reference
# 873-1,105 s (983)): WAKE_LOAD_EFFECT holds (share with / share without, sleeping cost with /
# cost without) there, c = 1 - (1 - t_region / t_reference) / asleep from the pulls' CPU times
# (0.12 against 0.28). At Fr = 1 (5 d, 7 d deep; active_region_30_stiff.yaml, 4 beds) it saved
# nothing measurable (44 % asleep with and without, 48-64 s against 47-68 s), so pricing every
# pull with it errs low there, where pulls cost little. Priced as factors on stiff_at_dwell's
# figures at any dwell, linear in f up to WAKE_LOAD_MEASURED and constant beyond (0.25 slept more
# and cost less, but read the drag high: not priced).
WAKE_LOAD_MEASURED = 0.1
WAKE_LOAD_EFFECT = (1.015, 0.42)


def stiff_at_dwell(sleep_time, wake_load=0.0):
    """(share ratio, sleeping cost) of a bed at KN_STIFF for this dwell (STIFF_AT_DWELL) and wake
    test relative to the load (WAKE_LOAD_EFFECT)."""
    dwells = sorted(STIFF_AT_DWELL)
    ratio, cost = (float(np.interp(float(sleep_time), dwells, [STIFF_AT_DWELL[t][k] for t in dwells]))
                   for k in (0, 1))
    t = min(1.0, max(0.0, float(wake_load)) / WAKE_LOAD_MEASURED)
    return (ratio * (1 + t * (WAKE_LOAD_EFFECT[0] - 1)), cost * (1 + t * (WAKE_LOAD_EFFECT[1] - 1)))


def stiffness(kn):
    """How far a bed of this K_n is from the tables' stiffness toward KN_STIFF's: 0 up to
    KN_TABLES, 1 from KN_STIFF on, linear in log K_n between."""
    t = math.log(float(kn) / KN_TABLES) / math.log(KN_STIFF / KN_TABLES)
    return min(1.0, max(0.0, t))


def stiff_share_factor(kn, wake_force, sleep_time=SLEEP_TIME_DEFAULT, wake_load=0.0):
    """The fraction of the tables' sleeping share that sleeps in a bed of this K_n at this
    wake_force, dwell and wake_load: 1 at the tables' stiffness; at KN_STIFF, the share ratio of
    stiff_at_dwell with a wake test at least the engine's default for the K_n, 0 with a more
    sensitive one (the stiff grains woken as fast as they sleep)."""
    sensitive = float(wake_force) < default_wake_force(kn) * (1 - 1e-9)
    at_stiff = 0.0 if sensitive else stiff_at_dwell(sleep_time, wake_load)[0]
    return 1.0 - stiffness(kn) * (1.0 - at_stiff)


def _given(value, default):
    """A setting as a config or a runs.csv gives it, `default` when unset (None in a config, NaN
    in a runs.csv)."""
    return default if value is None or value != value else float(value)


def _wake_force(value, kn):
    """A pull's wake_force as a config or a runs.csv gives it: the engine's default at the bed's
    K_n when unset."""
    return _given(value, default_wake_force(kn))


def damped_bed(pull, config):
    """Whether the pull's bed was poured with settling damping (at rest: more of it sleeps, and a
    sleeping grain costs less)."""
    pour = pour_settings(config, pull.bed.system)
    return float(pour.get("settle_damping", SETTLE_DAMPING_DEFAULT) or 0.0) > 0


def _sleep_time(value):
    """A pull's dwell as a config or a runs.csv gives it: SLEEP_TIME_DEFAULT when unset."""
    return _given(value, SLEEP_TIME_DEFAULT)


def _wake_load(value):
    """A pull's wake_load as a config or a runs.csv gives it: 0 (off, the engine's default) when unset."""
    return _given(value, WAKE_LOAD_DEFAULT)


# The bound (`estimate_cost.py --region-bound`): every grain outside R asleep from the first step
# and costing nothing, frictionless beds too: the most any active region of that radius can save.
BOUND = False


def sleeping_cost(pull, config):
    """What a sleeping grain costs in this pull's bed: SLEEPING_COST_DAMPED if it was poured with
    settling damping, else SLEEPING_COST, moved toward the stiff bed's at the pull's dwell
    and wake_load (stiff_at_dwell) by the bed's stiffness; 0 under BOUND."""
    if BOUND:
        return 0.0
    base = SLEEPING_COST_DAMPED if damped_bed(pull, config) else SLEEPING_COST
    settings = pull.settings_in(config)
    at_stiff = stiff_at_dwell(_sleep_time(settings.get("sleep_time")), _wake_load(settings.get("wake_load")))[1]
    return base + stiffness(pull.bed.value("kn")) * (at_stiff - base)


def bed_height(grains, lx, ly):
    """The height of a bed of this many grains, d (GRAINS_PER_VOLUME)."""
    return grains / (GRAINS_PER_VOLUME * lx * ly)


def outside_fraction(radius, lx, ly, grains, depth):
    """Fraction of a bed's grains farther than `radius` from an intruder at `depth` (d below the
    surface): one minus the volume of the sphere of that radius inside the bed (cut by the
    surface and the base, at most the bed) over the bed's."""
    height = bed_height(grains, lx, ly)
    r = float(radius)

    def cap(t):  # volume of a cap of height t cut from the sphere
        t = min(max(t, 0.0), 2 * r)
        return math.pi * t * t * (3 * r - t) / 3.0

    inside = 4.0 / 3.0 * math.pi * r**3 - cap(r - depth) - cap(r - (height - depth))
    return max(0.0, 1.0 - inside / (lx * ly * height))


# What the region's bookkeeping costs a pull whose grains do not sleep, as a share of the pull
# without it: in bench/region_map.sh's 10 d box (no grain asleep) the pulls with the region cost
# 1.02-1.05x those without it over four speeds, 3 rounds each (2026-12-05, the beds below).
REGION_OVERHEAD = 0.03


def overhead(pull, config):
    """REGION_OVERHEAD for a pull with the region on (0 without it, and under BOUND)."""
    if BOUND:
        return 0.0
    return REGION_OVERHEAD if active_radius(pull.settings_in(config), pull.bed.value("D")) > 0 else 0.0

# The tables' shares were measured in 40 d x 40 d beds of 25,600 grains, 7 d deep (the
# calibration bed). Grains nearer the intruder than REACH stay disturbed whatever R is, and in a
# narrow, shallow bed that is most of it: bench/region_map.sh (2026-12-05, K_n = 2e4, mu = 0.5,
# damped beds of 16 grains per d^2 of floor, D = 2 held 7 d deep, R = 3 D = 6 d, one thread;
# docs/pour-and-pull.md) saved, over the tables' share, nothing in the 10 d box (the region
# costs 2-5 %), 0.14 of it in the yield pull and none at Fr >= 1 in the 20 d box, 0.82-0.95 in the
# 40 d box. So the share, a share of the grains beyond R, is scaled by the part of those grains
# that also lie beyond REACH of the intruder (its periodic images included) in the pull's bed,
# over the same part in the calibration bed, at most 1 and 1 from R >= REACH (reach_factor):
# REACH = 12 d gives the 20 d box's 0.15 and the 10 d box's 0, and leaves the deep beds of
# 30-40 d boxes (the 70,000- and 39,375-grain beds that saved 1.2-3.3x) at 1.
REACH = 12.0
CALIBRATION_BED = (40.0, 40.0, 25600, 7.0)   # lx, ly, grains, depth


@functools.lru_cache(maxsize=4096)
def outside_in_box(radius, lx, ly, grains, depth, n=48):
    """Fraction of the bed's grains farther than `radius` from the intruder and its periodic
    images in x and y (a grid of n^3 points over the bed; the centred box is each point's nearest
    image), cut by the surface and the base as outside_fraction."""
    height = bed_height(grains, lx, ly)
    x = ((np.arange(n) + 0.5) / n - 0.5) * lx
    y = ((np.arange(n) + 0.5) / n - 0.5) * ly
    z = (np.arange(n) + 0.5) / n * height - (height - depth)
    X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
    return float(np.mean(X**2 + Y**2 + Z**2 > radius * radius))


def reach_factor(radius, lx, ly, grains, depth):
    """The fraction of the tables' sleeping share that sleeps in this bed (REACH,
    CALIBRATION_BED): of the grains beyond `radius`, the share also beyond REACH here, over the
    same in the calibration bed (the share is of the grains beyond the radius, so the bed's
    geometry enters once, through outside_fraction). 1 from radius >= REACH."""
    r = max(float(radius), REACH)
    if r <= radius:
        return 1.0

    def beyond_reach(bed):
        outside = outside_in_box(float(radius), *bed)
        return outside_in_box(r, *bed) / outside if outside > 0 else 0.0

    ref = beyond_reach(CALIBRATION_BED)
    if ref <= 0:
        return 1.0
    return min(1.0, beyond_reach((float(lx), float(ly), int(grains), float(depth))) / ref)


def asleep_fraction(pull, config, travel, table=None):
    """The expected mean fraction of the bed's grains asleep over a pull of `travel` d (0 without
    the region), with the shares of `table` (default: ASLEEP_SHARE_DAMPED for a bed poured with
    settling damping, else ASLEEP_SHARE, as they are at the call); under BOUND every grain
    outside the region."""
    sysc, settings = config["systems"][pull.bed.system], pull.settings_in(config)
    D = pull.bed.value("D")
    radius = active_radius(settings, D)
    if radius <= 0:
        return 0.0
    lx, ly, grains = float(sysc["lx"]), float(sysc["ly"]), int(sysc["grains"])
    pos = pull.bed.value("pos")
    depth = pos if pull.bed.place == "h" else bed_height(grains, lx, ly) - pos
    outside = outside_fraction(radius, lx, ly, grains, depth)
    if BOUND:
        return outside
    rest, duration = _sleep_time(settings.get("sleep_time")), travel / pull.V
    table = table or (ASLEEP_SHARE_DAMPED if damped_bed(pull, config) else ASLEEP_SHARE)
    share = asleep_share(float(froude(pull.V, D)), pull.bed.value("mu"), table)
    kn = pull.bed.value("kn")
    share *= stiff_share_factor(kn, _wake_force(settings.get("wake_force"), kn), rest,
                                _wake_load(settings.get("wake_load")))
    reach = reach_factor(radius, lx, ly, grains, depth)
    return share * outside * reach * max(0.0, 1.0 - rest / duration)


def measured_shares(runs):
    """share(Fr, mu) from runs with the region (a runs.csv of the validation: its asleep,
    active_radius, lx, ly, grains, h, distance, V, mu and D columns, and kn, wake_force,
    sleep_time and wake_load where it has them): per run, the asleep fraction over what the
    geometry, the bed's reach (reach_factor), the duration and the stiffness allow (the defaults for a table without the
    settings), so that pricing a pull of another stiffness applies its own; the median per friction and Froude number. A
    stiff run whose wake test woke its grains as fast as they slept (stiff_share_factor 0) says
    nothing about the table and is left out. Returns {mu: ((Fr, share), ...)}."""
    rows = runs[(runs.active_radius > 0) & runs.asleep.notna()]
    if rows.empty:
        raise ValueError("no pull with an active region (active_radius > 0) and a recorded asleep fraction")
    shares = {}
    for r in rows.itertuples():
        kn = getattr(r, "kn", KN_TABLES)
        rest = _sleep_time(getattr(r, "sleep_time", None))
        stiff = stiff_share_factor(kn, _wake_force(getattr(r, "wake_force", None), kn), rest,
                                   _wake_load(getattr(r, "wake_load", None)))
        allowed = outside_fraction(r.active_radius, r.lx, r.ly, r.grains, r.h) * max(
            0.0, 1.0 - rest * r.V / r.distance) * stiff * reach_factor(r.active_radius, r.lx, r.ly, r.grains, r.h)
        if allowed > 0:
            key = (round(float(r.mu), 3), round(float(r.Fr), 3))
            shares.setdefault(key, []).append(min(1.0, r.asleep / allowed))
    table = {}
    for (mu, fr), v in sorted(shares.items()):
        table.setdefault(mu, []).append((fr, float(np.median(v))))
    return {mu: tuple(points) for mu, points in table.items()}
