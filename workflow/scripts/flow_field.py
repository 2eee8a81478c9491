"""Rule flow_field: the velocity-field snapshot of each Fig. 9 pull as one CSV (a row per grain).

The middle snapshot of each pull (snapshots are spread evenly over the pull after its
transient); a pull without snapshots is logged and left out, and Fig. 9 says so."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821  (set by Snakemake)
from _setup import start  # noqa: E402

log = start(snakemake)  # noqa: F821
import pandas as pd  # noqa: E402
from analysis.runs import read_run, read_snapshots  # noqa: E402
from analysis.table import write_csv  # noqa: E402

sm = snakemake  # noqa: F821
parts = []
for panel, path in enumerate(sm.input):
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
write_csv(out, sm.output[0], float_format="%.8g")
