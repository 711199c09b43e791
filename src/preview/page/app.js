// The preview page: follows the server's event stream, refreshes the image,
// lists diagnostics, sends the controls and shows what a click hits.
"use strict";

const $ = (id) => document.getElementById(id);
const img = $("render");
let status = null;
let shown = "";

function el(tag, text, cls) {
  const e = document.createElement(tag);
  if (text !== undefined) e.textContent = text;
  if (cls) e.className = cls;
  return e;
}

function fmtTime(s) {
  if (!isFinite(s)) return "?";
  if (s < 60) return s.toFixed(1) + " s";
  return Math.floor(s / 60) + " min " + Math.round(s % 60) + " s";
}

function refreshImage() {
  if (!status || !status.has_image) return;
  const key = status.job + "-" + status.spp + "-" + $("exposure").value;
  if (key === shown) return;
  shown = key;
  img.src = "/image.png?exposure=" + $("exposure").value + "&v=" + key;
}

function showStatus(s) {
  status = s;
  img.hidden = !s.has_image && !img.src;
  img.classList.toggle("stale", s.failed);
  const rate = s.samples_per_second;
  const left = s.spp >= s.target_spp ? "done" : "ETA " + fmtTime(s.eta_seconds);
  $("stats").textContent = s.coarse
    ? "a quick low-resolution look; sampling the full image…"
    : s.has_image
    ? `${s.spp} / ${s.target_spp} spp · ${(rate / 1e6).toFixed(2)} M samples/s · ${left}`
    : (s.failed ? "the scene has errors" : "rendering the first round…");
  $("stats").dataset.spp = s.spp;
  if (document.activeElement !== $("integrator")) $("integrator").value = s.controls.integrator;
  if (document.activeElement !== $("spp")) $("spp").value = s.controls.spp_cap ?? "";
  showDiagnostics(s.diagnostics);
  refreshImage();
}

function showDiagnostics(list) {
  const box = $("diagnostics");
  box.replaceChildren();
  const order = (d) => (d.severity === "error" ? 0 : 1);
  for (const d of [...list].sort((a, b) => order(a) - order(b))) {
    const div = el("div", undefined, "diagnostic " + d.severity);
    div.dataset.code = d.code;
    const head = el("div");
    head.append(el("code", d.code), " ", el("span", d.message, "message"));
    div.append(head);
    if (d.file) {
      const where = el("div", `${d.file}:${d.line}:${d.column}`, "where");
      div.append(where);
      div.dataset.line = d.line;
    }
    // miette's text, as `rtlang check` prints it: excerpt, marked span, help.
    div.append(el("pre", d.rendered));
    box.append(div);
  }
}

function vec(v) {
  return "(" + v.map((x) => Number(x).toPrecision(4)).join(", ") + ")";
}

function showPick(p) {
  const box = $("pick");
  box.replaceChildren();
  const table = el("table");
  const row = (name, value) => {
    const tr = el("tr");
    const td = el("td");
    if (value instanceof Node) td.append(value); else td.textContent = value;
    tr.append(el("td", name), td);
    table.append(tr);
  };
  row("pixel", `${p.x}, ${p.y}`);
  if (p.hit) {
    box.dataset.kind = p.kind;
    box.dataset.line = p.line ?? "";
    row("object", p.kind);
    row("material", p.material ?? "?");
    if (p.file) {
      const src = el("span", `${p.file}:${p.line}`, "source");
      src.id = "pick-source";
      const pre = el("pre", p.excerpt);
      pre.id = "pick-excerpt";
      pre.hidden = true;
      src.addEventListener("click", () => { pre.hidden = !pre.hidden; });
      const cell = el("div");
      cell.append(src, pre);
      row("source", cell);
    }
    row("distance", Number(p.distance).toPrecision(5));
    row("point", vec(p.point));
    row("normal", vec(p.normal));
  } else {
    box.dataset.kind = "";
    box.dataset.line = "";
    row("object", p.pick_error ?? "nothing (background)");
  }
  const se = p.std_error.map((v) => (v === null ? "?" : Number(v).toPrecision(2)));
  row("estimate", `${vec(p.estimate)} ± (${se.join(", ")}) from ${p.samples} samples`);
  box.append(table);
}

img.addEventListener("click", async (ev) => {
  const r = img.getBoundingClientRect();
  const x = Math.floor((ev.clientX - r.left) * img.naturalWidth / r.width);
  const y = Math.floor((ev.clientY - r.top) * img.naturalHeight / r.height);
  const res = await fetch(`/pick?x=${x}&y=${y}`);
  if (res.ok) showPick(await res.json());
});

async function sendControls() {
  const body = `integrator=${$("integrator").value}&spp=${$("spp").value}`;
  const res = await fetch("/controls", { method: "POST", body });
  if (res.ok) showStatus(await res.json());
}
$("integrator").addEventListener("change", sendControls);
$("spp").addEventListener("change", sendControls);
$("exposure").addEventListener("input", () => {
  $("exposure-value").textContent = Number($("exposure").value).toFixed(1);
  refreshImage();
});

new EventSource("/events").onmessage = (ev) => showStatus(JSON.parse(ev.data));
