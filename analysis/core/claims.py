"""The paper's headline claims by letter, and which claim a report row's number tests: shared by
the report (its at-a-glance lines) and the reproduction ladder (its table by claim)."""

CLAIMS = {
    "a": "three regimes, Fr_1 ≈ 1 and Fr_2 ≈ 5, independent of D and h",
    "b": "θ(Fr) = Υ1 Fr^Υ2 + π/Υ3 (Eq. 7): Υ1 = -0.15, Υ2 = 0.38, Υ3 = 2.45",
    "c": "κ(Fr) = 0.887 + 0.185 Fr (Eq. 8, Fig. 8)",
    "d": "φ_0 ≈ 2 and F_Y saturating in μ",
    "e": "α_0 ≈ 1",
    "f": "α_μ + φ_μ ≈ 3",
    "g": "Table I: the μ = 0 drag in regime I is a'' + b'' Fr^c''",
}
OTHER = "other"     # a report row no claim names (a row the report gained later)


def claim_of(quantity):
    """The claim letter of a report row, from its quantity text (analysis/report/report.py)."""
    for prefix, letter in (("Fr_1 (", "a"), ("Fr_2 (", "a"), ("θ(Fr)", "b"), ("θ_present(Fr)", "b"), ("κ(Fr)", "c"),
                           ("φ_0", "d"), ("F_Y saturating", "d"), ("α_0", "e"), ("α_μ + φ_μ", "f"),
                           ("Table I", "g")):
        if quantity.startswith(prefix):
            return letter
    return OTHER
