/* The top bar's menu on narrow screens: the button opens and closes the navigation (a column under the bar). */
(function () {
  "use strict";
  var toggle = document.querySelector("[data-nav-toggle]");
  if (!toggle) return;
  toggle.addEventListener("click", function () {
    var open = toggle.getAttribute("aria-expanded") !== "true";
    toggle.setAttribute("aria-expanded", String(open));
    document.body.classList.toggle("nav-open", open);
  });
})();

/* A refused form's error summary is brought into view (it may sit below a long chart). Disabling a submitted
   form's buttons is forms.js's job. */
(function () {
  "use strict";
  var summary = document.querySelector("[data-error-summary]");
  if (summary) {
    summary.scrollIntoView({ block: "center" });
    summary.focus({ preventScroll: true });
  }
})();

/* Phones: a horizontal legend above a chart wraps onto several lines there and covers the titles, so it moves
   under the chart (the bottom margin grows to hold it). Desktop layouts are left as the server drew them. */
(function () {
  "use strict";
  var NARROW = 760;
  function legendsBelow() {
    if (!window.Plotly || window.innerWidth > NARROW) return;
    document.querySelectorAll(".js-plotly-plot").forEach(function (gd) {
      var legend = gd.layout && gd.layout.legend;
      if (!legend || legend.orientation !== "h" || gd.dataset.phoneLegend) return;
      gd.dataset.phoneLegend = "moving";
      var rows = Math.ceil((gd.data || []).filter(function (t) { return t.showlegend !== false; }).length / 2);
      var margin = (gd.layout.margin && gd.layout.margin.b) || 10;
      window.Plotly.relayout(gd, {
        "legend.yref": "container",
        "legend.y": 0,
        "legend.yanchor": "bottom",
        "legend.x": 0,
        "legend.xanchor": "left",
        "margin.t": Math.min((gd.layout.margin && gd.layout.margin.t) || 40, 50),
        "margin.b": margin + 30 + 22 * Math.max(1, rows),
      }).then(function () { gd.dataset.phoneLegend = "below"; });
    });
  }
  window.addEventListener("load", legendsBelow);
})();
