"""The layout of the code: no import circles, the layers import downwards only, and a long file says why."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("peenflow", "tasks")


def _modules() -> dict[str, Path]:
    out = {}
    for pkg in PACKAGES:
        for f in (ROOT / pkg).rglob("*.py"):
            parts = f.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            out[name] = f
    return out


def _imports(name: str, path: Path, known: set[str]) -> set[str]:
    """Modules of ours that ``name`` imports anywhere in its source (functions included)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            stems = [a.name for a in node.names]
            subs = []
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)] if node.level > 1 else base
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module or ""
            stems = [stem]
            subs = [f"{stem}.{a.name}" for a in node.names]
        else:
            continue
        for m in subs:
            if m in known:
                out.add(m)
        for m in stems:
            if m in known and not any(s in known for s in subs):
                out.add(m)
    out.discard(name)
    return out


def _graph() -> dict[str, set[str]]:
    modules = _modules()
    known = set(modules)
    return {n: _imports(n, p, known) for n, p in modules.items()}


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan); a package importing its own
    submodules in its ``__init__`` while they import each other is not a circle of theirs, so
    ``__init__`` edges down into the package are left out."""
    edges = {n: {d for d in deps if not d.startswith(n + ".")} for n, deps in graph.items()}
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def test_no_import_circles():
    assert _cycles(_graph()) == []


def test_the_cycle_finder_finds_one():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_layers_import_downwards():
    """The kernel imports nothing of ours but itself and its compile settings; the engine nothing of shot
    peening; the study package neither the stages nor the engine."""
    graph = _graph()
    rules = {
        "peenflow.fe": ("peenflow.fe", "peenflow._jit"),
        "peenflow.methods": ("peenflow.methods", "peenflow.fe", "peenflow._jit"),
        # the engine: itself, the TOML reader, and the package's version for provenance
        "peenflow.engine": ("peenflow.engine", "peenflow._toml", "peenflow"),
        # the study: itself, units, and the engine's canonical form of values (one serialisation of a key)
        "peenflow.study": ("peenflow.study", "peenflow._toml", "peenflow.units", "peenflow.engine.canonical"),
    }
    bad = []
    for layer, allowed in rules.items():
        for name, deps in graph.items():
            if name == layer or name.startswith(layer + "."):
                bad += [f"{name} -> {d}" for d in deps
                        if not any(d == a or (a != "peenflow" and d.startswith(a + ".")) for a in allowed)]
    assert bad == []


#: a Python file of more lines than this says why in its module docstring, on a line that starts "Length:"
MAX_LINES = 600
#: where the rule holds: the package, the stages and the benchmarks (tests are not held to it)
LENGTH_ROOTS = ("peenflow", "tasks", "benchmarks")
#: a reason is a sentence, not a word
MIN_REASON_WORDS = 8


def _length_reason(source: str) -> str | None:
    """The 'Length:' paragraph of a module's docstring (up to the next blank line), or None."""
    doc = ast.get_docstring(ast.parse(source)) or ""
    m = re.search(r"^Length:(.*?)(?:\n\s*\n|\Z)", doc, re.M | re.S)
    return " ".join(m.group(1).split()) if m else None


def _length_problems(files) -> list[str]:
    out = []
    for f in files:
        source = f.read_text(encoding="utf-8")
        lines = len(source.splitlines())
        reason = _length_reason(source)
        name = f.relative_to(ROOT).as_posix() if f.is_relative_to(ROOT) else f.name
        if lines > MAX_LINES and (reason is None or len(reason.split()) < MIN_REASON_WORDS):
            out.append(f"{name}: {lines} lines and no 'Length:' reason in its docstring")
        elif lines <= MAX_LINES and reason is not None:
            out.append(f"{name}: {lines} lines, yet its docstring says why it is long")
    return out


def test_a_python_file_over_600_lines_says_why():
    """Small modules with one job each: a file over MAX_LINES either is one cohesive thing and says so in its
    module docstring ('Length: ...'), or is split; a reason left in a file that has shrunk is stale."""
    files = [f for root in LENGTH_ROOTS for f in sorted((ROOT / root).rglob("*.py")) if "__pycache__" not in f.parts]
    assert len(files) > 100
    assert _length_problems(files) == []


def test_the_length_rule_finds_a_long_file_without_a_reason(tmp_path):
    body = "x = 1\n" * MAX_LINES
    cases = {"bare.py": '"""A module."""\n' + body,
             "terse.py": '"""A module.\n\nLength: because.\n"""\n' + body,
             "stated.py": '"""A module.\n\nLength: one pipeline in one class whose steps share the\nproblems collected so far.\n\nMore.\n"""\n' + body,
             "stale.py": '"""A module.\n\nLength: one pipeline in one class whose steps share the problems collected.\n"""\nx = 1\n'}
    for name, text in cases.items():
        (tmp_path / name).write_text(text)
    assert _length_reason(cases["stated.py"]) == "one pipeline in one class whose steps share the problems collected so far."
    n = {name: len(text.splitlines()) for name, text in cases.items()}
    assert _length_problems(sorted(tmp_path.glob("*.py"))) == [
        f"bare.py: {n['bare.py']} lines and no 'Length:' reason in its docstring",
        f"stale.py: {n['stale.py']} lines, yet its docstring says why it is long",
        f"terse.py: {n['terse.py']} lines and no 'Length:' reason in its docstring"]
