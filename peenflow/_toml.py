"""Reading TOML with messages that name the file, and the key where tomllib names only a position."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

_POSITION = re.compile(r"\(at line (\d+), column (\d+)\)")


class TomlFileError(ValueError):
    """A TOML file that cannot be read or parsed; the message names the file (and the key, if known)."""


def load_toml(path: Path) -> dict:
    """``tomllib.load`` of ``path``; a directory, binary data or a syntax error raise TomlFileError."""
    path = Path(path)
    if path.is_dir():
        raise TomlFileError(f"{path} is a directory; expected a study file (TOML)")
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except UnicodeDecodeError as exc:
        raise TomlFileError(f"{path}: not a text TOML file (byte {exc.start} is not UTF-8)") from None
    except tomllib.TOMLDecodeError as exc:
        raise TomlFileError(f"{path}: not valid TOML: {describe_toml_error(path, exc)}") from None


def describe_toml_error(path: Path, exc: tomllib.TOMLDecodeError) -> str:
    """tomllib's message, plus the key for "Cannot overwrite a value" (a key given twice)."""
    text = str(exc)
    m = _POSITION.search(text)
    if m is None or "overwrite" not in text:
        return text
    try:
        line = Path(path).read_text(encoding="utf-8").splitlines()[int(m.group(1)) - 1]
    except (OSError, IndexError, UnicodeDecodeError):
        return text
    key = line.split("=", 1)[0].strip()
    return f"key {key!r} is given twice ({text})" if key else text
