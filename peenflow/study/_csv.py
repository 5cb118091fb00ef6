"""Reading the CSV files a study may name: ``#`` lines and blank lines are comments."""

from __future__ import annotations

import csv
from pathlib import Path


class CsvFileError(ValueError):
    """A CSV that cannot be used; ``problems`` lists each reason (with line numbers)."""

    def __init__(self, problems: list[str]):
        super().__init__("; ".join(problems))
        self.problems = problems


def read_commented_csv(path: Path, error: type[CsvFileError],
                       expected: str) -> tuple[bytes, list[tuple[int, list[str]]]]:
    """(the file's bytes, [(line number, cells), ...]) of the rows that are not comments, the
    header row first. A file that is not UTF-8, or has no header row, raises ``error(problems)``;
    ``expected`` says what the header should name."""
    path = Path(path)
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise error([f"{path.name} is not a UTF-8 text file ({exc.reason} at byte {exc.start})"]) from None
    lines = [(n, line) for n, line in enumerate(text.splitlines(), start=1)
             if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise error([f"{path.name} has no header row; expected {expected}"])
    return raw, list(zip((n for n, _ in lines), csv.reader(line for _, line in lines)))
