"""Declaring tasks.

A task is a pure function of its parameters and its upstream results that
returns an :class:`xarray.Dataset`::

    @task(version="2", uses=("mypkg.kernel",))
    def indentation(impact: xr.Dataset, *, level: float, ctx: TaskContext) -> xr.Dataset:
        ...

* keyword arguments that receive upstream results are named in the graph
  (``graph.add(indentation, upstream={"impact": node})``); all other keyword
  arguments are parameters;
* ``ctx`` (optional) gives progress reporting and checkpoints;
* ``version``: when given, the result key uses it instead of the code
  fingerprint, so the author decides when a change invalidates results;
  ``status`` then flags results whose code changed under the same version
  as *stale*;
* ``uses``: modules/packages whose source also enters the code fingerprint
  (the kernel a task calls) with what they import from their own top-level
  package, on top of the task's own module and the modules of its own
  package that it imports (followed transitively);
* typed parameters: a parameter whose annotation is a class with
  ``__canonical__()`` and ``from_canonical(value)`` (``X`` or ``X | None``)
  enters the key as its canonical form and reaches the task rebuilt from
  it (:meth:`Task.bind`), so the task sees exactly what the key holds.
"""

from __future__ import annotations

import importlib
import inspect
import types
import typing
from dataclasses import dataclass, field
from typing import Callable

from .canonical import digest
from .fingerprint import function_fingerprint, local_imports, module_fingerprint, used_closure


@dataclass(frozen=True)
class Task:
    """A registered task: the function plus how its code is identified."""

    fn: Callable
    name: str
    version: str | None = None
    uses: tuple[str, ...] = ()
    wants_ctx: bool = field(default=False)

    @property
    def module(self) -> str:
        return self.fn.__module__

    @property
    def qualname(self) -> str:
        return self.fn.__qualname__

    def source_hash(self) -> str:
        """Fingerprint of the task's module, the modules of its own package it
        imports (transitively), and every module it declares it uses."""
        parts = [f"task:{function_fingerprint(self.fn)}"]
        parts += [f"{m}:{module_fingerprint(m)}" for m in local_imports(self.module)]
        parts += [f"{m}:{module_fingerprint(m)}" for m in sorted(self.uses)]
        # what the used packages import from their own top-level package (the kernel's compile settings)
        extra = sorted({d for m in self.uses for d in used_closure(m)} - set(self.uses) - set(local_imports(self.module)))
        parts += [f"{m}:{module_fingerprint(m)}" for m in extra]
        return digest("\n".join(parts))

    def code_id(self) -> str:
        """What enters the result key for the code: the version if declared."""
        return f"version:{self.version}" if self.version is not None else f"source:{self.source_hash()}"

    def typed_params(self) -> dict:
        """{parameter name: its typed-parameter class} (module docstring)."""
        hints = typing.get_type_hints(self.fn)
        out = {}
        for name, hint in hints.items():
            members = typing.get_args(hint) if isinstance(hint, types.UnionType) or \
                typing.get_origin(hint) is typing.Union else (hint,)
            for t in members:
                if isinstance(t, type) and callable(getattr(t, "from_canonical", None)):
                    out[name] = t
        return out

    def bind(self, params: dict) -> dict:
        """The keyword arguments for ``params`` in canonical form: typed parameters rebuilt."""
        typed = self.typed_params()
        return {k: (typed[k].from_canonical(v) if k in typed and v is not None else v) for k, v in params.items()}

    def __call__(self, *args, **kwargs):
        return self.fn(*args, **kwargs)


def task(name: str | None = None, *, version: str | int | None = None, uses: tuple[str, ...] = ()):
    """Decorator turning a function into a :class:`Task`."""

    def wrap(fn: Callable) -> Task:
        sig = inspect.signature(fn)
        return Task(
            fn=fn,
            name=name or fn.__name__,
            version=None if version is None else str(version),
            uses=tuple(uses),
            wants_ctx="ctx" in sig.parameters,
        )

    if callable(name):  # bare @task
        fn, name = name, None
        return wrap(fn)
    return wrap


def resolve_task(module: str, qualname: str) -> Task:
    """Find a task by import path (used on dask workers, which receive names)."""
    obj = importlib.import_module(module)
    for part in qualname.split("."):
        obj = getattr(obj, part)
    if not isinstance(obj, Task):
        raise TypeError(f"{module}.{qualname} is not a peenflow task")
    return obj
