#!/usr/bin/python3
"""Writes DIR/index.html from an evaluation folder written by nadir_eval
(metrics.json, series.csv, pairs.csv, trajectory.geojson): one self-contained
page (inline CSS, JavaScript and SVG, the data embedded; no network) with the
key figures, the trajectory over a local grid (OpenStreetMap tiles behind it
only when the reader ticks the box and is online), error, sigma and
protection-level plots against time, the pairs table and the process table.
Usage: report_html.py DIR"""
import csv
import html
import json
import sys

PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>nadir report: __TITLE__</title>
<link rel="icon" href="data:,">
<style>
body{font-family:system-ui,sans-serif;margin:0;background:#f6f7f9;color:#1c2330}
header{background:#1c2330;color:#fff;padding:14px 24px}
header h1{margin:0;font-size:20px}header p{margin:4px 0 0;color:#b8c2d3;font-size:13px}
main{padding:16px 24px;display:grid;grid-template-columns:repeat(auto-fit,minmax(560px,1fr));gap:16px}
section{background:#fff;border:1px solid #dde2ea;border-radius:6px;padding:12px 16px}
section.wide{grid-column:1/-1}h2{font-size:15px;margin:0 0 8px}
.figures{display:flex;flex-wrap:wrap;gap:10px}.fig{min-width:150px;padding:6px 10px;border-left:3px solid #3a7bd5;background:#f0f4fa}
.fig b{display:block;font-size:18px}.fig span{font-size:12px;color:#5a6577}
svg{width:100%;height:auto;background:#fff}svg text{font-size:11px;fill:#444}
.grid line{stroke:#e3e7ee}.axis{stroke:#888}.legend{font-size:12px}
table{border-collapse:collapse;font-size:12px;width:100%}th,td{padding:3px 6px;text-align:right;border-bottom:1px solid #eef0f4}
th{position:sticky;top:0;background:#eef2f8;cursor:pointer}td:first-child,th:first-child{text-align:left}
.scroll{max-height:360px;overflow:auto}tr.bad td{background:#fdecea}
#readout{font-size:12px;color:#5a6577;min-height:1.2em}label{font-size:12px}
rect.coast{fill:#8a94a6;opacity:.25}
</style></head><body data-rendered="no">
<header><h1>nadir flight report</h1><p>__SUBTITLE__</p></header>
<main>
<section class="wide"><h2>Key figures</h2><div class="figures" id="figures"></div></section>
<section><h2>Trajectory (east/north, m)</h2>
<label><input type="checkbox" id="osm"> OpenStreetMap background (needs a network; off: nothing is fetched)</label>
<svg id="trajectory" viewBox="0 0 600 600" role="img" aria-label="trajectory"></svg><div id="readout"></div></section>
<section><h2>Position error and 3&sigma; (m)</h2><svg id="errors" viewBox="0 0 600 300" role="img" aria-label="errors"></svg>
<h2>Protection level vs horizontal error (m)</h2><svg id="protection" viewBox="0 0 600 300" role="img" aria-label="protection level"></svg>
<h2>Yaw error and 3&sigma; (deg)</h2><svg id="yaw" viewBox="0 0 600 240" role="img" aria-label="yaw"></svg></section>
<section class="wide"><h2>Processes</h2><table id="processes"></table></section>
<section class="wide"><h2>Frame pairs (<span id="pairs-count"></span>; red: not solved or error above 5 % of the step; click a header to sort)</h2>
<div class="scroll"><table id="pairs"></table></div></section>
</main>
<script id="data" type="application/json">__DATA__</script>
<script>
"use strict";
const D = JSON.parse(document.getElementById("data").textContent);
const NS = "http://www.w3.org/2000/svg";
function el(tag, attrs, parent, text) {
  const e = document.createElementNS(NS, tag);
  for (const k in attrs) e.setAttribute(k, attrs[k]);
  if (text !== undefined) e.textContent = text;
  if (parent) parent.appendChild(e);
  return e;
}
function ticks(lo, hi, n) {
  const span = hi - lo || 1, step0 = span / n, mag = Math.pow(10, Math.floor(Math.log10(step0)));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= step0);
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9; v += step) out.push(+v.toFixed(10));
  return out;
}
function fmt(v, d) { return (v === null || v === undefined || Number.isNaN(v)) ? "" : (+v).toFixed(d); }
// A line chart: series [{name, x[], y[], color, dash}] in a <svg> of the given viewBox size.
function chart(svg, series, opts) {
  const W = +svg.viewBox.baseVal.width, H = +svg.viewBox.baseVal.height, m = {l: 50, r: 10, t: 10, b: 30};
  let xs = [], ys = [];
  for (const s of series) { xs = xs.concat(s.x); ys = ys.concat(s.y.filter((v) => Number.isFinite(v))); }
  let [x0, x1] = [Math.min(...xs), Math.max(...xs)], [y0, y1] = [Math.min(0, ...ys), Math.max(...ys)];
  if (opts && opts.equal) {
    const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2, half = Math.max(x1 - x0, y1 - y0) / 2 * 1.08 + 1;
    [x0, x1, y0, y1] = [cx - half, cx + half, cy - half, cy + half];
  }
  if (y1 === y0) y1 = y0 + 1;
  const X = (v) => m.l + (v - x0) / (x1 - x0) * (W - m.l - m.r), Y = (v) => H - m.b - (v - y0) / (y1 - y0) * (H - m.t - m.b);
  const g = el("g", {class: "grid"}, svg);
  for (const t of ticks(x0, x1, 8)) { el("line", {x1: X(t), x2: X(t), y1: m.t, y2: H - m.b}, g); el("text", {x: X(t), y: H - m.b + 14, "text-anchor": "middle"}, svg, t); }
  for (const t of ticks(y0, y1, 6)) { el("line", {x1: m.l, x2: W - m.r, y1: Y(t), y2: Y(t)}, g); el("text", {x: m.l - 4, y: Y(t) + 4, "text-anchor": "end"}, svg, t); }
  el("rect", {x: m.l, y: m.t, width: W - m.l - m.r, height: H - m.t - m.b, fill: "none", class: "axis"}, svg);
  let ly = m.t + 14;
  // Shaded time spans (the coasts), behind the curves.
  const bands = (opts && opts.bands) || [];
  for (const [a, b] of bands) el("rect", {x: X(a), y: m.t, width: Math.max(1, X(b) - X(a)), height: H - m.t - m.b, class: "coast"}, svg);
  if (bands.length) { el("text", {x: W - m.r - 6, y: ly, "text-anchor": "end", class: "legend", style: "fill:#5a6577"}, svg, "coasting (shaded)"); ly += 14; }
  for (const s of series) {
    let d = "";
    for (let i = 0; i < s.x.length; i++) if (Number.isFinite(s.y[i])) d += (d ? "L" : "M") + X(s.x[i]).toFixed(1) + " " + Y(s.y[i]).toFixed(1);
    el("path", {d, fill: "none", stroke: s.color, "stroke-width": s.width || 1.5, "stroke-dasharray": s.dash || "", class: "series " + (s.cls || "")}, svg);
    if (!s.name) continue;
    el("text", {x: W - m.r - 6, y: ly, "text-anchor": "end", class: "legend", style: "fill:" + s.color}, svg, s.name);
    ly += 14;
  }
  if (opts && opts.xlabel) el("text", {x: (W + m.l) / 2, y: H - 2, "text-anchor": "middle"}, svg, opts.xlabel);
  return {X, Y, x0, x1, y0, y1};
}
const S = D.series, col = (k) => S.map((r) => r[k]), t = col("t_s");
// Key figures.
const M = D.metrics, F = document.getElementById("figures");
const coasts = M.coasts || [], coastBands = coasts.map((c) => [c.start_s, c.start_s + c.duration_s]);
const coastAdded = (k) => Math.max(0, ...coasts.map((c) => Math.abs(c[k])));
for (const [label, value, note] of [
  ["distance flown", fmt(M.distance_m, 0) + " m in " + fmt(M.duration_s, 0) + " s"],
  ["final error", fmt(M.final_error_3d_m, 2) + " m (" + fmt(M.error_pct_3d, 3) + " %)"],
  ["RMS horizontal error", fmt(M.rms_error_h_m, 2) + " m"],
  ["yaw error RMS", fmt(M.rms_yaw_error_deg, 3) + " deg",
   M.imported ? "fused yaw vs the flight's recorded yaw (the INS the estimator fuses: not independent)"
              : "fused yaw vs truth yaw at each pose"],
  ["pairs solved", fmt(M.pairs_solved_pct, 1) + " % of " + M.pairs,
   M.pairs_not_solved_flagged ? M.pairs_not_solved_flagged + " flagged, not solved: " + M.pairs_not_solved_why : ""],
  ["NEES within 95 %", fmt(M.nees_h_within_95_pct, 1) + " %"],
  ["protection level exceeded", fmt(M.pl_exceeded_pct, 2) + " %"],
  M.latency_measured === false
    ? ["latency", "not measured", M.imported ? "an imported flight" : "a lockstep replay"]
    : ["latency p50 / p99", fmt(M.latency_p50_ms, 1) + " / " + fmt(M.latency_p99_ms, 1) + " ms"],
  ["poses (flagged)", M.poses + " (" + M.poses_flagged + ")"],
  coasts.length
    ? ["coasting", fmt(M.coast_s, 1) + " s in " + coasts.length + (coasts.length === 1 ? " episode" : " episodes"),
       "VO out, the position held (shaded in the plots); error added by one at most " + fmt(coastAdded("added_h_m"), 2) +
       " m horizontal, " + fmt(coastAdded("added_v_m"), 2) + " m vertical"]
    : ["coasting", "none", "VO never out"]]) {
  const d = document.createElement("div");
  d.className = "fig";
  d.innerHTML = "<b></b><span></span>";
  d.firstChild.textContent = value;
  d.lastChild.textContent = note ? label + ": " + note : label;
  F.appendChild(d);
}
// Trajectory over a local grid; OSM tiles on request only.
const traj = document.getElementById("trajectory");
const tr = chart(traj, [
  {name: "ground truth", x: col("true_e"), y: col("true_n"), color: "#d62728", width: 2.5, cls: "truth"},
  {name: "nadir estimate", x: col("est_e"), y: col("est_n"), color: "#1f77b4", cls: "estimate"}], {equal: true});
el("circle", {cx: tr.X(0), cy: tr.Y(0), r: 4, fill: "#000"}, traj);
const readout = document.getElementById("readout");
traj.addEventListener("mousemove", (ev) => {
  const p = traj.createSVGPoint(); p.x = ev.clientX; p.y = ev.clientY;
  const q = p.matrixTransform(traj.getScreenCTM().inverse());
  let best = 0, bd = Infinity;
  for (let i = 0; i < S.length; i++) { const d = (tr.X(S[i].est_e) - q.x) ** 2 + (tr.Y(S[i].est_n) - q.y) ** 2; if (d < bd) { bd = d; best = i; } }
  const r = S[best];
  readout.textContent = "t " + fmt(r.t_s, 2) + " s: error " + fmt(r.error_h_m, 2) + " m horizontal, 3 sigma " + fmt(3 * r.sigma_h_m, 2) + " m, protection level " + fmt(r.protection_level_m, 2) + " m, flags " + r.flags;
});
document.getElementById("osm").addEventListener("change", (ev) => {
  const old = document.getElementById("tiles");
  if (old) old.remove();
  if (!ev.target.checked || !D.reference) return;
  // Web-Mercator tiles covering the plotted square, drawn under the grid.
  const lat0 = D.reference.lat, lon0 = D.reference.lon, R = 6378137, deg = Math.PI / 180;
  const toLL = (e, n) => [lat0 + n / R / deg, lon0 + e / (R * Math.cos(lat0 * deg)) / deg];
  const span = tr.x1 - tr.x0, z = Math.max(1, Math.min(18, Math.round(Math.log2(40075016 * Math.cos(lat0 * deg) / span * 2.5))));
  const tile = (lat, lon) => [(lon + 180) / 360 * 2 ** z, (1 - Math.log(Math.tan(lat * deg) + 1 / Math.cos(lat * deg)) / Math.PI) / 2 * 2 ** z];
  const g = el("g", {id: "tiles", opacity: 0.6}, null);
  traj.insertBefore(g, traj.firstChild);
  const [la1, lo1] = toLL(tr.x0, tr.y1), [la2, lo2] = toLL(tr.x1, tr.y0);
  const [tx0, ty0] = tile(la1, lo1), [tx1, ty1] = tile(la2, lo2);
  const fromTile = (x, y) => { const lon = x / 2 ** z * 360 - 180, n = Math.PI - 2 * Math.PI * y / 2 ** z, lat = Math.atan(Math.sinh(n)) / deg;
    return [(lon - lon0) * deg * R * Math.cos(lat0 * deg), (lat - lat0) * deg * R]; };
  for (let x = Math.floor(tx0); x <= Math.floor(tx1); x++) for (let y = Math.floor(ty0); y <= Math.floor(ty1); y++) {
    const [e0, n0] = fromTile(x, y), [e1, n1] = fromTile(x + 1, y + 1);
    const img = el("image", {x: tr.X(e0), y: tr.Y(n0), width: tr.X(e1) - tr.X(e0), height: tr.Y(n1) - tr.Y(n0), preserveAspectRatio: "none"}, g);
    img.setAttribute("href", "https://tile.openstreetmap.org/" + z + "/" + x + "/" + y + ".png");
  }
});
// Error, sigma, protection level.
const ne = S.map((r) => r.est_n - r.true_n), ee = S.map((r) => r.est_e - r.true_e);
chart(document.getElementById("errors"), [
  {name: "north error", x: t, y: ne, color: "#1f77b4"},
  {name: "east error", x: t, y: ee, color: "#ff7f0e"},
  {name: "vertical error", x: t, y: col("error_v_m"), color: "#2ca02c"},
  {name: "±3σ north", x: t, y: col("sigma_n_m").map((v) => 3 * v), color: "#1f77b4", dash: "4 3", width: 1},
  {name: "", x: t, y: col("sigma_n_m").map((v) => -3 * v), color: "#1f77b4", dash: "4 3", width: 1},
  {name: "±3σ east", x: t, y: col("sigma_e_m").map((v) => 3 * v), color: "#ff7f0e", dash: "4 3", width: 1},
  {name: "", x: t, y: col("sigma_e_m").map((v) => -3 * v), color: "#ff7f0e", dash: "4 3", width: 1}], {xlabel: "time (s)", bands: coastBands});
chart(document.getElementById("protection"), [
  {name: "horizontal error", x: t, y: col("error_h_m"), color: "#1f77b4"},
  {name: "protection level (99 %)", x: t, y: col("protection_level_m").map((v) => v < 0 ? NaN : v), color: "#d62728"}], {xlabel: "time (s)", bands: coastBands});
chart(document.getElementById("yaw"), [
  {name: "yaw error", x: t, y: col("yaw_error_deg"), color: "#9467bd"},
  {name: "±3σ", x: t, y: col("sigma_yaw_deg").map((v) => 3 * v), color: "#9467bd", dash: "4 3", width: 1},
  {name: "", x: t, y: col("sigma_yaw_deg").map((v) => -3 * v), color: "#9467bd", dash: "4 3", width: 1}], {xlabel: "time (s)", bands: coastBands});
// Tables.
function table(id, columns, rows, bad) {
  const tab = document.getElementById(id);
  const head = tab.createTHead().insertRow();
  const body = tab.createTBody();
  const fill = (list) => {
    body.textContent = "";
    for (const r of list) {
      const tr_ = body.insertRow();
      if (bad && bad(r)) tr_.className = "bad";
      for (const [k, d] of columns) tr_.insertCell().textContent = typeof r[k] === "number" && d !== undefined ? fmt(r[k], d) : r[k];
    }
  };
  columns.forEach(([k], i) => {
    const th = document.createElement("th");
    th.textContent = k;
    let asc = true;
    th.addEventListener("click", () => { rows.sort((a, b) => (a[k] > b[k] ? 1 : a[k] < b[k] ? -1 : 0) * (asc ? 1 : -1)); asc = !asc; fill(rows); });
    head.appendChild(th);
  });
  fill(rows);
}
const procRows = Object.entries(M.processes || {}).map(([name, p]) => Object.assign({process: name}, p));
const procCols = [["process"]].concat(Object.keys(procRows[0] || {}).filter((k) => k !== "process").map((k) => [k, 0]));
table("processes", procCols, procRows, (r) => r.errors > 0 || r.malformed > 0);
const t0 = D.pairs.length ? D.pairs[0].utime : 0;
const pairs = D.pairs.map((p) => Object.assign({t_s: (p.utime - t0) / 1e6}, p));
document.getElementById("pairs-count").textContent = pairs.length + " pairs";
table("pairs", [["t_s", 2], ["step_m", 3], ["dx", 3], ["dy", 3], ["true_x", 3], ["true_y", 3], ["dyaw_deg", 4], ["true_dyaw_deg", 4],
  ["error_h_m", 3], ["error_pct", 2], ["inliers", 0], ["quality", 0], ["solved", 0], ["overlap_pct", 1]], pairs,
  (r) => !r.solved || r.error_pct > 5);
document.body.setAttribute("data-rendered", "ok");
</script></body></html>
"""


def read_csv(path):
    try:
        with open(path, newline="") as f:
            return [{k: float(v) if v not in ("", None) else None for k, v in r.items()} for r in csv.DictReader(f)]
    except FileNotFoundError:
        return []


def reference(folder):
    """Latitude/longitude of the local grid's origin, from trajectory.geojson."""
    try:
        with open(f"{folder}/trajectory.geojson") as f:
            lon, lat = json.load(f)["features"][0]["geometry"]["coordinates"][0][:2]
        return {"lat": lat, "lon": lon}
    except (FileNotFoundError, KeyError, IndexError, ValueError):
        return None


def main() -> int:
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) == 2 else 2
    folder = sys.argv[1]
    with open(f"{folder}/metrics.json") as f:
        metrics = json.load(f)
    series = read_csv(f"{folder}/series.csv")
    if not series:
        print(f"report_html: {folder}/series.csv has no rows", file=sys.stderr)
        return 1
    data = {"metrics": metrics, "series": series, "pairs": read_csv(f"{folder}/pairs.csv"),
            "reference": reference(folder)}
    # allow_nan=False would fail on NaN: write them as null instead.
    text = json.dumps(data, separators=(",", ":"), default=str).replace("NaN", "null").replace("Infinity", "null")
    title = f"{metrics['distance_m']:.0f} m flown, final error {metrics['final_error_3d_m']:.2f} m"
    subtitle = (f"{title} ({metrics['error_pct_3d']:.3f} % of distance) over {metrics['duration_s']:.0f} s; "
                f"{metrics['poses']} poses, {metrics['pairs']} frame pairs")
    page = (PAGE.replace("__TITLE__", html.escape(title)).replace("__SUBTITLE__", html.escape(subtitle))
            .replace("__DATA__", text.replace("</", "<\\/")))
    with open(f"{folder}/index.html", "w") as f:
        f.write(page)
    return 0


if __name__ == "__main__":
    sys.exit(main())
