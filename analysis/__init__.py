"""Analysis of granudrag pulls: tidy table, fits, figures, report, predictor.

Everything works on one tidy pandas table with a row per pull (see
`analysis.core.table.COLUMNS`), in the project's dimensionless units: lengths in
d, speeds in sqrt(g d), forces in rho d^3 g.

The rooms, one subpackage per concern (each says its job in its __init__; a test checks that
every name here is a subpackage or module, and that the rooms import each other without a cycle):
    core     the table (schema, Froude number, CSV), physics, the paper's numbers and claims,
             Param and Fit, the study's path scheme
    runs     run files (HDF5, from `granudrag pull`) into the table, each drag's error from its series
    fits     the regime fits, the other fits, Eq. 12's law, goodness, fits.json saved and read
    figures  one function per paper figure (PNG + PDF), and what they share
    regime_tests  claim (a) tested: a line, a quadratic and the paper's shape, with their power
    report   Markdown/HTML report with fitted-vs-published table and its verdicts
    deep_law  claims (d)-(f) on deep intruders and on every depth: alpha_mu, collapse, sum rule
    validation  validation studies against their reference protocol, pooled over studies
    ladder   the reproduction ladder (collect, claims, diagnostics, report)
and at the top, the commands that drive them:
    cli      `python -m analysis` and `granudrag-analysis`
    predict  `python -m analysis.predict` and `granudrag-predict`: drag from a saved fit file
    ladder_refit  `python -m analysis.ladder_refit`: the ladder's rungs refitted from their runs
    drag_profile  `python -m analysis.drag_profile`: the drag along each pull of a study

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
