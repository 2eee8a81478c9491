"""Rule force_trace: the drag time series of one pull (Fig. 4) as CSV."""

import pandas as pd

from analysis.core.table import write_csv
from analysis.runs.runs import read_force_trace
from granudrag_study.script import start

log = start(snakemake)
t, drag, transient = read_force_trace(snakemake.input[0])
write_csv(pd.DataFrame({"t": t, "drag": drag, "transient": transient}), snakemake.output[0])
log.info(f"force trace of {snakemake.input[0]}: {len(t)} samples, transient before t = {transient:g}")
