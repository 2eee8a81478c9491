"""The answers of the validation studies that compare beds made two ways, each point's drag the
mean over its beds with the bed scatter in its error (not paired: the beds differ): the settling
damping's (granudrag pour --settle_damping) and placement's (granudrag place, an intruder put
into a settled column, against the paper's pour with the intruder in place)."""

import numpy as np


def settle_damping_answer(cmp):
    ok = [f"{v:g}" for v, g in cmp.groupby("variant") if g.agrees.all()]
    return ("Settling damping whose beds give the paper's pour's drag at every point: "
            + (", ".join(ok) if ok else "none") + ".")


def _point(row):
    """"D = 4, h = 25, mu = 0, Fr = 0.05" of a comparison row (the keys it has)."""
    parts = []
    for key, name in (("D", "D"), ("h_requested", "h"), ("z_requested", "z"), ("mu", "mu"), ("kn", "K_n"),
                      ("Fr", "Fr")):
        value = row.get(key, np.nan)
        if isinstance(value, (int, float)) and np.isfinite(value):
            parts.append(f"{name} = {value:g}")
    return ", ".join(parts)


def placement_answer(cmp):
    """Whether placed beds pull as poured ones at every point, and where they do not: each miss
    with its relative difference and z."""
    misses = cmp[~cmp.agrees.astype(bool)]
    if misses.empty:
        return (f"Beds placed into a settled column pull as beds poured with the intruder in place (the "
                f"paper's protocol) at every point ({len(cmp)} point{'s' * (len(cmp) != 1)}, largest |z| "
                f"{np.abs(cmp.z).max():.2g}).")
    where = "; ".join(f"{_point(r)}: {100 * r['rel_diff']:+.1f} ± {100 * r['rel_diff_err']:.1f} % (z = {r['z']:.2g})"
                      for _, r in misses.iterrows())
    return (f"Placed beds disagree with the paper's pour (|z| >= 2) at {len(misses)} of {len(cmp)} points: "
            f"{where}.")
