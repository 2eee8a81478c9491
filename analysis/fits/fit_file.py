"""The JSON fit file: `save_fits` writes what the fits found (laws, fits, tables, notes and the
summary's further keys), `load_fits` reads it back (also for `python -m analysis.predict`);
the format is described in save_fits.
"""
import json
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from .. import __version__
from ..core.result import Fit
from ..core.table import write_text_atomic
from .fits import ScalingLaw

FORMAT, VERSION = "granudrag-fits", 1
_OWN_KEYS = ("format", "version", "written_by", "units", "laws", "fits", "tables", "notes")


class FitFileError(ValueError):
    """A file that is not a readable granudrag fit file."""


@dataclass
class FitFile:
    laws: list
    fits: dict
    tables: dict
    notes: list = field(default_factory=list)
    summary: dict = field(default_factory=dict)   # the further top-level keys (save_fits)


def save_fits(path, laws=(), fits=None, tables=None, notes=(), summary=None):
    """Write a JSON fit file:

        {"format": "granudrag-fits", "version": 1, "written_by": "granudrag-analysis <VERSION>",
         "laws":   [ScalingLaw: mu, kn, gamman, alpha, phi, regimes, ranges],
         "fits":   {name: Fit: model, params {name: {value, err}}, method,
                    n_points, x_range, meta, [replicates]},
         "tables": {name: [row objects]},
         "notes":  [fits that could not be made, in words],
         ...summary}

    summary: further top-level keys (fitset.summary: phi, alpha, alpha_drag, crossovers,
    at_bounds, violations, options; analysis/README.md). Errors are one standard error;
    null stands for "not estimable".
    """
    doc = {"format": FORMAT, "version": VERSION, "written_by": f"granudrag-analysis {__version__}",
           "units": "lengths in d, speeds in sqrt(g d), forces in rho d^3 g",
           "laws": [law.to_dict() for law in laws],
           "fits": {k: f.to_dict() for k, f in (fits or {}).items()},
           "tables": {k: json.loads(t.to_json(orient="records")) for k, t in (tables or {}).items()},
           "notes": [str(n) for n in notes]}
    for k, v in (summary or {}).items():
        if k in _OWN_KEYS:
            raise ValueError(f"summary key {k!r} would overwrite the fit file's own")
        doc[k] = v
    write_text_atomic(path, json.dumps(doc, indent=1, allow_nan=False))


def load_fits(path):
    """Read a fit file written by save_fits; FitFileError says what is wrong."""
    path = Path(path)
    if not path.is_file():
        raise FitFileError(f"{path}: no such fit file")
    try:
        doc = json.loads(path.read_text())
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise FitFileError(f"{path}: not a JSON fit file ({exc})") from None
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise FitFileError(f"{path}: not a granudrag fit file (no \"format\": \"{FORMAT}\")")
    if doc.get("version") != VERSION:
        raise FitFileError(f"{path}: fit-file version {doc.get('version')!r}, "
                           f"this code reads version {VERSION}")
    try:
        return FitFile(laws=[ScalingLaw.from_dict(d) for d in doc.get("laws", [])],
                       fits={k: Fit.from_dict(d) for k, d in doc.get("fits", {}).items()},
                       tables={k: pd.DataFrame(v) for k, v in doc.get("tables", {}).items()},
                       notes=[str(n) for n in doc.get("notes", [])],
                       summary={k: v for k, v in doc.items() if k not in _OWN_KEYS})
    except (KeyError, TypeError, ValueError, AttributeError, IndexError) as exc:
        # A part of the wrong kind (a number where a fit's dict belongs, say): damaged.
        raise FitFileError(f"{path}: damaged fit file ({type(exc).__name__}: {exc})") from None
