"""What "agrees" means for the validation studies (analysis.validation.validation,
analysis.validation.pull_length): a variant's drag F agrees with the reference's F_ref when

    z = (F - F_ref) / sqrt(e^2 + e_ref^2),  |z| < Z_AGREE;

the error a study raises when its table cannot answer its question; and how a key's value is
shown in labels. Both studies use these, and validation dispatches to pull_length, so they live
here rather than in either of them."""
import math
import numbers

Z_AGREE = 2.0   # |z| below this: agrees (a 95 % two-sided test for one comparison)


class ValidationError(ValueError):
    """The table cannot answer the study's question (says what is missing)."""


def label_value(v):
    """A key's value in a label or sentence: numbers as %g, names (a system) as they are."""
    return f"{v:g}" if isinstance(v, numbers.Real) else str(v)


def z_score(diff, err):
    """diff / err; with no error, infinite with the difference's sign, or 0 when the difference
    is 0 too (identical numbers: nothing to see, where inf * sign(0) would give NaN)."""
    if err > 0:
        return diff / err
    return 0.0 if diff == 0 else math.copysign(math.inf, diff)
