"""The checkpointable state (peenflow.fe.state) and its named shot records (peenflow.fe.records)."""

import numpy as np
import pytest

from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh
from peenflow.fe.model import Model, Target
from peenflow.fe.records import (SHOT_RECORD_DTYPE, SHOT_RECORD_FIELDS, SHOT_RECORD_UNITS, ShotRecord, as_records,
                                 record_columns, records_array)
from peenflow.fe.state import KernelState

MAT = Material(E=205e9, nu=0.29, density=7800.0, A=1408e6, B=600.8e6, n=0.234, C=0.0134, m=0.0)


def some_state():
    ax = np.linspace(0.0, 0.2e-3, 5)
    st = Model(Target(BoxMesh(ax, ax, ax)), MAT).new_state()
    rng = np.random.default_rng(3)
    for a in (st.x, st.v, st.f, st.stress, st.eps_p, st.hg, st.temp, st.energy, st.ctl):
        a += rng.standard_normal(a.shape)
    st.shot_index[0] = 2
    recs = [ShotRecord(shot_index=0, hit=True, restitution=0.61, peak_force=12.5, steps=900, win_i1=4),
            ShotRecord(shot_index=1, hit=False, vin_z=55.0, impact_energy=1e-4)]
    return st.with_records(records_array(recs))


def test_round_trip_is_exact_and_a_deep_copy():
    st = some_state()
    d = st.to_dict()
    back = KernelState.from_dict(d)
    for name, value in st.to_dict().items():
        assert back.to_dict()[name].dtype == value.dtype
        np.testing.assert_array_equal(back.to_dict()[name], value)
    d["x"][0, 0] += 1.0  # the dict owns its arrays ...
    back.v[0, 0] += 1.0  # ... and so does the restored state
    assert st.x[0, 0] != d["x"][0, 0] and st.v[0, 0] != back.v[0, 0]


def test_initial_state_is_at_rest_with_the_material_flow_stress():
    ax = np.linspace(0.0, 0.2e-3, 5)
    m = Model(Target(BoxMesh(ax, ax, ax)), MAT)
    st = m.new_state()
    np.testing.assert_array_equal(st.x, m.nodes0)
    assert not st.v.any() and not st.stress.any() and not st.eps_p.any() and st.shot_index[0] == 0
    assert np.all(st.sy_static == pytest.approx(MAT.A))  # room temperature, no plastic strain: A
    assert st.shot_records.dtype == SHOT_RECORD_DTYPE and len(st.shot_records) == 0


def test_records_are_read_by_name_whatever_their_order():
    st = some_state()
    rec = st.shot_records
    # the same fields in reverse order, plus one this version does not know
    other = np.dtype([(n, SHOT_RECORD_DTYPE[n]) for n in reversed(SHOT_RECORD_FIELDS)] + [("future", "f8")])
    shuffled = np.zeros(len(rec), dtype=other)
    for n in SHOT_RECORD_FIELDS:
        shuffled[n] = rec[n]
    np.testing.assert_array_equal(as_records(shuffled), rec)
    assert [ShotRecord.from_row(r) for r in as_records(shuffled)] == [ShotRecord.from_row(r) for r in rec]
    cols = record_columns(rec)
    assert cols["restitution"].tolist() == [0.61, 0.0] and cols["hit"].tolist() == [True, False]


def test_records_without_names_or_with_missing_fields_are_refused():
    with pytest.raises(ValueError, match="column position"):
        as_records(np.zeros((2, len(SHOT_RECORD_FIELDS))))
    short = np.zeros(2, dtype=[(n, "f8") for n in SHOT_RECORD_FIELDS if n != "peak_force"])
    with pytest.raises(ValueError, match="peak_force"):
        as_records(short)
    d = some_state().to_dict()
    d["shot_records"] = np.zeros((2, len(SHOT_RECORD_FIELDS)))
    with pytest.raises(ValueError, match="cannot be resumed"):
        KernelState.from_dict(d)


def test_a_record_survives_its_array_form_and_every_field_has_units():
    r = ShotRecord(shot_index=7, hit=True, vin_x=1.5, vin_z=-55.0, steps=1234, win_k1=9, spin_out_y=-3.25)
    assert ShotRecord.from_row(r.as_row()) == r
    assert set(SHOT_RECORD_UNITS) == set(SHOT_RECORD_FIELDS) and SHOT_RECORD_UNITS["peak_force"] == "N"
    assert SHOT_RECORD_DTYPE["steps"] == np.int64 and SHOT_RECORD_DTYPE["hit"] == np.bool_
