/* Live pods (apps/ui/templates/ui/includes/live_pods.html): poll each section's data-live-url and redraw its
   table (phase, planned node, node now, newest event), so a page follows the cluster without a reload.
   Polling pauses while the tab is hidden and backs off while the server does not answer. */
(function () {
  "use strict";
  if (window.continuumLivePods) return;  // the partial may be included more than once in a page
  window.continuumLivePods = true;
  var EVERY_MS = 4000;
  var MAX_MS = 30000;

  function cell(text, className) {
    var td = document.createElement("td");
    td.textContent = text || "";
    if (className) td.className = className;
    return td;
  }

  function phaseCell(phase) {
    var td = document.createElement("td");
    var badge = document.createElement("span");
    badge.className = "badge phase-" + (phase || "none").toLowerCase();
    badge.textContent = phase || "not seen";
    td.appendChild(badge);
    return td;
  }

  function ago(iso) {
    if (!iso) return "—";
    var s = Math.max(0, Math.round((Date.now() - new Date(iso).getTime()) / 1000));
    return s < 60 ? s + " s ago" : s < 3600 ? Math.round(s / 60) + " min ago" : Math.round(s / 3600) + " h ago";
  }

  function draw(section, data) {
    var body = section.querySelector("tbody");
    var rows = data.pods.map(function (p) {
      var tr = document.createElement("tr");
      tr.dataset.pod = p.pod;
      if (p.moved) tr.className = "moved";
      tr.appendChild(cell(p.label));
      tr.appendChild(cell(p.pod || "not pushed", "mono"));
      tr.appendChild(phaseCell(p.phase));
      tr.appendChild(cell(p.planned || "—"));
      tr.appendChild(cell((p.node || "—") + (p.moved ? " (not as planned)" : "")));
      tr.appendChild(cell(p.event || "—", "small"));
      var seen = cell(ago(p.at), "small muted");
      if (p.at) seen.title = p.at;
      tr.appendChild(seen);
      return tr;
    });
    if (!rows.length) {
      var tr = document.createElement("tr");
      var td = cell(data.empty || "No pods.", "muted");
      td.colSpan = 7;
      tr.appendChild(td);
      rows = [tr];
    }
    body.replaceChildren.apply(body, rows);
    var parts = Object.keys(data.phases).sort().map(function (k) { return data.phases[k] + " " + k; });
    if (data.moved) parts.push(data.moved + " not on their planned node");
    var more = data.total > data.pods.length ? " (the newest " + data.pods.length + " of " + data.total + " shown)" : "";
    section.querySelector(".live-summary").textContent = parts.join(", ") + more;
  }

  function follow(section) {
    var delay = EVERY_MS;
    var note = section.querySelector(".live-note");
    function poll() {
      if (document.hidden) { window.setTimeout(poll, EVERY_MS); return; }
      fetch(section.dataset.liveUrl, { credentials: "same-origin", headers: { Accept: "application/json" } })
        .then(function (r) { if (!r.ok) throw new Error("HTTP " + r.status); return r.json(); })
        .then(function (data) {
          draw(section, data);
          note.textContent = "";
          section.dataset.updated = new Date().toISOString();
          delay = EVERY_MS;
        })
        .catch(function (err) {
          delay = Math.min(delay * 2, MAX_MS);
          note.textContent = "(cannot reach the server: " + err.message + "; retrying)";
        })
        .then(function () { window.setTimeout(poll, delay); });
    }
    poll();
  }

  function start() { Array.prototype.forEach.call(document.querySelectorAll("section.live-pods[data-live-url]"), follow); }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start); else start();
})();
