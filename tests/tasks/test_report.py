"""report.html: written after every run, self-contained, and rendering in a real (headless) browser."""

import base64
import re
import shutil
import subprocess
import sys

import pytest

import peenflow
import peenflow.api

PROBE = """<div id="probe"></div><script>
window.__errors = [];
window.addEventListener("error", e => window.__errors.push(String(e.message || e.type)), true);
window.addEventListener("load", () => {
  const imgs = [...document.images];
  const broken = imgs.filter(i => !(i.complete && i.naturalWidth > 0)).length;
  const tables = [...document.querySelectorAll("table")];
  const p = document.getElementById("probe");
  p.dataset.images = imgs.length; p.dataset.broken = broken; p.dataset.tables = tables.length;
  p.dataset.headline = document.querySelector("#headline + table").rows.length - 1;
  p.dataset.widths = imgs.map(i => i.naturalWidth).join(",");
  p.dataset.errors = window.__errors.join(" | ");
});
</script>"""


def _report(study):
    from peenflow.report import report_dir

    report = report_dir(peenflow.api.open_store(study), study) / "report.html"
    assert report.parent.parent == study.parent / ".peenflow" / "reports" and report.is_file()
    return report


def test_every_run_writes_a_self_contained_report_beside_its_plots(micro):
    log = micro.with_name("run.log").read_text()
    report = _report(micro)
    assert f"wrote {report}" in log
    html = report.read_text()
    pngs = sorted(report.parent.glob("*.png"))
    assert len(pngs) == 4
    embedded = re.findall(r'src="data:image/png;base64,([^"]+)"', html)
    assert sorted(base64.b64decode(e) for e in embedded) == sorted(p.read_bytes() for p in pngs)
    assert not re.search(r'(src|href)="(https?:|file:|/)', html) and "<script" not in html  # nothing fetched
    graph = peenflow.api.load_study_graph(micro)
    for stage in graph.stages:
        assert f"<h3>{stage} (" in html
    assert html.count('class="state-done"') == len(graph.nodes)
    assert f"peenflow {peenflow.__version__}" in html or f"<td>{peenflow.__version__}</td>" in html
    assert "numpy" in html and "numba" in html and str(micro.parent / ".peenflow") in html
    cov = peenflow.open_result(micro, "coverage_curve")
    assert f"{float(cov.full_coverage_shots):.0f} shots" in html
    # the verb rewrites the same files from the store, computing nothing
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "report", str(micro)], capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0 and f"wrote {report}" in proc.stdout


def _browser():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    pytest.skip("no headless browser installed (Debian: apt-get install chromium); the report's browser test skips")


@pytest.mark.browser
def test_the_report_renders_its_tables_and_images_in_headless_chromium(micro, tmp_path):
    browser = _browser()
    report = _report(micro)
    probe = tmp_path / "probe.html"
    probe.write_text(report.read_text().replace("</body>", PROBE + "</body>"))
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--virtual-time-budget=10000"]
    dom = subprocess.run([browser, *flags, "--dump-dom", probe.as_uri()], capture_output=True, text=True,
                         timeout=120)
    m = re.search(r'<div id="probe"([^>]*)>', dom.stdout)
    assert m, dom.stdout[-2000:] + dom.stderr[-2000:]
    data = dict(re.findall(r'data-(\w+)="([^"]*)"', m.group(1)))
    assert data["images"] == "4" and data["broken"] == "0", data
    assert all(int(w) > 300 for w in data["widths"].split(",")), data  # decoded PNGs, not icons
    graph = peenflow.api.load_study_graph(micro)
    assert int(data["tables"]) >= 1 + len(graph.stages) + 1, data  # headline, one per stage, provenance
    assert int(data["headline"]) >= 10, data
    assert data["errors"] == "", data
    assert "Uncaught" not in dom.stderr and "ERR_FILE_NOT_FOUND" not in dom.stderr
    shot = tmp_path / "shot.png"
    subprocess.run([browser, *flags, "--window-size=1280,2400", f"--screenshot={shot}", report.as_uri()],
                   capture_output=True, timeout=120)
    import matplotlib.image

    pixels = matplotlib.image.imread(shot)
    assert pixels.shape[:2] == (2400, 1280)
    # not a blank page: plenty of ink (text, tables and the first figures)
    assert (pixels[..., :3].mean(axis=2) < 0.5).mean() > 0.01
