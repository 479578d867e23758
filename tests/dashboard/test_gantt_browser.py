"""The 100-processor WebGL Gantt chart in a real browser (system Chromium, fixtures of test_browser.py): no bar
drawn above the first processor's row (issue 30, item 1: four rows of bars sat above the first label, the
WebGL canvas being taller than Chromium's 8,192-pixel viewport). The figure-level checks are in
tests/ui/test_gantt_rows.py."""

import base64
from pathlib import Path

import pytest

from apps.ui import charts
from tests.dashboard.test_browser import browser  # noqa: F401 (the fixture)
from tests.ui.test_gantt_rows import wide_schedule

pytestmark = [pytest.mark.browser]

STATIC = Path(__file__).resolve().parents[2] / "static"
PLOTLY = STATIC / "vendor" / "plotly.min.js"
CHARTS = STATIC / "js" / "charts.js"  # draws every chart's data block (charts.to_html writes no inline script)
SLOW_MS = 180_000

DRAWN = "() => { const gd = document.getElementById('g'); return gd && gd.data && gd.data[0].y.length > 0; }"
NEXT_FRAMES = "() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)))"

#: The first coloured pixel row (any channel spread above 60: a bar, not white, grey grid or text) in a PNG.
FIRST_COLOURED_ROW = """async (src) => {
  const img = new Image(); img.src = src; await img.decode();
  const c = document.createElement('canvas'); c.width = img.width; c.height = img.height;
  const ctx = c.getContext('2d'); ctx.drawImage(img, 0, 0);
  const d = ctx.getImageData(0, 0, c.width, c.height).data;
  for (let y = 0; y < c.height; y++) for (let x = 0; x < c.width; x++) {
    const i = 4 * (y * c.width + x), r = d[i], g = d[i + 1], b = d[i + 2];
    if (Math.max(r, g, b) - Math.min(r, g, b) > 60) return y;
  }
  return -1;
}"""

#: The first row's label centre, the plot area's top and left edges and a row's height, in page pixels.
GEOMETRY = """() => {
  const gd = document.getElementById('g'), ya = gd._fullLayout.yaxis, size = gd._fullLayout._size;
  const label = [...document.querySelectorAll('.ytick text')].find((t) => t.textContent === 'p0');
  const box = label.getBoundingClientRect(), top = gd.getBoundingClientRect().top;
  return {label: box.top + box.height / 2, top: top + size.t, left: size.l, row: ya._length / ya._categories.length};
}"""


def test_no_webgl_bar_is_drawn_above_the_first_processor_row(browser, tmp_path):  # noqa: F811
    schedule, platform = wide_schedule()
    fig = charts.gantt_figure(schedule, platform=platform, critical=[])
    page_file = tmp_path / "gantt.html"
    script = f'<script src="{PLOTLY.as_uri()}"></script>'
    drawer = f'<script src="{CHARTS.as_uri()}"></script>'
    page_file.write_text(f'<html><body style="margin:0">{script}{charts.to_html(fig, "g")}{drawer}</body></html>')
    page = browser.new_page(viewport={"width": 1440, "height": 900})
    try:
        page.set_default_timeout(SLOW_MS)
        page.goto(page_file.as_uri(), wait_until="commit")
        page.wait_for_function(DRAWN)
        page.evaluate(NEXT_FRAMES)  # the WebGL frame drawn after the restyle
        geo = page.evaluate(GEOMETRY)
        row_top = geo["label"] - geo["row"] / 2
        clip = {"x": geo["left"] + 2, "y": geo["top"], "width": 400, "height": row_top + geo["row"] - geo["top"]}
        shot = base64.b64encode(page.screenshot(clip=clip)).decode()
        first = page.evaluate(FIRST_COLOURED_ROW, "data:image/png;base64," + shot)
    finally:
        page.close()
    assert first >= 0, "the first row has bars"
    # Bars are 80 % of a row thick, centred: the first coloured pixel is in the first row's band.
    assert geo["top"] + first >= row_top - 2, (geo, first)
