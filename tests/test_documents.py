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


#: the measurement log retired into docs/validation.md and docs/performance.md (CHANGELOG.md may name it as
#: history, and this file names it to look for it)
RETIRED = "BENCHMARKS" + ".md"


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: p.relative_to(REPO).as_posix())
def test_no_document_cites_the_removed_benchmarks_notebook(doc):
    assert RETIRED not in doc.read_text(encoding="utf-8")


#: where code cites the documents: the package, the stages, the benchmarks (scripts, README, reference
#: study files) and the tests; the benchmarks' git-ignored result stores are not code
CODE_ROOTS = ("peenflow", "tasks", "benchmarks", "tests")
CODE_SUFFIXES = (".py", ".md", ".toml")
IGNORED = (REPO / "benchmarks" / "reference" / "store",)
#: "docs/validation.md section 6", "docs/validation.md §8", "`docs/performance.md` sections 2 and 3", each
#: optionally followed by the quoted titles of the paragraphs meant: ', "Slow shots"' or ' ("Dense sequences")'
CITATION = re.compile(r"docs/([\w.-]+\.md)`?,?\s+(?:sections?\s+|§\s?)(\d+)((?:\s*(?:,|and)\s*\d+\b)*)")
TITLES = re.compile(r'(?:\s*[,(]\s*"([^"]+)")+')
TITLE = re.compile(r'"([^"]+)"')
DOC_MENTION = re.compile(r"docs/([\w.-]+\.md)")


def _code_files() -> list[Path]:
    out = []
    for root in CODE_ROOTS:
        for f in sorted((REPO / root).rglob("*")):
            if (f.suffix in CODE_SUFFIXES and f.is_file() and "__pycache__" not in f.parts
                    and not any(f.is_relative_to(i) for i in IGNORED) and f != Path(__file__).resolve()):
                out.append(f)
    return out


def _flat(text: str) -> str:
    """Text as one line, for comparing a cited title with a document: markup, comment and docstring line
    breaks dropped, case and runs of blanks ignored."""
    text = re.sub(r"\n\s*#:?\s*", " ", text)
    return " ".join(text.replace("**", "").replace("`", "").split()).lower()


def _sections(doc: Path) -> dict[int, str]:
    """Numbered sections of a document: {N: the section's text, from its '## N.' heading to the next}."""
    parts = re.split(r"^## (\d+)\. ", doc.read_text(encoding="utf-8"), flags=re.M)
    return {int(n): body for n, body in zip(parts[1::2], parts[2::2])}


def citations(text: str) -> list[tuple[str, int, list[str]]]:
    """Every 'docs/NAME.md section N' in ``text``: (NAME.md, N, the titles quoted after it), one entry
    per section of a 'sections 4 and 9'."""
    out = []
    for m in CITATION.finditer(text):
        numbers = [int(m.group(2))] + [int(n) for n in re.findall(r"\d+", m.group(3))]
        quoted = TITLES.match(text, m.end())
        titles = TITLE.findall(quoted.group(0)) if quoted and not m.group(3) else []
        out += [(m.group(1), n, titles if len(numbers) == 1 else []) for n in numbers]
    return out


def bad_citations(text: str, docs: Path) -> list[str]:
    """The citations in ``text`` of a document not in ``docs``, a section it does not have, or a quoted
    title that section does not contain."""
    bad = [f"docs/{name} (no such document)" for name in sorted(set(DOC_MENTION.findall(text)))
           if not (docs / name).is_file()]
    for name, n, titles in citations(text):
        if not (docs / name).is_file():
            continue
        sections = _sections(docs / name)
        if n not in sections:
            bad.append(f"docs/{name} section {n} (it has sections {sorted(sections)})")
            continue
        bad += [f'docs/{name} section {n}, "{t}" (not in that section)' for t in titles
                if _flat(t) not in _flat(sections[n])]
    return bad


def test_the_citation_reader_reads_every_form_and_finds_a_wrong_one(tmp_path):
    (tmp_path / "a.md").write_text("# A\n\n## 1. One\n\n**Slow shots** (text)\n\n## 2. Two\n\nx\n", encoding="utf-8")
    text = ('see docs/a.md section 1, "Slow shots"; docs/a.md §2 and `docs/a.md` sections 1 and 2;\n'
            '    docs/a.md\n    section 2 ("Dense\n    sequences")')
    assert citations(text) == [("a.md", 1, ["Slow shots"]), ("a.md", 2, []), ("a.md", 1, []), ("a.md", 2, []),
                               ("a.md", 2, ["Dense\n    sequences"])]
    assert bad_citations(text, tmp_path) == ['docs/a.md section 2, "Dense\n    sequences" (not in that section)']
    assert bad_citations("docs/a.md section 3; docs/b.md", tmp_path) == [
        "docs/b.md (no such document)", "docs/a.md section 3 (it has sections [1, 2])"]


def test_no_code_cites_the_retired_benchmarks_log():
    """The log's content lives on in docs/validation.md and docs/performance.md, by topic; code cites those."""
    citing = [f.relative_to(REPO).as_posix() for f in _code_files() if RETIRED in f.read_text(encoding="utf-8")]
    assert citing == []


def test_every_document_section_the_code_cites_exists():
    """Each 'docs/NAME.md section N' in code names an existing document, one of its numbered ('## N.')
    sections, and, where it quotes a paragraph's title, one that section holds."""
    found, bad = 0, []
    for f in _code_files():
        text = f.read_text(encoding="utf-8")
        found += len(citations(text))
        bad += [f"{f.relative_to(REPO).as_posix()}: {b}" for b in bad_citations(text, REPO / "docs")]
    assert found >= 60  # the reader still reads the code's citations (about 90 when written)
    assert bad == []


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
