"""A float32 copy of the blocked element kernel, for measurement only.

The solver's kernel is float64 (``Options.precision`` accepts only
"float64"; BENCHMARKS.md section 1 gives the measured reasons). To measure
what float32 state would buy, this module rebuilds ``_row`` / ``_rows_pass``
and their inlined helpers from the float64 source with every float literal
and every material constant cast to ``np.float32`` and the lane scratch in
float32, so the vectorised lane loops run 16 lanes per AVX-512 register
instead of 8. The plastic return (scalar, Newton) is shared with the float64
kernel. Not cached, not used by the solver.
"""

from __future__ import annotations

import inspect
import re
import textwrap

import numba
import numpy as np

from peenflow.fe import element, johnson_cook

_FLOAT = re.compile(r"(?<![\w.])(\d+\.\d*(?:e[+-]?\d+)?)")


def _f32_source(fn) -> str:
    src = textwrap.dedent(inspect.getsource(fn.py_func if hasattr(fn, "py_func") else fn))
    src = "\n".join(line for line in src.splitlines() if not line.startswith("@"))
    src = _FLOAT.sub(r"F(\1)", src)
    src = src.replace("float(", "F(").replace("np.zeros(_NSCR)", "np.zeros(_NSCR, np.float32)")
    src = src.replace("hdt = F(0.5) * dt", "dt = F(dt)\n    hdt = F(0.5) * dt")
    src = re.sub(r"= (mat\[M_\w+\])", r"= F(\1)", src)  # material constants
    src = src.replace("mod = F(mat[M_LAM]) + F(2.0) * mat[M_MU]", "mod = F(mat[M_LAM] + 2.0 * mat[M_MU])")
    return src


def build():
    """Return ``(serial, parallel)`` float32 element passes (same contract as ``element_rows``)."""
    ns = dict(vars(element))
    ns.update(vars(johnson_cook))
    ns.update(F=np.float32, np=np, math=__import__("math"), prange=numba.prange)
    ns.update(element.__dict__)
    for helper in (johnson_cook.jaumann_trial, johnson_cook.von_mises, element._corner_sums, element._corner_forces):
        src = _f32_source(helper)
        exec(src, ns)
        ns[helper.__name__] = numba.njit(inline="always", error_model="numpy", nogil=True)(ns[helper.__name__])
    exec(_f32_source(element._row), ns)
    ns["_row"] = numba.njit(error_model="numpy", nogil=True)(ns["_row"])
    exec(textwrap.dedent(inspect.getsource(element._rows_pass)), ns)
    exec(textwrap.dedent(inspect.getsource(element._rows_pass_parallel)), ns)
    return (numba.njit(error_model="numpy", nogil=True)(ns["_rows_pass"]),
            numba.njit(error_model="numpy", nogil=True, parallel=True)(ns["_rows_pass_parallel"]))
