"""The documentation refers only to what the repository has: README.md stays short and names
the two commands, and every relative link and every backticked repository path in README.md,
docs/*.md and config/README.md exists (outputs a run creates, under results/, logs/, build/ or
.venv/, are not checked)."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LADDER = ROOT / "results" / "reproduction"
REFERENCE = [ROOT / "README.md", ROOT / "config" / "README.md", *sorted((ROOT / "docs").glob("*.md")),
             LADDER / "README.md"]
# The dated records: measurements appended, never the place for today's number.
LOGS = [*sorted((ROOT / "docs" / "log").glob("*.md")), LADDER / "history.md"]
DOCS = REFERENCE + LOGS
PATH_PREFIXES = tuple("src/ analysis/ workflow/ config/ tests/ tools/ bench/ docs/ cmake/ requirements/ .test/".split())
NOT_A_PATH = re.compile(r"[\s<*{…]|\.\.\.")  # a pattern or placeholder, not one file


def _name(doc):
    return str(doc.relative_to(ROOT))


def test_readme_is_at_most_200_lines():
    lines = (ROOT / "README.md").read_text().splitlines()
    assert len(lines) <= 200, f"README.md has {len(lines)} lines: move detail to docs/"


def test_readme_names_the_two_commands():
    text = (ROOT / "README.md").read_text()
    for command in ("tools/study.sh", "tools/test.sh"):
        assert command in text, command


@pytest.mark.parametrize("doc", DOCS, ids=_name)
def test_relative_links_resolve(doc):
    missing = []
    text = doc.read_text()
    html = re.findall(r"<(?:img|a)\s[^>]*?(?:src|href)=\"([^\"]+)\"", text)     # a figure beside a table row
    for target in re.findall(r"\]\(([^)\s]+)\)", text) + html:
        path = target.split("#", 1)[0]
        if not path or re.match(r"[a-z][a-z0-9+.-]*:", path):  # an anchor in the page, or a URL
            continue
        if not (doc.parent / path).exists():
            missing.append(target)
    assert not missing, f"{_name(doc)} links to files the repository does not have: {missing}"


# A release's list of changes names files as they were then (some since renamed or removed).
CURRENT = [d for d in DOCS if not d.name.startswith("changes-")]


@pytest.mark.parametrize("doc", CURRENT, ids=_name)
def test_backticked_paths_exist(doc):
    missing = []
    for token in re.findall(r"`([^`]+)`", doc.read_text()):
        if not token.startswith(PATH_PREFIXES) or NOT_A_PATH.search(token):
            continue
        path = re.split(r"[:(]", token, maxsplit=1)[0]  # drop a trailing :line or (...)
        if not (ROOT / path).exists():
            missing.append(token)
    assert not missing, f"{_name(doc)} names paths the repository does not have: {missing}"


def test_nothing_cites_a_specification_the_repository_does_not_have():
    # The design was written from a specification outside the repository: sources and docs cite
    # the paper's sections and equations instead ("SPEC §2" once stood in six headers).
    cited = [str(p.relative_to(ROOT)) for folder in ("src", "analysis", "workflow", "config", "docs", "tools")
             for p in (ROOT / folder).rglob("*") if p.is_file() and p.suffix in {".cpp", ".hpp", ".py", ".smk",
                                                                                ".md", ".yaml", ".sh"}
             and re.search(r"\bSPEC\b ?(§|section|\d)", p.read_text(errors="replace"))]
    assert not cited, f"these cite SPEC, which the repository does not have: {cited}"


def test_the_ladder_readme_opens_with_one_row_per_claim_and_its_figure():
    # results/reproduction/README.md: a physicist reads the claims (a)-(g) first, each at the rung
    # closest to the paper's conditions with its evidence beside it (`ladder table` writes the
    # table between the markers); the dated history has its own file, linked.
    from analysis.core.claims import CLAIMS
    from analysis.ladder.ladder_summary import CLAIMS_BEGIN, CLAIMS_END
    text = (LADDER / "README.md").read_text()
    before = text[:text.index(CLAIMS_BEGIN)]
    assert before.count("\n## ") <= 1, "the claim table comes first, under at most its own heading"
    rows = [line for line in text[len(before):text.index(CLAIMS_END)].splitlines() if line.startswith("| **(")]
    assert [r[5] for r in rows] == sorted(CLAIMS), rows
    for letter, row in zip(sorted(CLAIMS), rows):
        assert f'<img src="evidence_{letter}.png"' in row and (LADDER / f"evidence_{letter}.png").is_file()
    # The written part (the generated tables aside) stays short: the dated record is in
    # history.md (it was about 9,000 words here before).
    from analysis.ladder.ladder import LADDER_BEGIN, LADDER_END
    written = text
    for a, b in ((CLAIMS_BEGIN, CLAIMS_END), (LADDER_BEGIN, LADDER_END)):
        written = written[:written.index(a)] + written[written.index(b):]
    assert "](history.md)" in text and len(written.split()) < 5000, "the dated history belongs in history.md"


# A measured figure that a reader would quote: a wall time ("39 min 49 s", "0:39:49" as the
# ladder's table writes it, "5 h 26 min") or a suite's time ("1,932 s of tests"). Each has one
# home among the reference documents and the configs' comments; the others link to it (the dated
# logs may repeat it: they record).
MEASURED = re.compile(r"\b\d+ min \d+ s\b|\b\d[\d,]* s of tests\b|\b\d+:[0-5]\d:[0-5]\d\b|\b\d+ h \d+ min\b")


def test_a_measured_figure_is_kept_in_one_reference_file():
    homes = {}
    configs = sorted((ROOT / "config").rglob("*.yaml"))
    for doc in REFERENCE + configs:
        for figure in set(MEASURED.findall(doc.read_text())):
            homes.setdefault(figure, []).append(_name(doc))
    twice = {f: files for f, files in homes.items() if len(files) > 1}
    assert not twice, f"figures kept by hand in two files (keep one home, link it): {twice}"


def test_the_figure_check_sees_a_copy():
    # The check above is not blind: the default study's wall time written into a second file is seen.
    text = "measured: 39 min 49 s on 2 cores; the suite, 1,932 s of tests; 0:39:49; 5 h 26 min"
    assert MEASURED.findall(text) == ["39 min 49 s", "1,932 s of tests", "0:39:49", "5 h 26 min"]
