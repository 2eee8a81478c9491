"""Rule table: every run file of the study -> results/runs.csv (one row per pull, analysis.runs),
results/table.csv (one row per point: replicate beds combined, analysis.table.combine_beds),
and the P(Z) of every pull (Fig. 7)."""

import sys
from pathlib import Path

import pandas as pd

from analysis.runs import load_runs, read_coordination_distribution
from analysis.study.script import start
from analysis.table import combine_beds, save_csv, write_csv

sm = snakemake
log = start(sm)
df, problems = load_runs(list(sm.input), root=sm.params.root, errors="collect")
Path(sm.output.problems).write_text("".join(p + "\n" for p in problems))
for p in problems:
    log.error(p)
if problems and not sm.params.allow_failed:
    sys.exit(
        f"table: {len(problems)} of {len(sm.input)} run files unusable (listed in "
        f"{sm.output.problems} and {sm.log[0]}); set table.allow_failed: true to leave them out"
    )
if df.empty:
    sys.exit("table: no usable run files")
off = (df.h_requested - df.h).dropna()
log.info(f"table: {len(df)} pulls, {df.system.nunique()} systems")
if len(off):
    worst = df.loc[off.abs().idxmax()]
    log.info(
        f"depth: measured minus requested from {-off.max():.3f} to {-off.min():.3f} d "
        f"(largest: requested {worst.h_requested:g}, measured {worst.h:.3f}, {worst.run})"
    )
save_csv(df, sm.output.runs)
points = combine_beds(df)
replicated = points[points.n_beds > 1]
log.info(
    f"table: {len(points)} points, {len(replicated)} with replicate beds; "
    f"{(~df.plateau.astype(bool)).sum()} of {len(df)} pulls without a converged drag error"
)
if len(replicated):
    rel = (replicated.drag_err_between / replicated.drag).median()
    log.info(f"between-bed error of the mean, median relative: {rel:.3g}")
save_csv(points, sm.output.table)

# P(Z) of every pull in the table (Fig. 7), long format: one row per run and Z.
parts = []
for row in df.itertuples(index=False):
    z, p = read_coordination_distribution(row.path)
    keys = {k: getattr(row, k) for k in ("run", "system", "D", "mu", "kn", "gamman", "V", "Fr")}
    parts.append(pd.DataFrame({**keys, "Z": z, "P": p}))
write_csv(pd.concat(parts, ignore_index=True), sm.output.coordination)
