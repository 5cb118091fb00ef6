"""One shot sequence on a REV, with a relaxed snapshot at each rung of a shot ladder.

Shared by ``strip_runs`` (the saturation ladder N = 10 ... 480 of §4: one run
per sequence to the largest N, the shots of rung N being the first N to
arrive) and ``target_runs`` (N_c shots on the part's REV, §5).

The run drives the kernel step by step (:class:`peenflow.fe.impact.ImpactRun`):
one impact per shot, and at each rung a snapshot, the state relaxed to rest
on a copy (the run continues from the unrelaxed state), reduced to depth
profiles averaged over the measuring region; a rung's snapshot is the same,
bit for bit, as a separate run of its shots.  The kernel state and the profiles already made are
checkpointed at every rung and every ``PEENFLOW_CHECKPOINT_EVERY_S``
seconds (default 30), so a killed run resumes from its last checkpoint with
the same result it would have had uninterrupted.  When the user stops the run
(Ctrl-C, SIGTERM, SIGHUP) it checkpoints after the current shot and stops.
A checkpoint this run cannot use (another task's, another mesh's, damaged) is
ignored with a note, never a failure.
"""

from __future__ import annotations

import os
import time

import numpy as np
import xarray as xr

from peenflow.methods import VOIGT, average_over_region, doubling_ladder, ladder_verdict, shot_stream

from . import _kernel as K
from ._common import COMPONENT_LONG_NAME, depth, labels, var
from .arc_height import release
from .outputs import Output, Outputs
from .params import FidelityParams, LadderParams, MaterialParams, ShotParams, StreamParams
from .saturation import MODELS

CHECKPOINT_EVERY_S = float(os.environ.get("PEENFLOW_CHECKPOINT_EVERY_S", "30"))

#: what a REV run gives (``strip_runs`` as it is; ``target_runs`` derives its own from it)
RUN = Outputs(
    "rev_run",
    stress_mean_Pa=Output(("shots", "layer", "component"), "Pa", "residual stress averaged over the measuring region"),
    stress_spread_Pa=Output(("shots", "layer", "component"), "Pa", "lateral std over the region"),
    stress_xx_Pa=Output(("shots", "layer"), "Pa", "sigma_xx profile"),
    stress_yy_Pa=Output(("shots", "layer"), "Pa", "sigma_yy profile"),
    plastic_strain_mean=Output(("shots", "layer"), "1", "equivalent plastic strain averaged over the measuring region"),
    restitution=Output(("impact",), "1", "coefficient of restitution per impact, in arrival order"),
    peak_force_N=Output(("impact",), "N", "peak contact force per impact"),
    energy_error=Output(("impact",), "1", "energy balance error / impact energy"),
    hourglass_peak=Output(("impact",), "1", "peak hourglass energy of the impact / impact energy (large on a mesh "
                                            "too coarse for the dent)"),
    ladder_saturated=Output((), "1", "1 if the ladder stopped with eq. (11)'s point T inside its data (a rung at "
                                     ">= 2 T), 0 if it stopped at almen.max_shots or T fell below the first rung",
                            optional=True,
                            attrs={"flag_values": np.array([0, 1]), "flag_meanings": "not_saturated saturated"}),
    ladder_saturation_shots=Output((), "1", "saturation point T of this sequence's own rungs, the stop rule's",
                                   optional=True),
    hit_fraction=Output((), "1", "fraction of shots that touched the REV"),
    shot_diameter_m=Output(("impact",), "m", "diameter of each shot, in arrival order (the nominal one without "
                                             "shot.diameter_spread_percent)"),
    impact_speed_m_s=Output(("impact",), "m s-1", "speed of each shot before its impact, in arrival order"),
)


def run_rev(ctx, *, material: MaterialParams, shot: ShotParams, fidelity: FidelityParams, side_m: float,
            measure_side_m: float, thickness_m: float, angle_deg: float, velocity_m_s: float, seed: int,
            ladder: list, extend: LadderParams | None = None, sequence_shots: int | None = None,
            stream: StreamParams | None = None) -> xr.Dataset:
    """The run (module docstring); ``ladder``: the rungs, or with ``extend`` ignored.

    ``sequence_shots``: the length of the sequence the shots are drawn from (default: the last rung). A
    longer sequence run only to the last rung is that sequence stopped there: its rungs are the ones a
    run through the whole sequence snapshots (the first n arrivals of one stream,
    :mod:`peenflow.methods.shot_stream`).

    ``stream``: the shots' size and speed spreads (None: every shot nominal).

    ``extend`` (a strip ladder that extends itself, ``almen.shot_counts = "auto"``):
    its first and largest shot counts, the saturation fit (``almen.saturation_fit``)
    and the strip the arc heights are computed for.  The rungs are then the doubling
    ladder first ... max_shots (the shot stream drawn for max_shots), and the
    run stops after the first rung at which :func:`ladder_verdict` on its own
    arc heights says stop.  The result then holds only the rungs run, and
    ``ladder_saturated`` / ``ladder_saturation_shots`` say how it ended.
    """
    ladder = list(doubling_ladder(extend.first_shots, extend.max_shots)) if extend else \
        sorted(int(n) for n in ladder)
    mesh = K.rev_mesh(fidelity, side_m, thickness_m)
    centroids = mesh.element_centroids()
    z_edges = mesh.z
    half = 0.5 * side_m
    region = (-0.5 * measure_side_m, 0.5 * measure_side_m, -0.5 * measure_side_m, 0.5 * measure_side_m)
    spreads_of = {} if stream is None else {"diameter_spread": stream.diameter_spread,
                                            "velocity_spread": stream.velocity_spread}
    shots_all = shot_stream(max(ladder[-1], sequence_shots or 0), shot.radius_m, half, half, angle_deg, velocity_m_s,
                            seed, **spreads_of)
    target = fidelity.boundary(mesh)
    material_k = material.to_kernel()
    options = fidelity.options(shot, ctx.threads if ctx else 1)
    nz = len(z_edges) - 1

    means: dict[int, np.ndarray] = {}
    spreads: dict[int, np.ndarray] = {}
    plastic: dict[int, np.ndarray] = {}
    state = None
    if ctx is not None and (ck := ctx.load_checkpoint()) is not None:
        problem = _unusable(ck, mesh, nz, ladder[-1])
        if problem:
            ctx.discard_checkpoint(problem)
        else:
            state = K.state_from_dataset(ck)
            for k, n in enumerate(ck.rung.values.tolist()):
                means[n], spreads[n], plastic[n] = (ck.rung_mean.values[k], ck.rung_spread.values[k],
                                                    ck.rung_plastic.values[k])

    def checkpoint(state_dict):
        rungs = sorted(means)
        extra = {
            "rung": (("rung",), np.array(rungs, dtype=np.int64)),
            "rung_mean": (("rung", "layer", "component"), np.array([means[n] for n in rungs]).reshape(-1, nz, 6)),
            "rung_spread": (("rung", "layer", "component"), np.array([spreads[n] for n in rungs]).reshape(-1, nz, 6)),
            "rung_plastic": (("rung", "layer"), np.array([plastic[n] for n in rungs]).reshape(-1, nz)),
        }
        ctx.save_checkpoint(K.state_to_dataset(state_dict, **extra))

    impacts = K.ImpactRun(target, material_k, options, state=state)
    last_save = [time.time()]

    # the shots the run is expected to need, for its progress and ETA: the ladder's end, or for a
    # self-extending ladder (a cap, not a plan) the first rung at >= 2 T of the fit to the rungs so far
    planned = [ladder[0] if extend else ladder[-1]]

    def shot_done(i):
        if ctx is None:
            return
        note = f"ladder expected to stop at {planned[0]} of at most {ladder[-1]}" if extend else ""
        ctx.progress(i + 1, planned[0], "shots", note)
        if ctx.stop_requested:
            checkpoint(impacts.checkpoint())
            ctx.stop(f"after shot {i + 1} of {ladder[-1]}")
        if time.time() - last_save[0] > CHECKPOINT_EVERY_S:
            checkpoint(impacts.checkpoint())
            last_save[0] = time.time()

    verdict = None
    run = []  # the rungs of the result: the whole ladder, or up to the rung that stopped it
    for n in ladder:
        run.append(n)
        if n not in means:
            # the rung's shots are the first n of the stream; they scale its relaxation's rest
            # criteria, as for a run of exactly these shots
            shots = shot.shots(shots_all.centres[:n], shots_all.velocities[:n],
                               shots_all.radii[:n] if shots_all.spread else None)
            with K.in_study_terms():
                for i in range(impacts.shots_done, n):
                    impacts.impact(shots, i)
                    shot_done(i)
                snap = impacts.snapshot(shots, where=f"relaxation of the rung at {n} shots")
            avg = average_over_region(centroids, snap.stress, z_edges, region)
            pavg = average_over_region(centroids, np.repeat(snap.eps_p[:, None], 6, axis=1), z_edges, region)
            means[n], spreads[n], plastic[n] = avg.mean, avg.std, pavg.mean[:, 0]
            if ctx is not None:
                checkpoint(impacts.checkpoint())
                last_save[0] = time.time()
        if extend:
            verdict = _verdict(means, run, z_edges, extend)
            if verdict.stop:
                break
            planned[0] = expected_end(ladder, n, verdict.saturation_shots)
    records = impacts.records  # named fields (peenflow.fe.records.ShotRecord)

    ladder_vars = {}
    if extend:
        ladder_vars = {"ladder_saturated": int(verdict.saturated),
                       "ladder_saturation_shots": verdict.saturation_shots}
        stop_reason = {"ladder_stop_reason": verdict.reason if verdict.stop else
                       f"stopped at the cap almen.max_shots = {run[-1]}: {verdict.reason}"}
    else:
        stop_reason = {}
    mean = np.array([means[n] for n in run])
    spread = np.array([spreads[n] for n in run])
    hit = records["hit"]
    return RUN.dataset(
        {"stress_mean_Pa": mean, "stress_spread_Pa": spread, "stress_xx_Pa": mean[:, :, 0],
         "stress_yy_Pa": mean[:, :, 1], "plastic_strain_mean": np.array([plastic[n] for n in run]),
         "restitution": records["restitution"], "peak_force_N": records["peak_force"],
         "energy_error": records["energy_error"], "hourglass_peak": records["hourglass_peak"], **ladder_vars,
         "hit_fraction": float(hit.mean()) if hit.size else 0.0,
         "shot_diameter_m": 2.0 * shots_all.radii[:hit.size],
         "impact_speed_m_s": np.sqrt(records["vin_x"] ** 2 + records["vin_y"] ** 2 + records["vin_z"] ** 2)},
        coords={"shots": var(np.array(run), ("shots",), "1", "number of shots N (rung of the ladder)"),
                "component": labels(VOIGT, "component", COMPONENT_LONG_NAME),
                "z_edge_m": depth(z_edges, "z_edge", "layer boundary depth below the peened surface"),
                "depth_m": depth(0.5 * (z_edges[1:] + z_edges[:-1]), "layer", "layer mid-depth below the peened surface"),
                "impact": var(np.arange(records["restitution"].size), ("impact",), "1", "impact number in arrival order")},
        attrs={"rev_side_m": side_m, "measure_side_m": measure_side_m, "thickness_m": thickness_m,
               "n_elements": int(mesh.n_elements), "seed": int(seed), **stop_reason},
    )


def expected_end(ladder: list, done: int, saturation_shots: float) -> int:
    """The rung a self-extending ladder is expected to stop at, after rung ``done``: the first at >= 2 T
    (eq. 11's saturation point T of the fit so far), at least the next rung; the next rung while T is
    unknown (NaN: fewer than 3 rungs, or no fit yet); the last rung when T lies beyond the ladder."""
    later = [n for n in ladder if n > done]
    if not later:
        return done
    if not np.isfinite(saturation_shots):
        return later[0]
    return next((n for n in later if n >= 2.0 * saturation_shots), ladder[-1])


_CHECKPOINT_VARS = ("rung", "rung_mean", "rung_spread", "rung_plastic", "kernel__x", "kernel__shot_index")


def _unusable(ck: xr.Dataset, mesh, nz: int, last: int) -> str:
    """Why checkpoint ``ck`` cannot resume this REV run ("" if it can)."""
    missing = [v for v in _CHECKPOINT_VARS if v not in ck.variables]
    if missing:
        return f"it lacks {', '.join(missing)}: written by another task"
    if problem := K.checkpoint_problem(ck):
        return problem
    if ck["kernel__x"].shape != (mesh.n_nodes, 3):
        return f"its state has {ck['kernel__x'].shape[0]} nodes, this REV {mesh.n_nodes}"
    if ck["rung_mean"].shape[1:] != (nz, 6):
        return f"its profiles have {ck['rung_mean'].shape[1]} layers, this REV {nz}"
    done = int(np.asarray(ck["kernel__shot_index"].values).ravel()[0])
    if not 0 <= done <= last:
        return f"it is at shot {done}, beyond this run's {last}"
    return ""


def _verdict(means: dict, rungs: list, z_edges, extend: LadderParams):
    """The stop rule on the rungs run so far: their arc heights (eqs. 6-9, as the
    ``arc_height`` stage computes them) and a saturation fit (``almen.saturation_fit``)."""
    ah = [release(z_edges, means[n][:, 0], extend.strip)[0] for n in rungs]
    return ladder_verdict(rungs, ah, MODELS[extend.fit])
