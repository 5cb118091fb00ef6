"""peenflow: shot-peening residual stresses from Almen intensity and coverage.

Layers (one folder each):

* ``peenflow.fe``      -- the numba FE/DEM impact kernel (arrays in, arrays out, SI units)
* ``peenflow.methods`` -- the paper's post-processing maths (coverage, arc height, fits)
* ``peenflow.engine``  -- the generic cached, resumable task DAG (knows nothing of peening)
* ``peenflow.study``   -- study-file schema, validation and the material/shot library
* ``tasks``            -- one module per methodology stage: study params -> kernel -> Dataset
"""

__version__ = "0.1.0"


def open_result(study_path, stage, store=None, allow_partial=False, lazy=True):
    """A stage's results as one xarray Dataset (dask-backed unless ``lazy=False``); see :mod:`peenflow.api`."""
    from .api import open_result as _open

    return _open(study_path, stage, store=store, allow_partial=allow_partial, lazy=lazy)
