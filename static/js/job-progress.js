/* Live progress of one job: poll the REST API (session auth) and update the bar, the log and the cancel/retry
   buttons until the job ends, then reload so the server renders the final state and the link to the result. */
(function () {
  "use strict";
  var box = document.getElementById("job-progress");
  if (!box || box.dataset.done === "true") return;

  var url = box.dataset.apiUrl;
  var bar = document.getElementById("job-bar");
  var barBox = document.getElementById("job-progressbar");
  var state = document.getElementById("job-state");
  var message = document.getElementById("job-message");
  var percent = document.getElementById("job-percent");
  var note = document.getElementById("job-poll-note");
  var logList = document.getElementById("job-log");
  var waiting = document.getElementById("job-waiting");
  var delay = 1000;
  var MAX_DELAY = 10000;

  function button(name, reason) {
    var b = document.getElementById("job-" + name);
    var why = document.getElementById("job-" + name + "-reason");
    if (!b) return;
    b.disabled = Boolean(reason) || Boolean(b.dataset.busy);  // busy: its form is being submitted (forms.js)
    if (reason) b.title = reason; else b.removeAttribute("title");
    if (why) why.textContent = reason || "";
  }

  function pad(n) { return (n < 10 ? "0" : "") + n; }

  function showLog(lines) {
    if (!logList || !lines) return;
    var items = lines.map(function (line) {
      var li = document.createElement("li");
      var t = document.createElement("time");
      var at = new Date(line.at);
      t.setAttribute("datetime", line.at);
      t.textContent = pad(at.getUTCHours()) + ":" + pad(at.getUTCMinutes()) + ":" + pad(at.getUTCSeconds());
      li.appendChild(t);
      if (line.progress !== null && line.progress !== undefined) {
        var p = document.createElement("span");
        p.className = "muted";
        p.textContent = " " + line.progress + "%";
        li.appendChild(p);
      }
      li.appendChild(document.createTextNode(" " + line.text));
      return li;
    });
    logList.replaceChildren.apply(logList, items);
  }

  function show(job) {
    var p = Math.max(0, Math.min(100, job.progress || 0));
    bar.style.width = p + "%";
    bar.className = "progress-bar state-" + job.state;
    barBox.setAttribute("aria-valuenow", String(p));
    percent.textContent = String(p);
    state.textContent = job.state.charAt(0).toUpperCase() + job.state.slice(1);
    state.className = "badge state-" + job.state;
    message.textContent = job.message || "";
    if (waiting) {  // a pending job no worker picked up for a minute says so (apps/jobs/dispatch.py)
      waiting.textContent = job.waiting_notice || "";
      waiting.hidden = !job.waiting_notice;
    }
    button("cancel", job.cancel_unavailable);
    button("retry", job.retry_unavailable);
    showLog(job.log);
  }

  function poll() {
    fetch(url, { credentials: "same-origin", headers: { Accept: "application/json" } })
      .then(function (response) {
        if (!response.ok) throw new Error("HTTP " + response.status);
        return response.json();
      })
      .then(function (job) {
        note.textContent = "";
        delay = 1000;
        show(job);
        if (job.state === "succeeded" || job.state === "failed" || job.state === "cancelled") {
          window.location.reload();
        } else {
          window.setTimeout(poll, delay);
        }
      })
      .catch(function (err) {
        // Keep trying with a growing pause: a restarting server should not end the live view.
        delay = Math.min(delay * 2, MAX_DELAY);
        note.textContent = "(cannot reach the server: " + err.message + "; retrying)";
        window.setTimeout(poll, delay);
      });
  }

  window.setTimeout(poll, 500);
})();
