// A Foxglove WebSocket client built on @foxglove/ws-protocol (Foxglove's own
// client library, independent of nadir's server): connects (retrying until
// the server is up), subscribes to the given topics, records what arrives
// and writes a JSON summary.
// Usage: node ws_client.js URL OUT.json [--topics A,B,...] [--disconnect-after S]
//          [--disconnect-after-messages N] [--idle-exit S] [--max-wait S]
// POSE messages are kept whole (utime, position, sigma, protection level);
// for the others counts and first/last timestamps. The last STATUS of the
// bridge itself (name "foxglove") is kept, with its peak resident memory read
// from /proc/PID/status while the client runs.
"use strict";
const fs = require("fs");
const WebSocket = require("ws");
const { FoxgloveClient } = require("@foxglove/ws-protocol");

const [url, outPath, ...rest] = process.argv.slice(2);
const opt = { topics: "POSE", disconnectAfter: 0, disconnectAfterMessages: 0, idleExit: 5, maxWait: 60 };
for (let i = 0; i < rest.length; i += 2) {
  const key = rest[i].replace(/^--/, "").replace(/-([a-z])/g, (_, c) => c.toUpperCase());
  opt[key] = key === "topics" ? rest[i + 1] : Number(rest[i + 1]);
}
const wanted = opt.topics.split(",");
const result = { url, topics: {}, pose: [], advertised: 0, status_messages: [], bridge_status: null,
                 bridge_peak_rss_kb: 0, connected: false, closed_by: null, received: 0 };
const started = Date.now();
let lastMessage = Date.now();
let done = false;

function finish(why) {
  if (done) return;
  done = true;
  result.closed_by = result.closed_by || why;
  fs.writeFileSync(outPath, JSON.stringify(result));
  process.exit(0);
}

function watchRss(pid) {
  try {
    const m = /VmRSS:\s+(\d+)/.exec(fs.readFileSync(`/proc/${pid}/status`, "utf8"));
    if (m) result.bridge_peak_rss_kb = Math.max(result.bridge_peak_rss_kb, Number(m[1]));
  } catch (e) { /* gone */ }
}

function connect() {
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const subs = new Map();  // subscription id -> topic
  client.on("error", () => {
    if (!result.connected) {
      if ((Date.now() - started) / 1000 > opt.maxWait) finish("server never came up");
      setTimeout(connect, 200);
    }
  });
  client.on("open", () => {
    result.connected = true;
    result.connected_at_ms = Date.now() - started;
    lastMessage = Date.now();
    if (opt.disconnectAfter > 0) setTimeout(() => { result.closed_by = "client (disconnect-after)"; client.close(); finish("client"); }, opt.disconnectAfter * 1000);
  });
  client.on("advertise", (channels) => {
    result.advertised += channels.length;
    for (const c of channels) {
      if (!wanted.includes(c.topic) && !wanted.includes("*")) continue;
      subs.set(client.subscribe(c.id), c.topic);
      result.topics[c.topic] = { count: 0, first_ns: null, last_ns: null, schema: c.schemaName };
    }
  });
  client.on("status", (s) => result.status_messages.push(s));
  client.on("message", ({ subscriptionId, timestamp, data }) => {
    lastMessage = Date.now();
    result.received++;
    if (opt.disconnectAfterMessages > 0 && result.received === opt.disconnectAfterMessages) {
      result.closed_by = "client (disconnect-after-messages)";
      client.close();
      finish("client");
      return;
    }
    const topic = subs.get(subscriptionId);
    const t = result.topics[topic];
    t.count++;
    if (t.first_ns === null) t.first_ns = timestamp.toString();
    t.last_ns = timestamp.toString();
    if (topic === "POSE" || topic === "STATUS") {
      const m = JSON.parse(new TextDecoder().decode(data));
      if (topic === "POSE") {
        result.pose.push([m.utime, m.north_m, m.east_m, m.down_m, m.sigma_north_m, m.protection_level_m, m.flags]);
      } else if (m.name === "foxglove") {
        result.bridge_status = m;
        watchRss(m.pid);
      }
    }
  });
  client.on("close", () => { if (result.connected) finish("server"); });
}

connect();
setInterval(() => {
  if (result.connected && opt.idleExit > 0 && Date.now() - lastMessage > opt.idleExit * 1000) finish("idle");
  if ((Date.now() - started) / 1000 > opt.maxWait + 600) finish("timeout");
}, 200);
