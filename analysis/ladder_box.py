"""The ladder's box axis: the drag at one point (K_n, D, Fr and the intruder's depth) in rungs
that differ in the width of the periodic box, and each box's drag against the next narrower
box's. A drag that settles as the box widens has left the finite-size effect behind (the paper's
system I is 40 d wide); one that keeps moving says the rungs are not yet at the paper's box, and
the crossovers fitted to them inherit the difference."""
import math

import numpy as np
import pandas as pd

from .ladder_diagnostics import _drag_series
from .point_errors import pooled_drag_err

BOX_COLUMNS = ["kn", "D", "Fr", "h", "lx", "rung", "drag", "drag_err", "narrower_lx", "ratio", "ratio_err", "z"]
SUMMARY_COLUMNS = ["kn", "D", "lx", "narrower_lx", "fr_lo", "fr_hi", "n_points", "ratio_median", "ratio_min",
                   "ratio_max", "n_beyond_2sigma"]
SAME_DEPTH = 1.0   # d: points further apart in depth are not compared (a rung's h follows its bed)
SPLIT_FR = 4.0     # the summary's ranges: up to regime II's start, and beyond (paper: Fr_2 ≈ 5)


def _series(table, rung):
    """One rung's μ = 0.5 drag-vs-Fr points (the series the crossovers are fitted to,
    ladder_diagnostics._drag_series), with their pooled errors."""
    s, _, kn = _drag_series(table)
    if not len(s) or "lx" not in s.columns:
        return pd.DataFrame(columns=BOX_COLUMNS[:8])
    return pd.DataFrame({"kn": float(kn), "D": s.D.astype(float), "Fr": s.Fr.astype(float),
                         "h": s.h.astype(float), "lx": s.lx.astype(float), "rung": rung,
                         "drag": s.drag.astype(float), "drag_err": pooled_drag_err(s).astype(float)})


def box_axis(tables):
    """tables: {rung: point table}. Every point measured in at least two boxes (the same K_n, D
    and Fr, depths within SAME_DEPTH), one row per box, widest last; each row against the next
    narrower box's: ratio = drag / narrower drag with its error (relative errors in quadrature),
    z = the difference over its error. The narrowest box's row has NaN there."""
    parts = [p for rung, t in tables.items() if len(p := _series(t, rung))]
    if not parts:
        return pd.DataFrame(columns=BOX_COLUMNS)
    points = pd.concat(parts, ignore_index=True)
    rows = []
    for _, g in points.groupby(["kn", "D", np.round(points.Fr, 6)]):
        g = g.sort_values("lx")
        chain = []
        for _, r in g.iterrows():
            narrower = [c for c in chain if c["lx"] < r.lx and abs(c["h"] - r.h) <= SAME_DEPTH]
            row = {**r.to_dict(), "narrower_lx": math.nan, "ratio": math.nan, "ratio_err": math.nan,
                   "z": math.nan}
            if narrower:
                n = max(narrower, key=lambda c: c["lx"])
                row.update(narrower_lx=n["lx"], ratio=r.drag / n["drag"],
                           ratio_err=r.drag / n["drag"] * math.hypot(r.drag_err / r.drag, n["drag_err"] / n["drag"]),
                           z=(r.drag - n["drag"]) / math.hypot(r.drag_err, n["drag_err"]))
            chain.append(row)
        compared = {c["narrower_lx"] for c in chain if np.isfinite(c["ratio"])}
        rows += [c for c in chain if np.isfinite(c["ratio"]) or c["lx"] in compared]
    out = pd.DataFrame(rows, columns=BOX_COLUMNS)
    return out.sort_values(["kn", "D", "lx", "Fr"], ignore_index=True)


def box_summary(box):
    """Per step along the box axis (K_n, D, narrower -> wider box) and Fr range (up to SPLIT_FR,
    and beyond): how many points, their ratios' median and range, and how many differ by more
    than two errors."""
    rows = []
    steps = box[np.isfinite(box.ratio.astype(float))]
    for (kn, D, lx, narrower), g in steps.groupby(["kn", "D", "lx", "narrower_lx"]):
        for lo, hi, part in ((0.0, SPLIT_FR, g[g.Fr <= SPLIT_FR]), (SPLIT_FR, math.inf, g[g.Fr > SPLIT_FR])):
            if not len(part):
                continue
            rows.append({"kn": kn, "D": D, "lx": lx, "narrower_lx": narrower, "fr_lo": lo, "fr_hi": hi,
                         "n_points": len(part), "ratio_median": float(part.ratio.median()),
                         "ratio_min": float(part.ratio.min()), "ratio_max": float(part.ratio.max()),
                         "n_beyond_2sigma": int((part.z.abs() > 2).sum())})
    return pd.DataFrame(rows, columns=SUMMARY_COLUMNS)
