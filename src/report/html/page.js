(function () {
  "use strict";
  var tip = document.getElementById("tip");
  function place(e) {
    tip.style.left = (e.pageX + 14) + "px";
    tip.style.top = (e.pageY + 14) + "px";
  }
  // The hover text of a design point, or of a point of a forced chart, beside the pointer at
  // once (its <title> otherwise shows only after a pause).
  document.addEventListener("mouseover", function (e) {
    var t = e.target.closest ? e.target.closest("[data-point],[data-hover]") : null;
    var title = t ? t.querySelector("title") : null;
    if (!title) { tip.hidden = true; return; }
    tip.textContent = title.textContent;
    tip.hidden = false;
    place(e);
  });
  document.addEventListener("mousemove", function (e) { if (!tip.hidden) { place(e); } });
  // A zone row highlights that zone's cells and points; clicking it again clears.
  function select(zone) {
    document.querySelectorAll(".hl").forEach(function (el) { el.classList.remove("hl"); });
    document.querySelectorAll("tr.sel").forEach(function (el) { el.classList.remove("sel"); });
    document.body.classList.toggle("zone-selected", zone !== null);
    if (zone === null) { return; }
    document.querySelectorAll("[data-zone]").forEach(function (el) {
      if (el.getAttribute("data-zone") === zone) {
        el.classList.add(el.tagName === "TR" ? "sel" : "hl");
      }
    });
  }
  document.querySelectorAll("tr.zone-row").forEach(function (tr) {
    function toggle() { select(tr.classList.contains("sel") ? null : tr.getAttribute("data-zone")); }
    tr.addEventListener("click", toggle);
    tr.addEventListener("keydown", function (e) { if (e.key === "Enter") { toggle(); } });
  });
})();
