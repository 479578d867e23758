/* Draws the dashboard's Plotly charts: apps/ui/charts.py's to_html writes each as a <div class="plotly-chart">
   and its figure as JSON in a data block (<script type="application/json">, never executed), so that no page
   needs an inline script (the Content-Security-Policy allows none). plotly.js comes from static files too. */
(function () {
  "use strict";

  /* Expands the WebGL Gantt traces' meta.gantt facts (apps/ui/charts.py, gl_gantt_facts) into their points and
     hover text, in _gantt_hover's words; numbers as Python's %.6g would print them. */
  function expandGantt(gd) {
    function num(x) {
      var a = Math.abs(x);
      if (a !== 0 && (a < 1e-4 || a >= 1e6)) {
        return x.toExponential(5).replace(/\.?0+e/, 'e').replace(/e([+-])(\d)$/, 'e$10$2');
      }
      return String(parseFloat(x.toPrecision(6)));
    }
    var idx = [], xs = [], ys = [], hs = [];
    gd.data.forEach(function (t, i) {
      var g = t.meta && t.meta.gantt; if (!g) return; g = JSON.parse(g);
      var n = g.task.length, x = new Float64Array(4 * n), y = new Array(4 * n), h = new Array(4 * n), u = g.unit;
      for (var k = 0; k < n; k++) {
        var s = g.start[k], f = g.finish[k], r = g.rows[g.row[k]];
        var text = '<b>' + g.task[k] + '</b> (frame ' + g.frame[k] + ')<br>processor: ' + g.processors[g.processor[k]] +
          '<br>start: ' + num(s) + u + '<br>finish: ' + num(f) + u + '<br>duration: ' + num(g.duration[k]) + u +
          (g.note && g.note[k] ? '<br>' + g.note[k] : '');
        x[4 * k] = s; x[4 * k + 1] = (s + f) / 2; x[4 * k + 2] = f; x[4 * k + 3] = NaN;
        y[4 * k] = y[4 * k + 1] = y[4 * k + 2] = y[4 * k + 3] = r;
        h[4 * k] = h[4 * k + 1] = h[4 * k + 2] = text; h[4 * k + 3] = '';
      }
      idx.push(i); xs.push(x); ys.push(y); hs.push(h);
    });
    if (idx.length) Plotly.restyle(gd, {x: xs, y: ys, hovertext: hs}, idx);
  }

  function draw(div) {
    var block = document.getElementById(div.getAttribute("data-figure"));
    if (!block || !window.Plotly) return;
    var figure = JSON.parse(block.textContent);
    window.Plotly.newPlot(div, figure.data, figure.layout, figure.config).then(function () {
      if (div.hasAttribute("data-gl-gantt")) expandGantt(div);
    });
  }

  document.querySelectorAll("div.plotly-chart[data-figure]").forEach(draw);
})();
