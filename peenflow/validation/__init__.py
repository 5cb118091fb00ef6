"""Validation cases, the readings of their figures, and the measured runs: what the tests and the
benchmark drivers (``benchmarks/``, benchmarks/README.md) share.

* ``single_impact``  the single-impact cases (one shot on a refined block), a run of one, the keys of
                     its runs, and each case's converged reference
* ``readings``       how a single impact's figures are read off its fields (surface line, sigma_xx(z)
                     column) and how far each reading resolves on a coarser mesh
* ``goals``          issue 13 section 1's single-impact goals, figure by figure
* ``study_level``    the study-level references (strip points and the section 5 target refined
                     until converged) and each element size's error against them
* ``kernel_cases``   the kernel benchmarks' shared cases: the strip REV, the REVs a study builds, the
                     element-pass state, the layer profile
* ``runs``           the measured runs: compact summaries shipped in ``data/`` (read by tests and
                     tables, written by the drivers)

It builds on the kernel (``peenflow.fe``), the methods, the study layer and the stages (``tasks``);
none of those imports it (tests/test_validation.py checks).
"""
