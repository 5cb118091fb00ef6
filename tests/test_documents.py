"""The user documents: every link resolves inside the repository, nothing points outside it, the
README stays a short guide, and no history (issue numbers, dates) leaks into them (it goes to
CHANGELOG.md)."""

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
DOCS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
LINKED = DOCS + [REPO / "CHANGELOG.md"]
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def _anchors(text: str) -> set[str]:
    """GitHub's heading anchors: lower case, punctuation dropped, spaces to hyphens."""
    out = set()
    for h in re.findall(r"^#{1,6} (.+)$", text, re.M):
        out.add(re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-"))
    return out


@pytest.mark.parametrize("doc", LINKED, ids=lambda p: p.relative_to(REPO).as_posix())
def test_links_resolve_inside_the_repository(doc):
    text = doc.read_text(encoding="utf-8")
    bad = []
    for target in LINK.findall(text):
        if re.match(r"[a-z]+://", target):  # a citation of a published source, not a file
            continue
        path, _, anchor = target.partition("#")
        dest = (doc.parent / path).resolve() if path else doc
        if not dest.is_relative_to(REPO) or not dest.exists():
            bad.append(target)
        elif anchor and dest.suffix == ".md" and anchor not in _anchors(dest.read_text(encoding="utf-8")):
            bad.append(target)
    assert not bad, f"{doc.name}: links that do not resolve inside the repository: {bad}"
    assert "../shared" not in text and "shared/" not in text, f"{doc.name} names a path outside the repository"


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: p.relative_to(REPO).as_posix())
def test_no_history_in_the_user_documents(doc):
    text = doc.read_text(encoding="utf-8")
    assert not re.findall(r"\b[Ii]ssue \d+", text), f"{doc.name} cites issue numbers"
    assert not re.findall(r"\b20\d\d-[01]\d-[0-3]\d\b", text), f"{doc.name} carries dates"


#: docs/study-files.md quotes a bound's refusal verbatim (tests/study/test_bounds.py), and the reasons in
#: peenflow/study/bounds.py still cite the former BENCHMARKS.md: strict, so fixing them turns this into a failure
#: that asks for the mark to go
@pytest.mark.parametrize("doc", DOCS, ids=lambda p: p.relative_to(REPO).as_posix())
def test_no_document_cites_the_removed_benchmarks_notebook(doc):
    assert "BENCHMARKS.md" not in doc.read_text(encoding="utf-8")


def test_the_readme_is_a_short_guide_with_its_two_commands():
    text = (REPO / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 200
    # the two commands .ci/run and a new user run, exactly
    assert ("python3.11 -m venv .venv && .venv/bin/pip install -e . && .venv/bin/peenflow run studies/quickstart.toml"
            in text)
    assert 'python3.11 -m venv .venv && .venv/bin/pip install -e ".[test]" && .venv/bin/pytest' in text


def test_every_environment_setting_is_documented_with_its_default():
    """Each ``PEENFLOW_*`` variable the code reads has a row in docs/architecture.md's settings table, and a
    default the code states as text (``os.environ.get(NAME, "30")``) is the documented one."""
    rows = {}
    for line in (REPO / "docs" / "architecture.md").read_text(encoding="utf-8").splitlines():
        m = re.match(r"\| `(PEENFLOW_[A-Z_]+)` \| ([^|]+) \|", line)
        if m:
            rows[m.group(1)] = m.group(2).strip()
    sources = "\n".join(p.read_text(encoding="utf-8") for d in ("peenflow", "tasks")
                        for p in sorted((REPO / d).rglob("*.py")))
    names = set(re.findall(r"[\"'](PEENFLOW_[A-Z_]+)[\"']", sources))
    assert "PEENFLOW_CHECKPOINT_EVERY_S" in names
    assert names <= set(rows), f"undocumented settings: {sorted(names - set(rows))}"
    for name, default in re.findall(r"environ\.get\(\"(PEENFLOW_[A-Z_]+)\", \"([^\"]*)\"\)", sources):
        assert rows[name].split()[0] == default, (name, rows[name], default)
