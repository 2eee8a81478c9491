"""Claim (a) tested per drag-vs-Fr series: a line against a quadratic and the paper's shape, with power."""
