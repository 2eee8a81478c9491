"""Rule validation: a validation study's runs against the reference protocol (analysis.validation.validation)."""

from analysis.core.table import load_csv
from analysis.validation.validation import validate
from granudrag_study.script import start

log = start(snakemake)
paths = validate(load_csv(snakemake.input[0]), snakemake.params.study, snakemake.params.outdir)
log.info(paths[-1].read_text())
