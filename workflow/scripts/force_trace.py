"""Rule force_trace: the drag time series of one pull (Fig. 4) as CSV."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821  (set by Snakemake)
from _setup import start  # noqa: E402

log = start(snakemake)  # noqa: F821
import pandas as pd  # noqa: E402
from analysis.runs import read_force_trace  # noqa: E402
from analysis.table import write_csv  # noqa: E402

sm = snakemake  # noqa: F821
t, drag, transient = read_force_trace(sm.input[0])
write_csv(pd.DataFrame({"t": t, "drag": drag, "transient": transient}), sm.output[0])
log.info(f"force trace of {sm.input[0]}: {len(t)} samples, transient before t = {transient:g}")
