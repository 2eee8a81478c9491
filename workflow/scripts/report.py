"""Rule report: report.md and report.html from the table, fits.json and the figure files; the
pulls the table left out (results/table_problems.txt: failed pulls and unusable run files, with
table.allow_failed) are listed under the title, each with its reason."""

import html
from pathlib import Path

from analysis.core.table import load_csv, write_text_atomic
from analysis.fits.fitset import load_results
from analysis.report.report import write_report
from granudrag_study.script import start

TITLE = "Pulls left out of the table"


def intro(n):
    return (f"{n} planned pull{'s' if n != 1 else ''} {'are' if n != 1 else 'is'} not in the table, "
            "the fits or the figures below (table.allow_failed); the study's next run retries a "
            "failed pull:")


def list_left_out(md_path, html_path, left_out):
    """Put the left-out pulls under the report's title, in report.md and report.html."""
    md = md_path.read_text()
    block = f"## {TITLE}\n\n{intro(len(left_out))}\n\n" + "".join(f"- {x}\n" for x in left_out) + "\n"
    head, sep, rest = md.partition("\n")
    write_text_atomic(md_path, head + sep + "\n" + block + rest.lstrip("\n") if sep else md + "\n" + block)
    page = html_path.read_text()
    block = (f"<h2>{html.escape(TITLE)}</h2><p>{html.escape(intro(len(left_out)))}</p><ul>"
             + "".join(f"<li>{html.escape(x)}</li>" for x in left_out) + "</ul>")
    at = page.find("</h1>")
    at = at + len("</h1>") if at >= 0 else page.rfind("</body>")
    write_text_atomic(html_path, page[:at] + block + page[at:])


log = start(snakemake)
df = load_csv(snakemake.input.table)
outdir = Path(snakemake.output.md).parent
md = write_report(df, load_results(snakemake.input.fits), outdir, snakemake.params.n_boot, snakemake.params.seed)
left_out = [x for x in Path(snakemake.input.problems).read_text().splitlines() if x.strip()]
if left_out:
    list_left_out(Path(snakemake.output.md), Path(snakemake.output.html), left_out)
    log.warning(f"report: {len(left_out)} pulls left out of the table, listed under the title")
log.info(f"report: {md} ({len(df)} pulls)")
