"""peenflow.fe -- the numba explicit FE/DEM shot-impact kernel (SI units, arrays in, arrays out).

Public API::

    from peenflow.fe import (run_impacts, Options, Target, Material, Shots,
                             graded_box, graded_axis, box_mesh, BoxMesh,
                             KernelState, KernelInstabilityError, hertz, johnson_plastic)

    result = run_impacts(Target(graded_box(...)), Material(E=..., nu=..., density=..., A=..., B=..., n=..., C=...),
                         Shots(centres=(n,3), velocities=(n,3), radius=R, density=rho), Options(),
                         state=None, snapshot_after=(10, 20), on_shot_done=None)

    # or step by step (the loop run_impacts is):
    run = ImpactRun(target, material, options, state=None)     # set up a model (or resume a checkpoint)
    record = run.impact(shots, run.shots_done)                 # one impact -> a named ShotRecord
    snapshot = run.snapshot(shots)                             # relaxed copy of the state -> Snapshot
    state = run.checkpoint()                                   # dict of arrays; ImpactRun(..., state=state)

Modules (one concept each): ``mesh`` (structured hex box, graded axes),
``boundary`` (fixity masks), ``periodic`` (periodic faces: mesh check, tied
masters, the roll that keeps impacts off the seam), ``johnson_cook`` (eq. 1
and its return mapping), ``element`` (one-point hex + hourglass; ``element_reference``
its per-element reference),
``contact`` (rigid sphere, kinematic + Coulomb), ``shots`` (shot data, free
flight, Hertz/Johnson estimates), ``window`` (the active window: size,
validity, viscous-spring faces, sponge), ``solver`` (the explicit loop over
an active window), ``relaxation`` (global static / dynamic relaxation),
``multigrid`` (its preconditioner), ``box_stiffness`` (the element's
stiffness on a box grid and its product: the multigrid's operator;
``box_stiffness_reference`` the plain products the tests compare it against),
``records`` (the named per-shot record), ``state`` (checkpointable state), ``model`` (static arrays of a run,
target), ``safety`` (status codes -> exceptions), ``impact`` (the driver:
:class:`ImpactRun`'s steps and the :func:`run_impacts` loop).
"""

from peenflow.fe.impact import ImpactRun, ImpactRunResult, Options, Snapshot, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, box_mesh, graded_axis, graded_box, symmetric_axis
from peenflow.fe.model import Target
from peenflow.fe.safety import KernelInstabilityError
from peenflow.fe.shots import Shots, hertz, johnson_plastic
from peenflow.fe.records import SHOT_RECORD_DTYPE, SHOT_RECORD_FIELDS, ShotRecord
from peenflow.fe.state import KernelState
from peenflow.fe.window import ViscousSpringFaces

__all__ = [
    "run_impacts", "ImpactRun", "ShotRecord", "SHOT_RECORD_DTYPE", "Options", "ImpactRunResult", "Snapshot", "Target", "Material", "Shots",
    "BoxMesh", "box_mesh", "graded_axis", "graded_box", "symmetric_axis",
    "KernelState", "SHOT_RECORD_FIELDS", "KernelInstabilityError", "hertz", "johnson_plastic", "ViscousSpringFaces",
]
