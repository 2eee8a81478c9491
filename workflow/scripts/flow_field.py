"""Rule flow_field: the velocity-field snapshot of each Fig. 9 pull as one CSV (a row per grain).

The middle snapshot of each pull (snapshots are spread evenly over the pull after its
transient); a pull without snapshots, or that failed (table.allow_failed leaves a placeholder),
is logged and left out, and Fig. 9 says so."""

import pandas as pd

from analysis.core.table import write_csv
from analysis.runs.runs import read_run, read_snapshots
from granudrag_study.failures import describe, is_placeholder
from granudrag_study.script import start

log = start(snakemake)
parts = []
for panel, path in enumerate(snakemake.input):
    if is_placeholder(path):
        log.warning(f"{describe(path)}; left out of Fig. 9")
        continue
    snaps = read_snapshots(path)
    if not snaps:
        log.warning(f"{path}: no snapshots (pull.snapshots is 0); left out of Fig. 9")
        continue
    run = read_run(path)
    snap = snaps[len(snaps) // 2]
    parts.append(snap.assign(panel=panel, D=run["D"], V=run["V"], time=snap.attrs["time"]))
    log.info(f"{path}: snapshot at t = {snap.attrs['time']:g}, {len(snap)} grains in the slab")
columns = ["panel", "D", "V", "time", "dx", "dz", "vx", "vz"]
out = pd.concat(parts, ignore_index=True)[columns] if parts else pd.DataFrame(columns=columns)
write_csv(out, snakemake.output[0], float_format="%.8g")
