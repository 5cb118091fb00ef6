"""What a person reads after a run: the headline numbers, the plots and one self-contained report.html.

Views of stored results, remade from whatever is done and never part of a
result's key; the ``run`` and ``report`` verbs (and the API) attach them to a
study's graph -- the pipeline only computes.

* ``headline``  the study's headline numbers: ``(quantity, value with unit, note)`` rows
* ``plots``     the figures (PNG, matplotlib): saturation, control curves, coverage, residual stress
* ``html``      ``report.html``: headline, figures, every point, provenance
* ``reading``   a stage's stored results, or None while none is done

Numbers are SI in the store; here they become mm, um and MPa (:mod:`peenflow.units`).
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["applies", "headline_rows", "report_dir", "write_reports"]

#: stages whose results these reports read: a graph with none of them (a toy pipeline) gets no report
READS = ("saturation", "control_curve", "target_velocity", "coverage_curve", "strip_coverage", "residual_profile",
         "target_indentation", "strip_rev", "target_rev")


def applies(graph) -> bool:
    """Whether the graph has any stage these reports read."""
    return any(stage in graph.stages for stage in READS)


def headline_rows(graph, store) -> list:
    """The study's headline numbers from what is done ([] when the reports do not apply; one row
    naming the failure if they fail: a summary never hides the run's own outcome)."""
    if not applies(graph):
        return []
    from .headline import headline_numbers

    try:
        return list(headline_numbers(graph, store))
    except Exception as exc:
        return [("headline numbers", "failed", f"{type(exc).__name__}: {exc}")]


def report_dir(store, study_path: Path) -> Path:
    """Where a study's plots and report go: in its store, one folder per study file.

    ``<store>/reports/<file stem>-<8 hex of the file's absolute path>``: never a
    tracked folder, and neither a copy of the study elsewhere nor another study
    run into the same ``--store`` overwrites them.
    """
    from peenflow.engine.canonical import digest

    resolved = Path(study_path).resolve()
    return store.report_dir(f"{resolved.stem}-{digest(str(resolved), 8)}")


def write_reports(graph, store, study_path) -> list[Path]:
    """The plots and report.html of a study from what is done; the paths written ([] when the
    reports do not apply)."""
    if not applies(graph):
        return []
    from .html import write_report
    from .plots import write_plots

    out = report_dir(store, study_path)
    written = write_plots(graph, store, out, graph.labels)
    return written + [write_report(graph, store, out, Path(study_path), written, headline_rows(graph, store))]
