"""The drag along a pull: the mean of -F_x in windows of travel, and the drag of a pull's late part.

The table's drag is the mean after a discarded transient (min(D + d, travel/4) of travel). That
assumes the start of a pull, where the intruder set going at V from rest in a packed bed meets
more resistance, has died out by then. This module shows where it has: each pull's drag in
consecutive windows of travel (`windows`), and the drag from a later travel on (`late_drag`)
beside the table's, per D and Fr combined over the beds (`compare`). A late drag below the
table's by more than its error says the discarded transient was too short at that speed.

    python -m analysis.drag_profile RUNS.csv [--window 2] [--late 8] [--output-dir DIR]

RUNS.csv is a study's runs.csv (its `path` column names each run file). Writes
DIR/drag_profile.csv (one row per run and window) and DIR/drag_late.csv (one row per D and Fr),
and prints the comparison.
"""
import argparse
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from .core.table import bed_mean, write_csv
from .validation.pull_length import read_convergence

PROFILE_COLUMNS = ["D", "Fr", "seed", "x_lo", "x_hi", "drag", "samples"]
LATE_COLUMNS = ["D", "Fr", "beds", "travel", "transient", "drag", "drag_err", "late_from", "late_drag",
                "late_err", "ratio", "z"]


def windows(travel, drag, width):
    """The mean drag in consecutive windows [k w, (k + 1) w) of travel from 0 (a sample's travel
    is the end of its interval, so the first window holds the samples up to w); only whole
    windows. Returns a DataFrame of x_lo, x_hi, drag, samples."""
    travel, drag = np.asarray(travel, float), np.asarray(drag, float)
    n = int(math.floor(travel[-1] / width + 1e-9)) if len(travel) else 0
    rows = []
    for k in range(n):
        inside = (travel > k * width) & (travel <= (k + 1) * width + 1e-9)
        if inside.any():
            rows.append({"x_lo": k * width, "x_hi": (k + 1) * width, "drag": float(drag[inside].mean()),
                         "samples": int(inside.sum())})
    return pd.DataFrame(rows, columns=["x_lo", "x_hi", "drag", "samples"])


def late_drag(travel, drag, start, width):
    """(mean drag of the samples after `start` of travel, its error): the error from the scatter of
    the means of windows `width` wide (batch means; windows as long as the force's correlations
    make them independent), NaN with fewer than two windows."""
    travel, drag = np.asarray(travel, float), np.asarray(drag, float)
    keep = travel > start
    w = windows(travel[keep] - start, drag[keep], width)
    mean = float(drag[keep].mean()) if keep.any() else math.nan
    err = float(w.drag.std(ddof=1) / math.sqrt(len(w))) if len(w) >= 2 else math.nan
    return mean, err


def read_series(runs):
    """Each run's force series (read_convergence's: travel, drag, transient), in the runs' order."""
    return [read_convergence(path)[1] for path in runs.path]


def profiles(runs, width=2.0, series=None):
    """Every run of a runs.csv table (path, D, Fr, seed): its windows of travel. series: the
    runs' read_series, when already read."""
    series = read_series(runs) if series is None else series
    parts = [windows(sr["travel"], sr["drag"], width).assign(D=float(r.D), Fr=float(r.Fr), seed=int(r.seed))
             for (_, r), sr in zip(runs.iterrows(), series)]
    return pd.concat(parts, ignore_index=True)[PROFILE_COLUMNS] if parts else pd.DataFrame(columns=PROFILE_COLUMNS)


def compare(runs, late_from=8.0, width=2.0, series=None):
    """Per D and Fr, over the beds (bed_mean, the point table's rule): the table's drag (runs.csv's
    drag and drag_err, after the run's transient) against the drag after `late_from` of travel;
    ratio late / table and z = (late - table) / hypot(errors). series: as in profiles. A pull too
    short for its late part's error counts with none."""
    series = read_series(runs) if series is None else series
    runs = runs.reset_index(drop=True)
    rows = []
    for (D, Fr), g in runs.groupby(["D", "Fr"]):
        mine = [series[i] for i in g.index]
        late = [late_drag(sr["travel"], sr["drag"], late_from, width) for sr in mine]
        table, table_err = bed_mean(g.drag, g.drag_err)
        m, e = bed_mean([v for v, _ in late], np.nan_to_num([err for _, err in late]))
        rows.append({"D": D, "Fr": Fr, "beds": len(g), "travel": float(np.mean([sr["travel"][-1] for sr in mine])),
                     "transient": float(np.mean([sr["transient"] for sr in mine])), "drag": table,
                     "drag_err": table_err, "late_from": late_from, "late_drag": m, "late_err": e,
                     "ratio": m / table, "z": (m - table) / math.hypot(e, table_err)})
    return pd.DataFrame(rows, columns=LATE_COLUMNS)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m analysis.drag_profile", description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", help="a study's runs.csv (its path column names the run files)")
    parser.add_argument("--window", type=float, default=2.0, help="window of travel, d (default 2)")
    parser.add_argument("--late", type=float, default=8.0, help="the late drag from this travel on, d (default 8)")
    parser.add_argument("--output-dir", default=None, help="where to write drag_profile.csv and drag_late.csv")
    a = parser.parse_args(argv)
    if a.window <= 0 or a.late < 0:
        parser.error("--window must be above 0 and --late at least 0")
    runs = pd.read_csv(a.runs)
    missing = {"path", "D", "Fr", "seed", "drag", "drag_err"} - set(runs.columns)
    if missing:
        parser.error(f"{a.runs} has no column(s) {sorted(missing)}: give a study's runs.csv")
    series = read_series(runs)          # each run file read once, for both tables
    prof, late = profiles(runs, a.window, series), compare(runs, a.late, a.window, series)
    if a.output_dir:
        out = Path(a.output_dir)
        out.mkdir(parents=True, exist_ok=True)
        write_csv(prof, out / "drag_profile.csv")
        write_csv(late, out / "drag_late.csv")
    with pd.option_context("display.width", 200):
        print(late.round(3).to_string(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
