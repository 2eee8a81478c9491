"""analysis.ladder.ladder_deep: a claim's `deep` rungs (system II's depths) in the claim table,
refused by name when misnamed, quiet before their rung is collected, several in their order."""
import pandas as pd
import pytest
from test_ladder import deep_law_csv

from analysis.ladder.ladder_claims import LadderError


def test_a_claims_deep_entry_is_refused_by_name_when_wrong_and_quiet_before_its_rung_is_read(tmp_path):
    from analysis.ladder.ladder_deep import deep_cells
    from analysis.ladder.ladder_summary import read_summary
    names = ["rung-a", "rung-deep"]
    good = {"f": {"closest": ["rung-a"], "deep": {"rung": "rung-deep", "show": {"sum_yield": "sum"}}}}
    spec = read_summary({"summary": good}, names)["f"]
    assert spec["deep"] == [{"rung": "rung-deep", "show": {"sum_yield": "sum"}}]
    assert deep_cells(tmp_path, spec) == []                       # no deep_law.csv yet: no cells
    (tmp_path / "rung-deep").mkdir()
    deep_law_csv(tmp_path / "rung-deep" / "deep_law.csv")
    assert deep_cells(tmp_path, spec) == ["sum, h ≥ 45 d (45-65 d), `rung-deep`: 2.80 ± 0.29 (paper ≈ 3) — "
                                          "reproduced within error bars"]
    assert deep_cells(tmp_path, read_summary({"summary": {"f": {}}}, names)["f"]) == []
    for deep, message in (
            ({"rung": "rung-z", "show": {"sum_yield": "s"}}, "summary.f.deep.rung names a rung not listed: rung-z"),
            ({"rung": "rung-deep", "show": {"alpha": "s"}}, "summary.f.deep.show names no depth-law quantity: alpha"),
            ({"rung": "rung-deep"}, r"summary.f.deep takes \{rung"),
            ([{"rung": "rung-deep", "show": {}}, {"rung": "rung-y", "show": {}}],
             r"summary.f.deep\[1\].rung names a rung not listed: rung-y")):
        with pytest.raises(LadderError, match=message):
            read_summary({"summary": {"f": {"deep": deep}}}, names)
    (tmp_path / "rung-deep" / "deep_law.csv").write_text("D,mu\n4,0.5\n")
    with pytest.raises(LadderError, match="not a deep_law.csv .no column"):
        deep_cells(tmp_path, spec)


def test_a_claim_quotes_several_deep_rungs_in_their_order_and_skips_one_not_collected(tmp_path):
    """The sum rule at μ = 0.5 and at μ = 0 come from different rungs: a `deep` list quotes each
    rung's cells in the list's order, and (f)'s figure gets every rung's sums; a rung without its
    deep_law.csv yet adds nothing."""
    from analysis.ladder.ladder_deep import deep_cells, deep_sums
    from analysis.ladder.ladder_summary import read_summary
    names = ["rung-a", "deep-mu0", "deep-mu05", "deep-later"]
    entries = [{"rung": r, "show": {"sum_yield": f"sum {r}"}} for r in ("deep-mu0", "deep-later", "deep-mu05")]
    spec = read_summary({"summary": {"f": {"closest": ["rung-a"], "deep": entries}}}, names)["f"]
    for rung, mu in (("deep-mu05", 0.5), ("deep-mu0", 0.0)):
        (tmp_path / rung).mkdir()
        deep_law_csv(tmp_path / rung / "deep_law.csv")
        table = pd.read_csv(tmp_path / rung / "deep_law.csv").assign(mu=mu)
        table.to_csv(tmp_path / rung / "deep_law.csv", index=False)
    cells = deep_cells(tmp_path, spec)
    assert [c.split(",")[0] for c in cells] == ["sum deep-mu0", "sum deep-mu05"]
    rows = deep_sums(tmp_path, spec)
    assert list(rows.rung) == ["deep-mu0", "deep-mu05"] and list(rows.mu) == [0.0, 0.5]
