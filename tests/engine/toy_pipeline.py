"""A small, generic pipeline for the engine's tests (no physics).

source(n) -> scale[factor] (swept) -> total (combined over factor)
counter(steps): a long task that checkpoints after every step (``lanes = N``: instead, a sweep of N
lane_counter points that log each step to $TOY_LOG and store only their sum, the same whether resumed or not).
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


def _count(ctx, steps: int, delay_s: float, lane: int = 0) -> tuple[float, int]:
    """Add up 0..steps-1, a checkpoint after every step; returns (the sum, the step it started at)."""
    state = ctx.load_checkpoint()
    start = int(state.step) if state is not None else 0
    acc = float(state.acc) if state is not None else 0.0
    for k in range(start, steps):
        time.sleep(delay_s)
        acc += k
        ctx.progress(k + 1, steps, "steps")  # before the checkpoint: its position is the last progress
        ctx.save_checkpoint(xr.Dataset({"step": ((), k + 1), "acc": ((), acc)}))
        _log("step", f"{lane}/{k}")
        if ctx.stop_requested:  # a checkpoint is saved: stop here (Ctrl-C, SIGTERM, SIGHUP)
            ctx.stop(f"after step {k + 1} of {steps}")
    return acc, start


@task()
def counter(*, steps: int, delay_s: float = 0.0, ctx) -> xr.Dataset:
    acc, start = _count(ctx, steps, delay_s)
    return xr.Dataset({"acc": ((), acc), "started_at_step": ((), start)})


@task()
def lane_counter(*, lane: int, steps: int, delay_s: float = 0.0, ctx) -> xr.Dataset:
    acc, _ = _count(ctx, steps, delay_s, lane)
    return xr.Dataset({"acc": ((), acc)})


def build(path) -> Graph:
    with open(path, "rb") as f:
        cfg = tomllib.load(f)
    toy = cfg["toy"]
    g = Graph(cfg["study"]["name"])
    src = g.add(source, params={"n": toy["n"], "delay_s": toy.get("source_delay_s", 0.0)})
    scaled = g.sweep(scale, dims={"factor": toy["factors"]}, upstream={"src": src},
                     params={"delay_s": toy.get("delay_s", 0.0)})
    g.add(total, upstream={"scaled": scaled})
    counting = {"steps": toy.get("steps", 3), "delay_s": toy.get("counter_delay_s", 0.0)}
    if "lanes" in toy:
        g.sweep(lane_counter, dims={"lane": list(range(toy["lanes"]))}, params=counting)
    else:
        g.add(counter, params=counting)
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


@task()
def draw(*, factor: float, rep: int) -> xr.Dataset:
    """One 'repetition' of a factor: the value factor * (rep + 1)."""
    _log("draw", f"{factor}/{rep}")
    if f"{factor}/{rep}" == os.environ.get("TOY_FAIL_DRAW"):
        raise RuntimeError(f"draw {factor}/{rep} fails on purpose")
    return xr.Dataset({"value": ((), float(factor) * (rep + 1))})


@task()
def pooled(draws: xr.Dataset, *, factor: float) -> xr.Dataset:
    """Everything a factor's repetitions add up to (consumes the whole grown group)."""
    _log("pooled", int(draws.sizes["rep"]))
    return xr.Dataset({"sum": draws.value.sum("rep"), "reps": ((), int(draws.sizes["rep"]))})


def build_growing(path) -> Graph:
    """draw[factor, rep] grows in rep until the group's values add up to ``target``
    (at most ``max_reps``); pooled[factor] sums each factor's group."""
    from peenflow.engine.growth import Grow, GrowVerdict

    with open(path, "rb") as f:
        cfg = tomllib.load(f)
    toy = cfg["toy"]

    def until(datasets, coords):
        s = sum(float(d.value) for d in datasets)
        return GrowVerdict(s < toy["target"], f"sum {s:g} against {toy['target']:g}")

    g = Graph(cfg["study"]["name"])
    draws = g.sweep(draw, dims={"factor": toy["factors"], "rep": list(range(toy["max_reps"]))},
                    grow=Grow("rep", toy.get("start", 1), until))
    g.sweep(pooled, dims={"factor": toy["factors"]}, upstream={"draws": draws})
    return g
