"""Analysis of granudrag pulls: tidy table, fits, figures, report, predictor.

Everything works on one tidy pandas table with a row per pull (see
`analysis.table.COLUMNS`), in the project's dimensionless units: lengths in
d, speeds in sqrt(g d), forces in rho d^3 g.

The main modules (each a file of this folder; a test checks that every name here is one):
    table    schema, Froude number, validation, CSV loading
    runs     run files (HDF5, from `granudrag pull`) into the table
    path_scheme  the study's paths (bed, column, pull) declared once: their components, table columns
    restitution  Kuwabara-Kono e(v_n) theory curve (Fig. 2)
    paper    the published numbers the report compares against
    result   Param (value, err) and Fit, the fit-result types
    regimes  three-regime drag(Fr) fit with fitted crossovers
    fits     the other fits, the Eq. 12 scaling law, fit-file save/load
    goodness every fit's chi^2/dof and runs test of its residuals (rejects a model that trends)
    alpha_drag  alpha_mu from the drag at several speeds, averaged (Fig. 18)
    fitset   every fit of a table into fits.json, and back
    figures, figures_yield, figures_drawing, figures_bed
             one function per paper figure (PNG + PDF), and what they share
    claims   the paper's headline claims by letter
    report   Markdown/HTML report with fitted-vs-published table
    report_render  the report's blocks as Markdown and HTML
    predict  command-line drag prediction from a saved fit file
    ladder, ladder_*  the reproduction ladder (collect, claims, diagnostics, report)

The workflow's library (config, plan, paths, cost) is another package, `granudrag_study`
(workflow/granudrag_study/), which the analysis does not import.

Importing the package does not import matplotlib; only the figure modules do.
"""

from pathlib import Path as _Path


def _release():
    """The release, declared once in the repository's VERSION file (as the engine's
    `granudrag --version`); an installed copy without the file asks its metadata."""
    declared = _Path(__file__).resolve().parent.parent / "VERSION"
    if declared.is_file():
        return declared.read_text().split()[0]
    from importlib.metadata import version

    return version("granudrag-analysis")


__version__ = _release()
