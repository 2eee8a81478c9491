"""The ladder's axes: the drag at one point (D, Fr and the intruder's depth) in rungs that differ
in one setting, the periodic box's width, the contacts' stiffness K_n or the pull's length, with
the others held, and each rung's drag against the previous one's along the axis.

Along the box: a drag that settles as the box widens has left the finite-size effect behind (the
paper's system I is 40 d wide); one that keeps moving says the rungs are not yet at the paper's
box, and the crossovers fitted to them inherit the difference. Along K_n: the paper finds the
drag of regimes I and II moving with K_n and the crossovers not (Sec. III I), so a ratio that is
the same at every Fr says the curve's shape held while its level moved, and one that changes
across Fr ≈ 4 says the stiffness moved the crossover. Along the pull's length (the paper pulls one
box length, Sec. II): a ratio near 1 says the shorter pull's drag had reached its steady value; one
away from it, a drag that drifts along the pull (a wake that builds, a surface that heaves)."""
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..core.point_errors import pooled_drag_err
from .ladder_diagnostics import _drag_series

POINT_COLUMNS = ["kn", "lx", "distance", "D", "Fr", "h", "rung", "drag", "drag_err"]
COLUMNS = POINT_COLUMNS + ["previous", "ratio", "ratio_err", "z"]
SUMMARY_COLUMNS = ["kn", "lx", "distance", "D", "previous", "fr_lo", "fr_hi", "n_points", "ratio_median", "ratio_min",
                   "ratio_max", "n_beyond_2sigma"]
SAME_DEPTH = 1.0   # d: points further apart in depth are not compared (a rung's h follows its bed)
SPLIT_FR = 4.0     # the summary's ranges: up to regime II's start, and beyond (paper: Fr_2 ≈ 5)


@dataclass(frozen=True)
class Axis:
    """One axis of the ladder: `along` the column that differs between the rungs compared (each
    against the previous value: the narrower box, the softer contacts, the shorter pull), `held`
    the columns that must be equal, `name` the stem of its files (<name>.csv, <name>.png)."""
    along: str
    held: tuple
    name: str
    title: str          # ladder.md's section heading, without "###"


BOX = Axis("lx", ("kn", "distance"), "box_axis", "The drag against the box's width")
STIFFNESS = Axis("kn", ("lx", "distance"), "stiffness_axis", "The drag against the contacts' stiffness")
LENGTH = Axis("distance", ("kn", "lx"), "length_axis", "The drag against the pull's length")
AXES = (BOX, STIFFNESS, LENGTH)
HEADS = {"kn": "K_n", "lx": "box", "distance": "pull"}   # the settings' names in tables and figures
_FORMATS = {"kn": "{:.0e}", "lx": "{:g} d", "distance": "{:g} d"}


def setting(column, value):
    """A setting's value as the tables and figures write it: K_n 2e+06, a box 20 d."""
    return _FORMATS[column].format(value)


def _series(table, rung):
    """One rung's μ = 0.5 drag-vs-Fr points (the series the crossovers are fitted to,
    ladder_diagnostics._drag_series), with their pooled errors; the pull's length is the distance
    travelled rounded to whole d (a pull ends within a step of its target)."""
    s, _, kn = _drag_series(table)
    if not len(s) or not {"lx", "distance"} <= set(s.columns):
        return pd.DataFrame(columns=POINT_COLUMNS)
    return pd.DataFrame({"kn": float(kn), "lx": s.lx.astype(float),
                         "distance": np.round(s.distance.astype(float)), "D": s.D.astype(float),
                         "Fr": s.Fr.astype(float), "h": s.h.astype(float), "rung": rung,
                         "drag": s.drag.astype(float), "drag_err": pooled_drag_err(s).astype(float)})


def independent(tables, extends=None):
    """The rungs of tables that are independent points: a rung another rung of tables extends
    (extends: {rung: the rung it grew in place from}, ladder.yaml) is left out. An extension's
    results directory is a copy of the rung it extends, grown with more pulls or beds, so its
    points hold the other's pulls: counting both would count those pulls twice."""
    grown = {base for rung, base in (extends or {}).items() if base and rung in tables}
    return {rung: t for rung, t in tables.items() if rung not in grown}


def axis_steps(tables, axis, extends=None):
    """tables: {rung: point table}. Every point measured at two or more values of axis.along
    (the same settings axis.held, D and Fr, depths within SAME_DEPTH), one row per value, in order along
    the axis; each row against the previous value's: ratio = drag / previous drag with its error
    (relative errors in quadrature), z = the difference over its error. The first value's row
    has NaN there. extends: {rung: the rung it extends}: only independent rungs count
    (independent), so a rung and its in-place extension are one point at their value."""
    tables = independent(tables, extends)
    parts = [p for rung, t in tables.items() if len(p := _series(t, rung))]
    if not parts:
        return pd.DataFrame(columns=COLUMNS)
    points = pd.concat(parts, ignore_index=True)
    rows = []
    for _, g in points.groupby([*axis.held, "D", np.round(points.Fr, 6)]):
        chain = []
        for _, r in g.sort_values(axis.along).iterrows():
            before = [c for c in chain if c[axis.along] < r[axis.along] and abs(c["h"] - r.h) <= SAME_DEPTH]
            row = {**r.to_dict(), "previous": math.nan, "ratio": math.nan, "ratio_err": math.nan, "z": math.nan}
            if before:
                p = max(before, key=lambda c: c[axis.along])
                row.update(previous=p[axis.along], ratio=r.drag / p["drag"],
                           ratio_err=r.drag / p["drag"] * math.hypot(r.drag_err / r.drag, p["drag_err"] / p["drag"]),
                           z=(r.drag - p["drag"]) / math.hypot(r.drag_err, p["drag_err"]))
            chain.append(row)
        compared = {c["previous"] for c in chain if np.isfinite(c["ratio"])}
        rows += [c for c in chain if np.isfinite(c["ratio"]) or c[axis.along] in compared]
    out = pd.DataFrame(rows, columns=COLUMNS)
    return out.sort_values([*axis.held, "D", axis.along, "Fr"], ignore_index=True)


def axis_summary(steps, axis):
    """Per step along the axis (the held settings, D, previous -> next value) and Fr range (up to
    SPLIT_FR, and beyond): how many points, their ratios' median and range, and how many differ
    by more than two errors."""
    rows = []
    done = steps[np.isfinite(steps.ratio.astype(float))]
    for (*held, D, value, previous), g in done.groupby([*axis.held, "D", axis.along, "previous"]):
        for lo, hi, part in ((0.0, SPLIT_FR, g[g.Fr <= SPLIT_FR]), (SPLIT_FR, math.inf, g[g.Fr > SPLIT_FR])):
            if not len(part):
                continue
            rows.append({**dict(zip(axis.held, held)), axis.along: value, "D": D, "previous": previous, "fr_lo": lo,
                         "fr_hi": hi, "n_points": len(part), "ratio_median": float(part.ratio.median()),
                         "ratio_min": float(part.ratio.min()), "ratio_max": float(part.ratio.max()),
                         "n_beyond_2sigma": int((part.z.abs() > 2).sum())})
    return pd.DataFrame(rows, columns=SUMMARY_COLUMNS)


def box_axis(tables, extends=None):
    """The box axis: each box's drag against the next narrower box's (axis_steps along lx)."""
    return axis_steps(tables, BOX, extends)


def stiffness_axis(tables, extends=None):
    """The stiffness axis: each K_n's drag against the next softer rung's, in the same box."""
    return axis_steps(tables, STIFFNESS, extends)


def length_axis(tables, extends=None):
    """The pull-length axis: each pull's drag against the next shorter pull's, same box and K_n."""
    return axis_steps(tables, LENGTH, extends)
