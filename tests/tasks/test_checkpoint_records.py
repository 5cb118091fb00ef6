"""Checkpoints store the kernel state's shot records by field name: a real checkpoint survives the netCDF
file bit for bit and resumes the same run; an old checkpoint with the positional table is refused with a
note and the run starts afresh (never a crash, never a misread column)."""

from __future__ import annotations

import numpy as np
import pytest

from peenflow.engine import DirectoryStore, TaskContext
from peenflow.engine.interrupt import Interrupted
from peenflow.engine.netcdf_io import read_dataset, write_dataset
from peenflow.fe.impact import ImpactRun, Options
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.model import Target
from peenflow.fe.records import SHOT_RECORD_DTYPE, SHOT_RECORD_FIELDS
from peenflow.fe.shots import Shots
from peenflow.fe.state import KernelState
from tasks import _kernel as K

from .test_limits import _rev, _same, _StopAfter, micro  # noqa: F401  (micro: the fixture)

R = 0.29e-3
MAT = Material(E=205e9, nu=0.29, density=7800.0, A=1408e6, B=600.8e6, n=0.234, C=0.0134, m=0.0)


def test_a_checkpoint_survives_the_file_and_resumes_the_same_run(tmp_path):
    ax = np.linspace(-0.6e-3, 0.6e-3, 25)
    target = Target(BoxMesh(ax, ax.copy(), graded_axis(0.15e-3, 50e-6, 0.5e-3, 1.3)))
    shots = Shots([[0.0, 0.0, -R - 1e-6], [2e-3, 0.0, -R - 1e-6], [60e-6, 0.0, -R - 1e-6]],
                  [[0.0, 0.0, 45.0], [0.0, 0.0, 45.0], [4.0, 0.0, 40.0]], R, 7800.0)  # shot 1 misses
    run = ImpactRun(target, MAT, Options(window_warning=False))
    run.impact(shots, 0)
    run.impact(shots, 1)
    ck = run.checkpoint()
    path = tmp_path / "ck.nc"
    write_dataset(K.state_to_dataset(ck, rung=(("rung",), np.array([2]))), path)
    back = K.state_from_dataset(read_dataset(path))
    assert sorted(back) == sorted(ck)
    for name in ck:
        if name == "shot_records":
            assert back[name].dtype.names == SHOT_RECORD_FIELDS
            for f in SHOT_RECORD_FIELDS:
                assert back[name][f].dtype == SHOT_RECORD_DTYPE[f]
                np.testing.assert_array_equal(back[name][f], ck[name][f])
        else:
            assert back[name].dtype == ck[name].dtype
            np.testing.assert_array_equal(back[name], ck[name])
    assert back["shot_records"]["hit"].tolist() == [True, False]
    resumed = ImpactRun(target, MAT, Options(window_warning=False), state=back)
    assert resumed.shots_done == 2
    a, b = run.impact(shots, 2), resumed.impact(shots, 2)
    assert a == b  # the same record, field by field
    np.testing.assert_array_equal(run.state.stress, resumed.state.stress)


def test_a_positional_record_table_is_refused_by_the_kernel_state():
    ax = np.linspace(0.0, 0.2e-3, 5)
    st = ImpactRun(Target(BoxMesh(ax, ax, ax)), MAT).checkpoint()
    st["shot_records"] = np.zeros((3, len(SHOT_RECORD_FIELDS)))
    with pytest.raises(ValueError, match="column position"):
        KernelState.from_dict(st)


def test_an_old_positional_checkpoint_is_ignored_with_a_note(micro, tmp_path):  # noqa: F811
    store = DirectoryStore(tmp_path / "store")
    ctx = _StopAfter(store, "k" * 32, "p", "study", 1, shots=4)
    with pytest.raises(Interrupted):
        _rev(micro, ctx)
    ck = ctx.load_checkpoint()
    # the same checkpoint as the base tree wrote it: one (n, 34) table, columns by position
    old = ck.drop_vars([v for v in ck.variables if str(v).startswith("kernel__shot_records__")])
    old["kernel__shot_records"] = (("kernel__shot_records__0", "kernel__shot_records__1"),
                                   np.zeros((4, len(SHOT_RECORD_FIELDS))))
    TaskContext(store, "k" * 32, "p", "study", 1).save_checkpoint(old)
    again = TaskContext(store, "k" * 32, "p", "study", 1)
    _same(_rev(micro, again), _rev(micro, None))
    assert again.notes and "column position" in again.notes[0] and "started from the beginning" in again.notes[0]
