"""Code fingerprints that ignore cosmetic edits.

A result key includes a fingerprint of the code that made it, so that a
change in the physics invalidates results.  Numba's own disk cache only
notices edits to the file of the compiled function, not to the modules it
calls, so we fingerprint whole modules and packages ourselves.

The fingerprint is a hash of the module's abstract syntax tree with
docstrings removed: comments, blank lines, formatting and docstrings do not
change it, so fixing a typo in a docstring does not throw away hours of
results.  Line numbers are not part of ``ast.dump`` output by default.
"""

from __future__ import annotations

import ast
import functools
import importlib
import inspect
from pathlib import Path

from .canonical import digest


def _strip_docstrings(tree: ast.AST) -> ast.AST:
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if (
                body
                and isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)
            ):
                node.body = body[1:] or [ast.Pass()]
    return tree


def source_fingerprint(source: str) -> str:
    """Fingerprint of Python source text, blind to comments/docstrings/layout."""
    tree = _strip_docstrings(ast.parse(source))
    return digest(ast.dump(tree, annotate_fields=True, include_attributes=False))


# Fingerprints are cached per file for the life of the process: a long run
# must record the code it has loaded, not an edit made on disk while it runs.
@functools.lru_cache(maxsize=None)
def _file_fingerprint(path: str) -> str:
    return source_fingerprint(Path(path).read_text(encoding="utf-8"))


def file_fingerprint(path: Path) -> str:
    return _file_fingerprint(str(path))


def module_fingerprint(module_name: str) -> str:
    """Fingerprint of a module, or of every ``.py`` file of a package.

    Files are visited in sorted order of their path *relative to the
    package*, so the result does not depend on where the package is
    installed.
    """
    module = importlib.import_module(module_name)
    origin = getattr(module, "__file__", None)
    if origin is None:
        raise ValueError(f"module {module_name!r} has no source file to fingerprint")
    origin_path = Path(origin)
    if origin_path.name == "__init__.py":
        root = origin_path.parent
        parts = []
        for f in sorted(root.rglob("*.py"), key=lambda p: p.relative_to(root).as_posix()):
            parts.append(f"{f.relative_to(root).as_posix()}:{file_fingerprint(f)}")
        return digest("\n".join(parts))
    return file_fingerprint(origin_path)


def _is_task_def(node: ast.AST) -> bool:
    if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
        return False
    for dec in node.decorator_list:
        target = dec.func if isinstance(dec, ast.Call) else dec
        name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
        if name.endswith("task"):
            return True
    return False


@functools.lru_cache(maxsize=None)
def _task_fingerprint(path: str, fn_name: str) -> str:
    tree = _strip_docstrings(ast.parse(Path(path).read_text(encoding="utf-8")))
    # Other tasks of the same module are their own business; helpers, constants
    # and imports count for every task of the module.
    tree.body = [n for n in tree.body if not (_is_task_def(n) and n.name != fn_name)]
    return digest(ast.dump(tree, annotate_fields=True, include_attributes=False))


def function_fingerprint(fn) -> str:
    """Fingerprint of the module defining task function ``fn``, minus its other tasks."""
    module = inspect.getmodule(fn)
    if module is not None and getattr(module, "__file__", None):
        return _task_fingerprint(str(Path(module.__file__)), fn.__name__)
    return source_fingerprint(inspect.getsource(fn))
