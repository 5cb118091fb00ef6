"""Methodology stages: one module per stage (or per task two stages share), each a registered peenflow task.

The one place that translates: :mod:`tasks.params` reads the validated study
once into typed parameters in SI and converts them to the kernel's objects;
:mod:`tasks.pipeline` wires the stages into a graph (``STAGES`` names them);
:mod:`tasks.preflight` checks a study against the kernel's own limits before
any compute; every stage declares its outputs (:mod:`tasks.outputs`) and
returns an SI Dataset with CF ``units``.  The views of the results (headline,
plots, report.html) are :mod:`peenflow.report`'s.
"""
