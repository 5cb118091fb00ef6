"""Methodology stages: one module per stage (or per task two stages share), each a registered peenflow task.

The one place that translates: :mod:`tasks.params` reads the validated study
once into typed parameters in SI and converts them to the kernel's objects;
:mod:`tasks.pipeline` wires the stages into a graph (``STAGES`` names them);
every stage returns an SI Dataset with CF ``units``, and only the edges
(:mod:`tasks.headline`, :mod:`tasks.plots`, :mod:`tasks.report`) show mm and MPa.
"""
