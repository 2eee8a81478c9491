"""A null replica of a bed: a copy with one mobile grain's velocity changed by a tiny amount
(default 1e-9 sqrt(g d) along x). Pulled like the original it is the same physics, and chaos
makes its trajectory independent of the original's within a few time units, so the pair's
difference is what a paired comparison (analysis.validation) must call agreement: it measures
how far two pulls through one bed drift apart when nothing physical changed.

    /usr/bin/python3 tools/null_replica.py BED OUT [--epsilon 1e-9] [--grain K]

--grain: the first mobile grain at or after this index (default: the bed's middle index).
Writes OUT atomically (a temporary file, then a rename); BED is not touched.
"""
import argparse
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np

SPECIES = "/particles/all/species/value"
VELOCITY = "/particles/all/velocity/value"
MOBILE = 0


def replicate(bed, out, epsilon=1e-9, grain=None):
    """Copies `bed` to `out` with grain k's x velocity raised by epsilon; returns k."""
    with h5py.File(bed, "r") as f:
        if SPECIES not in f or VELOCITY not in f:
            raise ValueError(f"{bed}: no {SPECIES} or {VELOCITY}: not a granudrag bed (granudrag pour writes one)")
        species = f[SPECIES][()]
    start = len(species) // 2 if grain is None else grain
    if not 0 <= start < len(species):
        raise ValueError(f"--grain {start}: the bed has bodies 0 to {len(species) - 1}")
    mobile = np.flatnonzero(species[start:] == MOBILE)
    if not len(mobile):
        raise ValueError(f"{bed}: no mobile grain at or after index {start}; give a smaller --grain")
    k = int(start + mobile[0])
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(out)), suffix=".h5.tmp")
    os.close(fd)
    try:
        shutil.copyfile(bed, tmp)
        with h5py.File(tmp, "r+") as f:
            v = f[VELOCITY]
            row = v[k]
            row[0] += epsilon
            v[k] = row
        os.replace(tmp, out)
    except BaseException:
        os.unlink(tmp)
        raise
    return k


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bed")
    ap.add_argument("out")
    ap.add_argument("--epsilon", type=float, default=1e-9, help="velocity change, sqrt(g d) (default 1e-9)")
    ap.add_argument("--grain", type=int, default=None, help="first candidate index (default: the middle)")
    a = ap.parse_args(argv)
    try:
        k = replicate(a.bed, a.out, a.epsilon, a.grain)
    except (OSError, ValueError) as e:
        print(f"null_replica: {e}", file=sys.stderr)
        return 2
    print(f"null_replica: {a.out}: grain {k}'s x velocity + {a.epsilon:g}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
