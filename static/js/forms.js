/* One submit per click: a POST form's submit buttons are disabled once it is submitted (after the browser has
   read the clicked button's name and value), and marked busy, so a slow answer cannot be submitted twice.
   They come back when the page is shown again from the back/forward cache, or after a long silence (a form
   that answers with a download leaves the page in place). A form with data-resubmit opts out. */
(function () {
  "use strict";
  var RESTORE_MS = 30000;

  function buttons(form) {
    return Array.prototype.slice.call(form.querySelectorAll("button[type=submit], button:not([type]), input[type=submit]"))
      .concat(form.id ? Array.prototype.slice.call(document.querySelectorAll("[form='" + form.id + "'][type=submit]")) : []);
  }

  function setBusy(form, busy) {
    buttons(form).forEach(function (b) {
      if (busy) {
        if (b.disabled) return;
        b.dataset.busy = "1";
        b.disabled = true;
        b.setAttribute("aria-busy", "true");
      } else if (b.dataset.busy) {
        delete b.dataset.busy;
        b.disabled = false;
        b.removeAttribute("aria-busy");
      }
    });
  }

  document.addEventListener("submit", function (event) {
    var form = event.target;
    if (event.defaultPrevented || !(form instanceof HTMLFormElement)) return;
    if ((form.getAttribute("method") || "get").toLowerCase() !== "post" || "resubmit" in form.dataset) return;
    window.setTimeout(function () { setBusy(form, true); }, 0);
    window.setTimeout(function () { setBusy(form, false); }, RESTORE_MS);
  });

  window.addEventListener("pageshow", function (event) {
    if (event.persisted) Array.prototype.forEach.call(document.forms, function (f) { setBusy(f, false); });
  });
})();
