"""Rule table: every run file of the study -> results/runs.csv (one row per pull, analysis.runs.runs),
results/table.csv (one row per point: replicate beds combined, analysis.core.table.combine_beds; a
point poured once takes the study's pooled between-bed scatter, else the config's
table.bed_scatter prior, and says which in bed_scatter_source; the drag's errors recomputed from
each pull's force series, analysis.runs.series_error, beside the engine's and the beds' spread),
and the P(Z) of every pull (Fig. 7). Unusable run files and the placeholders of failed pulls
(table.allow_failed, granudrag_study.failures) are listed in results/table_problems.txt, one
line each with the reason, and, with table.allow_failed, left out; the failed pulls also in
results/failed_pulls.txt, which the end of the run removes so that the next run retries them."""

import sys
from pathlib import Path

import pandas as pd

from analysis.core.table import combine_beds, mark_yield, save_csv, write_csv
from analysis.runs.runs import load_runs, read_coordination_distribution
from granudrag_study.failures import describe, is_placeholder
from granudrag_study.script import start

sm = snakemake
log = start(sm)
failed = [p for p in sm.input.runs if is_placeholder(p)]
df, problems = load_runs([p for p in sm.input.runs if p not in failed], root=sm.params.root, errors="collect")
problems = [describe(p, sm.params.root) for p in failed] + problems
Path(sm.output.problems).write_text("".join(p + "\n" for p in problems))
Path(sm.output.failed).write_text("".join(p + "\n" for p in problems[: len(failed)]))
for p in problems:
    log.error(p)
if problems and not sm.params.allow_failed:
    sys.exit(
        f"table: {len(problems)} of {len(sm.input.runs)} run files unusable (listed in "
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
df = mark_yield(df, sm.params.yield_speed)  # which pulls are the yield force (report.yield_speed)
save_csv(df, sm.output.runs)
points = combine_beds(df, prior=sm.params.bed_scatter)
replicated = points[points.n_beds > 1]
log.info(
    f"table: {len(points)} points, {len(replicated)} with replicate beds; "
    f"{(~df.plateau.astype(bool)).sum()} of {len(df)} pulls without a converged drag error "
    f"(analysis.runs.series_error; the engine's: {(~df.plateau_engine.astype(bool)).sum()}), the errors "
    f"a median {(df.drag_err / df.drag_err_engine).median():.3g} of the engine's"
)
if len(replicated):  # pull noise alone: about 1 (a median 0.83 with three beds)
    log.info(
        "beds' standard deviation of a point's drag over its mean pull error, median: "
        f"{replicated.drag_bed_sd_ratio.median():.3g} (the engine's errors: "
        f"{replicated.drag_bed_sd_ratio_engine.median():.3g})"
    )
sources = points.bed_scatter_source.value_counts()
log.info("bed scatter of the points: " + ", ".join(f"{n} {s}" for s, n in sources.items()))
if "none" in sources:
    log.warning(
        f"table: {sources['none']} points poured once have no bed scatter in their errors "
        "(no replicated point in the study, no table.bed_scatter prior in the config)"
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
