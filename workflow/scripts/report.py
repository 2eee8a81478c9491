"""Rule report: report.md and report.html from the table, fits.json and the figure files."""

from pathlib import Path

from analysis.fitset import load_results
from analysis.report import write_report
from analysis.study.script import start
from analysis.table import load_csv

log = start(snakemake)
df = load_csv(snakemake.input.table)
outdir = Path(snakemake.output.md).parent
md = write_report(df, load_results(snakemake.input.fits), outdir, snakemake.params.n_boot, snakemake.params.seed)
log.info(f"report: {md} ({len(df)} pulls)")
