"""Rule fits: every fit of the report, bootstraps included -> fits.json (analysis.fits.fitset)."""

from analysis.core.table import load_csv
from analysis.fits.fitset import Options, run_fits, save_results
from granudrag_study.script import start

log = start(snakemake)
options = Options.from_dict(dict(snakemake.params.options))
r = run_fits(load_csv(snakemake.input[0]), options=options)
save_results(snakemake.output[0], r)
log.info(f"fits ({options.to_dict()}): {len(r.regimes)} regime fits, {len(r.laws)} scaling laws, "
         f"{len(r.alpha_drag)} averaged alpha_mu, {len(r.notes)} not made")
for note in r.notes:
    log.info(note)
