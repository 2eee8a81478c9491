"""Rule report: fits, figures and the report (analysis.report.build_report)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821  (set by Snakemake)
from _setup import start  # noqa: E402

log = start(snakemake)  # noqa: F821
import pandas as pd  # noqa: E402
from analysis.report import build_report  # noqa: E402
from analysis.table import load_csv  # noqa: E402

sm = snakemake  # noqa: F821
df = load_csv(sm.input.table)
engine, theory = pd.read_csv(sm.input.restitution), pd.read_csv(sm.input.theory)
trace = pd.read_csv(sm.input.trace)
coordination = pd.read_csv(sm.input.coordination, dtype={"system": str})
flow = pd.read_csv(sm.input.flow)
panels = [(g.D.iloc[0], g.V.iloc[0], g) for _, g in flow.groupby("panel")]
label = (f"granudrag drop test ($K_n = {theory.kn.iloc[0]:.3g}$, "
         f"$\\gamma_n = {theory.gamman.iloc[0]:.4g}$)")
md = build_report(df, sm.output[0], n_boot=sm.params.n_boot, seed=sm.params.seed,
                  restitution=(engine.v_n, engine.e_dem, theory.v_n, theory.e, label),
                  trace=(trace.t, trace.drag, float(trace.transient.iloc[0])),
                  coordination=coordination, flow=panels)
log.info(f"report: {md} ({len(df)} pulls)")
