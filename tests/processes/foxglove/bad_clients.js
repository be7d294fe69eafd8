// Misbehaving clients against a Foxglove WebSocket server, each on its own
// connection, at the same time as the good ones: raw TCP garbage instead of
// a handshake, a handshake without the foxglove subprotocol, text that is not
// JSON, an unknown op, a subscription to a channel never advertised, binary
// frames, an oversized frame, an invalid WebSocket frame after the handshake,
// and a slow consumer (subscribes to everything, then stops reading).
// Writes what each saw (status messages, whether and how it was closed).
// Usage: node bad_clients.js HOST PORT OUT.json [--slow-pause S]
"use strict";
const fs = require("fs");
const net = require("net");
const WebSocket = require("ws");

const [host, port, outPath, , slowPauseArg] = process.argv.slice(2);
const slowPause = Number(slowPauseArg || 20);
const url = `ws://${host}:${port}`;
const PROTO = "foxglove.websocket.v1";
const results = {};

function rawGarbage() {
  return new Promise((resolve) => {
    const s = net.connect(Number(port), host, () => s.write(Buffer.from("\x00\xff garbage that is not HTTP\r\n\r\n\x16\x03")));
    let data = "";
    s.on("data", (d) => { data += d.toString("latin1"); });
    s.on("close", () => resolve({ closed: true, reply: data.split("\r\n")[0] }));
    s.on("error", () => {});
    setTimeout(() => { s.destroy(); resolve({ closed: false, reply: data.split("\r\n")[0] }); }, 8000);
  });
}

// A connection that sends `frames` (strings or Buffers) once advertised and
// collects status messages until closed or `waitMs` passes.
function session(frames, { protocols = [PROTO], waitMs = 4000, raw = null, spacingMs = 0 } = {}) {
  return new Promise((resolve) => {
    const r = { opened: false, statuses: [], closed: false, close_code: null, error: null };
    const ws = new WebSocket(url, protocols);
    ws.on("unexpected-response", (req, res) => { r.error = `HTTP ${res.statusCode}`; r.closed = true; resolve(r); });
    ws.on("error", (e) => { r.error = r.error || e.message; });
    ws.on("open", () => { r.opened = true; });
    ws.on("message", (data, isBinary) => {
      if (isBinary) return;
      const m = JSON.parse(data.toString());
      if (m.op === "advertise") {
        frames.forEach((f, i) => {
          if (!spacingMs) ws.send(f);
          else setTimeout(() => { if (ws.readyState === WebSocket.OPEN) ws.send(f); }, i * spacingMs);
        });
        if (raw) ws._socket.write(raw);
      }
      if (m.op === "status") r.statuses.push(m.message);
    });
    ws.on("close", (code) => { r.closed = true; r.close_code = code; resolve(r); });
    setTimeout(() => { ws.terminate(); resolve(r); }, waitMs);
  });
}

function slowConsumer() {
  return new Promise((resolve) => {
    const r = { opened: false, subscribed: 0, received_before_pause: 0, closed: false, close_code: null };
    const ws = new WebSocket(url, [PROTO]);
    ws.on("error", () => {});
    ws.on("message", (data, isBinary) => {
      if (isBinary) { r.received_before_pause++; return; }
      const m = JSON.parse(data.toString());
      if (m.op !== "advertise") return;
      r.opened = true;
      const subs = m.channels.map((c, i) => ({ id: 100 + i, channelId: c.id }));
      r.subscribed = subs.length;
      ws.send(JSON.stringify({ op: "subscribe", subscriptions: subs }));
      // Stop reading: the server's send buffer for this client fills up.
      setTimeout(() => ws._socket.pause(), 500);
      setTimeout(() => { ws._socket.resume(); }, slowPause * 1000);
    });
    ws.on("close", (code) => { r.closed = true; r.close_code = code; r.closed_at_s = (Date.now() - t0) / 1000; resolve(r); });
    const t0 = Date.now();
    setTimeout(() => { ws.terminate(); resolve(r); }, slowPause * 1000 + 5000);
  });
}

async function main() {
  // Wait for the server.
  for (let i = 0; i < 300; i++) {
    const up = await new Promise((res) => { const s = net.connect(Number(port), host, () => { s.destroy(); res(true); }); s.on("error", () => res(false)); });
    if (up) break;
    await new Promise((res) => setTimeout(res, 200));
  }
  await new Promise((res) => setTimeout(res, 3000));  // mid-flight
  const slow = slowConsumer();
  const parallel = await Promise.all([
    rawGarbage(),
    session([], { protocols: ["not-foxglove"] }),
    session(["this is not json", "{\"op\": 3}"]),
    session([JSON.stringify({ op: "frobnicate" })]),
    session([JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: 99999 }] })]),
    session([Buffer.from([1, 2, 3, 4])]),
    session(["x".repeat(200 * 1024)]),
    session([], { raw: Buffer.from([0x81, 0x05, 0x68, 0x65, 0x6c, 0x6c, 0x6f]) }),  // unmasked client frame
    session(Array.from({ length: 15 }, () => JSON.stringify({ op: "unadvertise" })), { waitMs: 6000, spacingMs: 50 }),
  ]);
  [results.raw_garbage, results.no_subprotocol, results.not_json, results.unknown_op, results.unknown_channel,
   results.binary, results.oversized, results.invalid_frame, results.many_errors] = parallel;
  results.slow_consumer = await slow;
  fs.writeFileSync(outPath, JSON.stringify(results, null, 1));
  process.exit(0);
}
main().catch((e) => { console.error(e); process.exit(1); });
