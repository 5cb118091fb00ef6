"""Code fingerprints that ignore cosmetic edits.

A result key includes a fingerprint of the code that made it, so that a
change in the physics invalidates results.  Numba's own disk cache only
notices edits to the file of the compiled function, not to the modules it
calls, so we fingerprint whole modules and packages ourselves.

The fingerprint is a hash of the module's abstract syntax tree with
docstrings removed: comments, blank lines, formatting and docstrings do not
change it, so fixing a typo in a docstring does not throw away hours of
results.  Line numbers are not part of ``ast.dump`` output by default.

A task's code is its own module (less its other tasks) plus every module of
its own top-level package that it imports, directly or through another such
module (:func:`local_imports`): a helper module shared by two stages, or a
stage module another stage imports, is part of both stages' code.  Modules
outside that package enter only when the task declares them (``uses``) --
together with every module of the used package's own top-level package that
it imports (:func:`used_closure`: a kernel package's compile settings in a
sibling module are the kernel's code too) -- so an edit to the engine or to a
third-party library invalidates nothing.
"""

from __future__ import annotations

import ast
import functools
import importlib
import importlib.util
import inspect
import threading
from pathlib import Path

from .canonical import digest


# CPython 3.11 keeps the AST constructor's recursion depth in one state per
# interpreter, not per thread: two threads parsing at once (tasks of a
# dask.distributed worker fingerprinting their code) can fail with
# "SystemError: AST constructor recursion depth mismatch" (python/cpython
# gh-106905).  Parsing under one lock is cheap: fingerprints are cached per file.
_PARSE_LOCK = threading.Lock()


def parse(source: str) -> ast.AST:
    """``ast.parse(source)``, one thread at a time."""
    with _PARSE_LOCK:
        return ast.parse(source)


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
    tree = _strip_docstrings(parse(source))
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


def _imported_modules(tree: ast.AST, module_name: str, is_package: bool) -> set[str]:
    """Absolute names of the modules an AST imports: ``from X import y`` gives
    ``X.y`` when ``y`` is a submodule, else ``X`` (where ``y`` is defined)."""
    package = module_name if is_package else module_name.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)] if node.level > 1 else base
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module or ""
            if stem:
                subs = {f"{stem}.{a.name}" for a in node.names if a.name != "*"}
                modules = {m for m in subs if _is_module(m)}
                out.update(modules)
                if modules != subs or not subs:  # a name defined in ``stem`` itself
                    out.add(stem)
    return out


def _is_module(name: str) -> bool:
    try:
        return _module_file(name) is not None
    except (ModuleNotFoundError, ValueError):
        return False


@functools.lru_cache(maxsize=None)
def _module_file(module_name: str) -> str | None:
    spec = importlib.util.find_spec(module_name)
    if spec is None or not spec.origin or not spec.origin.endswith(".py"):
        return None
    return spec.origin


@functools.lru_cache(maxsize=None)
def local_imports(module_name: str) -> tuple[str, ...]:
    """Modules of ``module_name``'s own top-level package that it imports,
    directly or transitively (sorted, itself excluded)."""
    top = module_name.partition(".")[0]
    seen = {module_name}
    todo = [module_name]
    while todo:
        name = todo.pop()
        path = _module_file(name)
        if path is None:
            continue
        tree = parse(Path(path).read_text(encoding="utf-8"))
        for dep in _imported_modules(tree, name, Path(path).name == "__init__.py"):
            if dep.partition(".")[0] != top or dep in seen:
                continue
            if _is_module(dep):
                seen.add(dep)
                todo.append(dep)
    seen.discard(module_name)
    return tuple(sorted(seen))


@functools.lru_cache(maxsize=None)
def used_closure(module_name: str) -> tuple[str, ...]:
    """The modules of ``module_name``'s top-level package that ``module_name`` -- a module, or every
    module of a package -- imports, directly or transitively, outside ``module_name`` itself (sorted).

    ``uses=("peenflow.fe",)`` fingerprints the kernel package; the kernel's modules import
    ``peenflow._jit`` (how every kernel function is compiled), which is then part of the kernel's code.
    """
    top = module_name.partition(".")[0]
    origin = _module_file(module_name)
    if origin is None:
        return ()
    if Path(origin).name == "__init__.py":
        root = Path(origin).parent
        members = {module_name + "".join("." + part for part in f.relative_to(root).with_suffix("").parts)
                   for f in root.rglob("*.py")}
        members = {m[: -len(".__init__")] if m.endswith(".__init__") else m for m in members}
    else:
        members = {module_name}
    inside = lambda m: m == module_name or m.startswith(module_name + ".")  # noqa: E731
    seen, todo, out = set(members), list(members), set()
    while todo:
        name = todo.pop()
        path = _module_file(name)
        if path is None:
            continue
        tree = parse(Path(path).read_text(encoding="utf-8"))
        for dep in _imported_modules(tree, name, Path(path).name == "__init__.py"):
            if dep.partition(".")[0] != top or dep in seen or not _is_module(dep):
                continue
            seen.add(dep)
            todo.append(dep)
            if not inside(dep):
                out.add(dep)
    return tuple(sorted(out))


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
    tree = _strip_docstrings(parse(Path(path).read_text(encoding="utf-8")))
    # Other tasks of the same module are their own business; helpers, constants
    # and imports count for every task of the module.
    tree.body = [n for n in tree.body if not (_is_task_def(n) and n.name != fn_name)]
    return digest(ast.dump(tree, annotate_fields=True, include_attributes=False))


def clear_fingerprint_cache() -> None:
    """Forget every cached fingerprint and import closure, so that edits made on
    disk since they were taken are seen (tests; a long-lived client)."""
    for cached in (_file_fingerprint, _task_fingerprint, local_imports, used_closure, _module_file):
        cached.cache_clear()


def function_fingerprint(fn) -> str:
    """Fingerprint of the module defining task function ``fn``, minus its other tasks."""
    module = inspect.getmodule(fn)
    if module is not None and getattr(module, "__file__", None):
        return _task_fingerprint(str(Path(module.__file__)), fn.__name__)
    return source_fingerprint(inspect.getsource(fn))
