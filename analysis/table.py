"""The tidy pull table: schema, validation and CSV loading (the Froude number: analysis.physics).

One row per pull. All quantities are dimensionless in grain density rho,
mean grain diameter d and gravity g (SPEC section 1).
"""
from pathlib import Path

import numpy as np
import pandas as pd

from .physics import froude

# name -> (kind, meaning). "text" columns identify; "number" columns are data.
COLUMNS = {
    "system": ("text", "geometry family of the paper: 'I' (vary D) or 'II' (vary h)"),
    "D": ("number", "intruder diameter [d]"),
    "h": ("number", "depth of the intruder centre below the bed's free surface [d]"),
    "mu": ("number", "grain friction coefficient"),
    "kn": ("number", "normal stiffness K_n [rho d g]"),
    "gamman": ("number", "normal damping gamma_n [sqrt(g/d^3)]"),
    "V": ("number", "pulling speed [sqrt(g d)]"),
    "Fr": ("number", "Froude number, paper Eq. 4"),
    "drag": ("number", "time-averaged drag <F_x> [rho d^3 g]"),
    "drag_err": ("number", "standard error of the drag (block averaging)"),
    "n_contacts": ("number", "mean intruder coordination number n"),
    "theta": ("number", "mean contact angle at contact formation, Eq. 6 [rad]"),
    "Z": ("number", "mean bulk coordination number near the intruder"),
    "kappa": ("number", "normalised coordination number, Eq. 8"),
    "run": ("text", "identifier of the pull (its run directory)"),
}
TEXT_COLUMNS = [c for c, (kind, _) in COLUMNS.items() if kind == "text"]
NUMBER_COLUMNS = [c for c, (kind, _) in COLUMNS.items() if kind == "number"]

# Every pull has these; the observables after them may be NaN (a yield pull
# that made too few contacts has no meaningful theta, for instance).
REQUIRED_FINITE = ["D", "h", "mu", "kn", "gamman", "V", "Fr", "drag"]

# The paper's zero-speed limit: the yield force is the drag at this speed.
YIELD_SPEED = 0.01


class TableError(ValueError):
    """A file or frame that is not a usable pull table."""


def validate_table(df):
    """Raise ValueError naming every missing, ill-typed or invalid column.

    Extra columns are allowed. Returns df unchanged so calls can chain.
    """
    if not isinstance(df, pd.DataFrame):
        raise ValueError(f"expected a pandas DataFrame, got {type(df).__name__}")
    missing = [c for c in COLUMNS if c not in df.columns]
    if missing:
        found = ", ".join(map(str, df.columns[:8])) + (", ..." if df.shape[1] > 8 else "")
        raise ValueError(f"missing columns: {', '.join(missing)} (found: {found or 'none'})")
    problems = []
    for c in NUMBER_COLUMNS:
        kind = df[c].dtype.kind
        if kind not in "iuf":
            problems.append(f"{c} must be numeric (has dtype {df[c].dtype})")
    for c in TEXT_COLUMNS:
        if not (pd.api.types.is_object_dtype(df[c]) or pd.api.types.is_string_dtype(df[c])):
            problems.append(f"{c} must be text (has dtype {df[c].dtype})")
    if problems:
        raise ValueError("ill-typed columns: " + "; ".join(problems))
    for c in REQUIRED_FINITE:
        bad = ~np.isfinite(df[c].to_numpy(dtype=float))
        if bad.any():
            problems.append(f"{c} is missing or not finite in {bad.sum()} row(s)")
    if problems:
        raise ValueError("invalid values: " + "; ".join(problems))
    for c, ok in [("D", df.D > 0), ("h", df.h > 0), ("mu", df.mu >= 0),
                  ("kn", df.kn > 0), ("gamman", df.gamman >= 0), ("V", df.V >= 0)]:
        if not ok.all():
            problems.append(f"{c} out of range in {(~ok).sum()} row(s)")
    # Fr is stored for convenience but must be Eq. 4 of the stored V and D,
    # otherwise a table mixing conventions (e.g. Eq. 5) would fit silently.
    off = ~np.isclose(df.Fr, froude(df.V, df.D), rtol=1e-4, atol=1e-9)
    if off.any():
        problems.append(f"Fr differs from froude(V, D) (paper Eq. 4) in {off.sum()} row(s)")
    if problems:
        raise ValueError("invalid values: " + "; ".join(problems))
    return df


def load_csv(path):
    """Read a pull table from CSV; raise TableError saying what is wrong."""
    path = Path(path)
    if not path.is_file():
        raise TableError(f"{path}: no such file")
    with open(path, "rb") as fh:
        head = fh.read(4096)
    if head.startswith(b"\x89HDF"):
        raise TableError(f"{path}: is an HDF5 file, not a CSV pull table "
                         "(run files are collected into a table by the run loader)")
    if b"\x00" in head:
        raise TableError(f"{path}: is a binary file, not a CSV pull table")
    try:
        df = pd.read_csv(path, dtype={c: str for c in TEXT_COLUMNS})
    except (UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise TableError(f"{path}: not a readable CSV file ({exc})") from None
    try:
        return validate_table(df)
    except ValueError as exc:
        raise TableError(f"{path}: not a granudrag pull table: {exc}") from None


def write_csv(df, path, float_format="%.10g"):
    """Write df as CSV atomically: a temporary file beside path, then a rename, so that an
    interrupted write never leaves a truncated file under the final name."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    df.to_csv(tmp, index=False, float_format=float_format)
    tmp.replace(path)


def save_csv(df, path):
    """Write a validated table so that load_csv reads it back unchanged."""
    validate_table(df)
    extra = [c for c in df.columns if c not in COLUMNS]
    write_csv(df[list(COLUMNS) + extra], path, float_format="%.17g")


# --- Run files (HDF5) ---------------------------------------------------
# The engine's per-pull HDF5 files are read into this table by
# `analysis.runs.load_runs(paths)`.


def yield_rows(df, speed=YIELD_SPEED):
    """Rows pulled at the zero-speed limit (their drag is the yield force F_Y)."""
    return df[np.isclose(df.V, speed, rtol=1e-6, atol=1e-12)]


def reference_params(df):
    """The (kn, gamman) pair with the most pulls: the study's default contact law."""
    counts = df.groupby(["kn", "gamman"]).size()
    if counts.empty:
        raise ValueError("empty table has no reference contact parameters")
    return tuple(float(v) for v in counts.idxmax())


def select(df, *, atol=1e-9, **equal):
    """Rows whose columns equal the given values (floats compared with atol)."""
    keep = np.ones(len(df), dtype=bool)
    for col, value in equal.items():
        if isinstance(value, str):
            keep &= (df[col] == value).to_numpy()
        else:
            keep &= np.isclose(df[col].to_numpy(dtype=float), value, rtol=1e-9, atol=atol)
    return df[keep]
