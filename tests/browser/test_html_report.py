"""The studies' HTML pages in a real browser (issue 20, item 5): a small `contact2d compare`
and a small `sweep`, each page opened from disk in headless Chromium (Debian's chromium and
chromium-driver, through python3-selenium), and checked against the study's own CSV and markdown:

- nothing is loaded from outside the page (no resource fetched, no <script>, <link> or src=),
  every <img> (there should be none) decoded, element ids unique, every <use> pointing into
  its own chart (gnuplot's SVGs share ids; the page prefixes them per chart);
- one inline <svg> per chart the markdown shows, each drawn (a non-empty box, paths and text);
- the table's header is the CSV's header, its rows the CSV's rows (data-value exactly), each
  shown number the cell's value to the 4 significant digits it prints;
- the title and the verdict read as the markdown's heading and verdict paragraph;
- a scene path holding `<script>` and `&` appears as text.

Run by CTest (Browser.HtmlReport) with C2D_BINARY, C2D_SOURCE_DIR and TMPDIR set. Without
chromium, chromedriver or selenium the tests fail, saying what to install.
"""
import csv
import math
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

import pytest

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
SOURCE = pathlib.Path(os.environ.get("C2D_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
BINARY = os.environ.get("C2D_BINARY", str(SOURCE / "build" / "app" / "contact2d"))
INSTALL = "apt-get install chromium chromium-driver python3-selenium (scripts/bootstrap.sh)"


@pytest.fixture(scope="module")
def browser():
    for path in (CHROMIUM, CHROMEDRIVER):
        if not os.access(path, os.X_OK):
            pytest.fail(f"{path} is missing; the HTML report test needs it: {INSTALL}")
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError as e:
        pytest.fail(f"selenium is not importable by {sys.executable} ({e}): {INSTALL}")
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--window-size=1400,1000"):
        options.add_argument(arg)
    driver = webdriver.Chrome(service=Service(executable_path=CHROMEDRIVER), options=options)
    yield driver
    driver.quit()


@pytest.fixture(scope="module")
def workdir():
    return pathlib.Path(tempfile.mkdtemp(prefix="c2d_html_report_", dir=os.environ.get("TMPDIR")))


def run_study(args, out):
    p = subprocess.run([BINARY, *args, "--out", str(out), "--quiet"], capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 0, f"contact2d {' '.join(args)}: exit {p.returncode}\n{p.stdout}{p.stderr}"


def plain(text):
    """Markdown's **bold** and `code` as the browser shows them, whitespace collapsed."""
    return " ".join(text.replace("**", "").replace("`", "").split())


def close_to_shown(value, shown):
    """The shown number is the value to 4 significant digits (integers in full)."""
    v, s = float(value), float(shown)
    return abs(v - s) <= 5.0001e-4 * abs(v) + 1e-300


def check_page(driver, out, name):
    html, md_text = out / f"{name}.html", (out / f"{name}.md").read_text()
    with open(out / f"{name}.csv", newline="") as f:
        table = list(csv.reader(f))
    driver.get(html.as_uri())
    js = driver.execute_script
    assert js("return document.readyState") == "complete"

    # Self-contained: nothing fetched, nothing that could fetch or run.
    assert js("return performance.getEntriesByType('resource').length") == 0
    assert js("return document.querySelectorAll('script, link, iframe, object, embed, [src]')"
              ".length") == 0
    for src, width in js("return [...document.images].map(i => [i.src, i.naturalWidth])"):
        assert width > 0, f"broken image {src}"
    ids = js("return [...document.querySelectorAll('[id]')].map(e => e.id)")
    assert len(ids) == len(set(ids)), "duplicate element ids"
    stray = js("""return [...document.querySelectorAll('use')].filter(u => {
        const ref = u.getAttribute('href') || u.getAttribute('xlink:href') || '';
        const target = ref.startsWith('#') ? document.getElementById(ref.slice(1)) : null;
        return !target || target.closest('svg.chart') !== u.closest('svg.chart');
      }).length""")
    assert stray == 0, "a <use> points outside its own chart"

    # One drawn SVG per chart the markdown shows.
    stems = re.findall(r"!\[[^\]]*\]\(([\w.-]+)\.png\)", md_text)
    assert stems, f"{name}.md shows no chart"
    charts = js("""return [...document.querySelectorAll('svg')].map(s => {
        const r = s.getBoundingClientRect();
        return {figure: s.closest('figure') ? s.closest('figure').id : '', width: r.width,
                height: r.height, drawn: s.querySelectorAll('path, line, polyline').length,
                text: s.querySelectorAll('text').length};
      })""")
    assert [c["figure"] for c in charts] == [f"chart-{s}" for s in stems]
    for c in charts:
        assert c["width"] > 0 and c["height"] > 0, c
        assert c["drawn"] > 0 and c["text"] > 0, c

    # The table is the CSV: every column once (the ones to compare may come first).
    header = js("return [...document.querySelectorAll('#study-table thead th')]"
                ".map(th => th.textContent)")
    assert sorted(header) == sorted(table[0]) and len(set(header)) == len(header)
    order = [table[0].index(name) for name in header]
    rows = js("""return [...document.querySelectorAll('#study-table tbody tr')].map(tr =>
        [...tr.cells].map(td => [td.dataset.value, td.textContent]))""")
    assert len(rows) == len(table) - 1 >= 1
    for row, expected in zip(rows, table[1:]):
        assert [value for value, _ in row] == [expected[c] for c in order]
        for value, shown in row:
            if value == "":
                assert shown == "–"
            elif re.fullmatch(r"[-+]?[\d.]+(e[-+]?\d+)?", value):
                assert close_to_shown(value, shown), (value, shown)
            else:
                assert shown == value

    # Title and verdict: the markdown's heading and its first paragraph.
    paragraphs = md_text.split("\n\n")
    assert js("return document.querySelector('h1').textContent") == paragraphs[0][2:]
    verdict = js("return document.querySelector('#verdict p').textContent")
    assert plain(verdict) == plain(paragraphs[1])
    return html


def test_compare_page_in_chromium(browser, workdir):
    # The scene lives in a folder whose name is markup: the page must show it as text.
    scene_dir = workdir / "a&b <script>document.title='x'<"
    scene_dir.mkdir()
    scene = scene_dir / "hertz.toml"
    shutil.copy(SOURCE / "examples" / "hertz_rigid.toml", scene)
    out = workdir / "compare"
    run_study(["compare", str(scene), "--set", "analysis.mesh_scale=8", "--levels", "1",
               "--methods", "lagrange,penalty"], out)
    html = check_page(browser, out, "compare")
    assert browser.execute_script("return document.querySelector('h1').textContent") == \
        f"contact2d compare: {scene}"
    assert browser.title == f"contact2d compare: {scene}"
    assert "<script>document" not in html.read_text()
    print(f"compare.html: {html.stat().st_size} bytes")


def test_sweep_page_in_chromium(browser, workdir):
    out = workdir / "sweep"
    run_study(["sweep", str(SOURCE / "examples" / "hertz_rigid.toml"), "--method", "penalty",
               "--set", "analysis.mesh_scale=8", "--set", "contact.penalty.k=1e6:1e10:log:3"], out)
    html = check_page(browser, out, "sweep")
    print(f"sweep.html: {html.stat().st_size} bytes")
