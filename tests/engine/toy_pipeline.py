"""A small, generic pipeline for the engine's tests (no physics).

source(n) -> scale[factor] (swept) -> total (combined over factor)
counter(steps): a long task that checkpoints after every step.
probe: a sweep of points, then one lone point after them, that record the compute
threads they were given and the threads in use meanwhile (``build_probe``).
"""

from __future__ import annotations

import os
import threading
import time
import tomllib

import numpy as np
import xarray as xr

from peenflow.engine import Graph, task


def _log(event: str, what) -> None:
    """Append to $TOY_LOG (if set): lets tests see who computed what, when."""
    path = os.environ.get("TOY_LOG")
    if path:
        with open(path, "a") as f:  # O_APPEND: lines from several processes do not interleave
            f.write(f"{event} {what} {os.getpid()} {time.time():.6f}\n")


@task()
def source(*, n: int, delay_s: float = 0.0) -> xr.Dataset:
    time.sleep(delay_s)
    x = np.arange(n, dtype=float)
    return xr.Dataset({"value": ("i", x ** 2)}, coords={"i": x}, attrs={"description": "squares"})


@task(version="1")
def scale(src: xr.Dataset, *, factor: float, delay_s: float = 0.0) -> xr.Dataset:
    _log("start", factor)
    time.sleep(delay_s)
    # An outside condition (not a parameter), like a node running out of memory.
    if str(factor) == os.environ.get("TOY_FAIL_FACTOR"):
        raise RuntimeError(f"factor {factor} fails on purpose")
    _log("scale", factor)
    return xr.Dataset({"scaled": src.value * factor})


@task()
def total(scaled: xr.Dataset) -> xr.Dataset:
    return xr.Dataset({"total": scaled.scaled.sum("i")})


@task()
def counter(*, steps: int, delay_s: float = 0.0, ctx) -> xr.Dataset:
    state = ctx.load_checkpoint()
    start = int(state.step) if state is not None else 0
    acc = float(state.acc) if state is not None else 0.0
    for k in range(start, steps):
        time.sleep(delay_s)
        acc += k
        ctx.save_checkpoint(xr.Dataset({"step": ((), k + 1), "acc": ((), acc)}))
        ctx.progress(k + 1, steps, "steps")
        if ctx.stop_requested:  # a checkpoint is saved: stop here (Ctrl-C, SIGTERM, SIGHUP)
            ctx.stop(f"after step {k + 1} of {steps}")
    return xr.Dataset({"acc": ((), acc), "started_at_step": ((), start)})


def build(path) -> Graph:
    with open(path, "rb") as f:
        cfg = tomllib.load(f)
    toy = cfg["toy"]
    g = Graph(cfg["study"]["name"])
    src = g.add(source, params={"n": toy["n"], "delay_s": toy.get("source_delay_s", 0.0)})
    scaled = g.sweep(scale, dims={"factor": toy["factors"]}, upstream={"src": src},
                     params={"delay_s": toy.get("delay_s", 0.0)})
    g.add(total, upstream={"scaled": scaled})
    g.add(counter, params={"steps": toy.get("steps", 3), "delay_s": toy.get("counter_delay_s", 0.0)})
    return g


# Threads granted to the probe points now running in this process.
_in_use = {"now": 0, "peak": 0}
_in_use_lock = threading.Lock()


@task()
def probe(after: xr.Dataset | None = None, *, member: int, hold_s: float, ctx) -> xr.Dataset:
    threads = ctx.threads  # may wait for the budget: never while holding our lock
    with _in_use_lock:
        _in_use["now"] += threads
        _in_use["peak"] = max(_in_use["peak"], _in_use["now"])
    time.sleep(hold_s)
    with _in_use_lock:
        peak = _in_use["peak"]
        _in_use["now"] -= threads
    return xr.Dataset({"threads": ((), threads), "peak_threads_in_use": ((), peak)})


def build_probe(path) -> Graph:
    with open(path, "rb") as f:
        cfg = tomllib.load(f)
    toy = cfg["toy"]
    g = Graph(cfg["study"]["name"])
    wide = g.sweep(probe, dims={"member": list(range(toy["members"]))}, stage="wide",
                   params={"hold_s": toy["hold_s"]})
    g.add(probe, stage="lone", upstream={"after": wide} if toy.get("lone_after_wide", True) else {},
          params={"member": -1, "hold_s": toy["hold_s"]})
    return g
