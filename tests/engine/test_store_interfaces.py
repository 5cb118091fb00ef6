"""The store owns its layout: no module but peenflow/engine/store.py builds a path inside a store."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: the store's own folders, joined onto a path (``/ "results"``), spelled as a path (``"results/..."``),
#: or its default folder name
LAYOUT = re.compile(r'/\s*"(results|failures|slots|checkpoints|progress|leases|runs|locks|reports)"'
                    r'|"(results|failures|slots|checkpoints|progress|leases|runs|locks|reports)/'
                    r'|"\.peenflow"')


def test_no_module_but_the_store_builds_store_paths():
    offenders = []
    for folder in ("peenflow", "tasks", "benchmarks"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            if path == ROOT / "peenflow" / "engine" / "store.py":
                continue
            for n, line in enumerate(path.read_text().splitlines(), 1):
                if LAYOUT.search(line):
                    offenders.append(f"{path.relative_to(ROOT)}:{n}: {line.strip()}")
    assert not offenders, "ask the store for the location instead:\n" + "\n".join(offenders)


def test_the_rule_finds_a_store_path_built_elsewhere():
    # the pattern is not blind: each way of building one is caught
    for line in ('base = store.root / "progress"', 'store.glob("checkpoints/*/checkpoint.nc")',
                 'study.parent / ".peenflow"', "root / 'x' / \"leases\""):
        assert LAYOUT.search(line), line
    assert not LAYOUT.search('g.add(task, upstream={"runs": runs})')
