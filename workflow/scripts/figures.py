"""Rules figure_*: draw the figures the rule's PNG outputs name (analysis.figures.figure_list)."""

from analysis.figures.figure_list import draw_files
from granudrag_study.script import start

log = start(snakemake)
for line in draw_files(snakemake.input.items(), snakemake.output):
    log.info(line)
