"""``report.html``: one self-contained page per study -- headline numbers, plots, every point, provenance.

It opens in a browser from disk, with no server and nothing fetched: the
plots are embedded as PNG data URIs, the style is inline, there is no
script.  Written after every run beside the plots (:func:`peenflow.report.report_dir`)
and by ``peenflow report STUDY``.

Sections: the headline numbers (:mod:`peenflow.report.headline`); the process map when the study
has one (:mod:`peenflow.report.map_section`); the figures; one table
per stage with every point, its sweep values, state, run time, host and
key, and its full parameters on demand (``<details>``); provenance: the
peenflow version and code fingerprints, package versions, host(s), study
file and store path.
"""

from __future__ import annotations

import base64
import html
import json
import platform
import socket
from datetime import datetime, timezone
from pathlib import Path

import xarray as xr

from peenflow.engine import plan

STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 80em; color: #222; }
h1 { margin-bottom: 0.2em; } h2 { border-bottom: 1px solid #ccc; margin-top: 2em; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
th { background: #f0f0f0; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
img { max-width: 100%; border: 1px solid #ddd; margin: 0.5em 0; }
figure { margin: 0 0 1.5em; } figcaption { color: #555; font-size: 0.9em; }
details pre { white-space: pre-wrap; font-size: 0.8em; max-width: 60em; }
.state-done { color: #060; } .state-failed { color: #a00; } .state-pending, .state-stale { color: #a60; }
"""


def _e(x) -> str:
    return html.escape(str(x))


def _table(header, rows, num_cols=()) -> str:
    out = ["<table>", "<tr>" + "".join(f"<th>{_e(h)}</th>" for h in header) + "</tr>"]
    for r in rows:
        cells = []
        for i, c in enumerate(r):
            cls = ' class="num"' if i in num_cols else ""
            cells.append(f"<td{cls}>{c}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def _point_rows(graph, store):
    """Per stage: [(node, state, key, attrs of its stored result or {})]."""
    by_stage: dict[str, list] = {}
    for item in plan(graph, store, list(graph.nodes)):
        attrs = {}
        if item.key and item.state.value in ("done", "stale"):
            path = store.result_path(item.node.task.name, item.key)
            try:
                with xr.open_dataset(path) as ds:  # metadata only: no values are read
                    attrs = dict(ds.attrs)
            except (OSError, ValueError):
                attrs = {}
        by_stage.setdefault(item.node.stage, []).append((item.node, item.state.value, item.key, attrs))
    return by_stage


def build_report(graph, store, study_path: Path, images: list[Path], headline_rows) -> str:
    now = datetime.now(timezone.utc).isoformat(timespec="seconds")
    by_stage = _point_rows(graph, store)
    all_attrs = [a for rows in by_stage.values() for (_, _, _, a) in rows if a]
    parts = [f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
             f"<title>peenflow report: {_e(graph.name)}</title><style>{STYLE}</style></head><body>",
             f"<h1>peenflow report: {_e(graph.name)}</h1>",
             f"<p>study file <code>{_e(study_path)}</code>; store <code>{_e(store.root)}</code>; "
             f"written {now}</p>"]

    parts.append("<h2 id=\"headline\">Headline numbers</h2>")
    if headline_rows:
        parts.append(_table(["quantity", "value", "note"],
                            [(_e(q), _e(v), _e(n)) for q, v, n in headline_rows], num_cols=(1,)))
    else:
        parts.append("<p>No stage that gives a headline number is done yet.</p>")

    from .map_section import FIGURES, map_section
    from .reading import stage_or_none

    parts += map_section(stage_or_none(graph, store, "process_map"), stage_or_none(graph, store, "suggested_settings"),
                         images, _table, stage_or_none(graph, store, "verified_settings"))
    from .sensitivity_section import FIGURE as TORNADO
    from .sensitivity_section import sensitivity_section

    parts += sensitivity_section(stage_or_none(graph, store, "sensitivity"), images, _table)
    images = [img for img in images if Path(img).name not in FIGURES and Path(img).name != TORNADO]
    parts.append("<h2 id=\"figures\">Figures</h2>")
    if not images:
        parts.append("<p>No figure yet.</p>")
    for img in images:
        data = base64.b64encode(Path(img).read_bytes()).decode("ascii")
        parts.append(f"<figure><img alt=\"{_e(Path(img).stem)}\" src=\"data:image/png;base64,{data}\">"
                     f"<figcaption>{_e(Path(img).name)}</figcaption></figure>")

    parts.append("<h2 id=\"points\">Every point</h2>")
    total_wall = 0.0
    for stage, rows in by_stage.items():
        dims = list(rows[0][0].coords)
        table_rows = []
        for node, state, key, attrs in rows:
            wall = attrs.get("peenflow_wall_s")
            total_wall += float(wall) if wall is not None else 0.0
            params = json.dumps(node.params, indent=1, sort_keys=True, default=str)
            table_rows.append([
                *(_e(node.coords[d]) for d in dims),
                f"<span class=\"state-{_e(state)}\">{_e(state)}</span>",
                _e(f"{float(wall):.1f}") if wall is not None else "",
                _e(attrs.get("peenflow_finished", "")), _e(attrs.get("peenflow_host", "")),
                f"<code>{_e((key or '')[:12])}</code>",
                f"<details><summary>{len(node.params)} parameters</summary><pre>{_e(params)}</pre></details>",
            ])
        parts.append(f"<h3>{_e(stage)} ({len(rows)} point{'s' if len(rows) != 1 else ''}, "
                     f"task {_e(rows[0][0].task.name)})</h3>")
        parts.append(_table([*dims, "state", "run time (s)", "finished (UTC)", "host", "key", "parameters"],
                            table_rows, num_cols=(len(dims) + 1,)))
    parts.append(f"<p>Compute time of the stored points, summed: {total_wall:.1f} s.</p>")

    parts.append("<h2 id=\"provenance\">Provenance</h2>")
    versions = sorted({a.get("peenflow_versions", "") for a in all_attrs} - {""})
    hosts = sorted({str(a.get("peenflow_host", "")) for a in all_attrs} - {""})
    codes = sorted({(a.get("peenflow_task", ""), a.get("peenflow_code", ""), a.get("peenflow_source_hash", ""))
                    for a in all_attrs})
    from peenflow import __version__

    prov = [("peenflow (this report)", _e(__version__)),
            ("python (this report)", _e(platform.python_version())),
            ("report written on", _e(socket.gethostname())),
            ("computed on", _e(", ".join(hosts) or "-")),
            ("store", f"<code>{_e(store.root)}</code>"),
            ("study file", f"<code>{_e(study_path)}</code>")]
    for v in versions:
        prov.append(("package versions of the results", "<br>".join(
            _e(f"{k} {val}") for k, val in sorted(json.loads(v).items()))))
    parts.append(_table(["what", "value"], prov))
    parts.append(_table(["task", "code id in the key", "code fingerprint"],
                        [(_e(t), f"<code>{_e(c)}</code>", f"<code>{_e(h)}</code>") for t, c, h in codes if t]))
    parts.append("</body></html>\n")
    return "\n".join(parts)


def write_report(graph, store, out_dir: Path, study_path: Path, images: list[Path], rows: list) -> Path:
    """Write ``out_dir/report.html`` (atomically) with the headline ``rows`` and return its path."""
    from peenflow.engine.atomic import write_text_atomic

    text = build_report(graph, store, Path(study_path), [p for p in images if Path(p).suffix == ".png"], rows)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "report.html"
    write_text_atomic(path, text)
    return path
