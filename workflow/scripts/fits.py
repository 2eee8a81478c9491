"""Rule fits: every fit of the report, bootstraps included -> fits.json (analysis.fitset)."""

from analysis.fitset import run_fits, save_results
from analysis.study.script import start
from analysis.table import load_csv

log = start(snakemake)
r = run_fits(load_csv(snakemake.input[0]), n_boot=snakemake.params.n_boot, seed=snakemake.params.seed)
save_results(snakemake.output[0], r)
log.info(f"fits: {len(r.regimes)} regime fits, {len(r.laws)} scaling laws, {len(r.notes)} not made")
for note in r.notes:
    log.info(note)
