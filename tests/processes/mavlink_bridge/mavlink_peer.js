#!/usr/bin/env node
// The independent MAVLink implementation the bridge's codec is checked
// against: node-mavlink (npm), over real UDP sockets.
//   node mavlink_peer.js listen COUNT TIMEOUT_MS
//     binds 127.0.0.1 on a free port, prints "PORT <n>", then one JSON line per
//     packet node-mavlink splits, checks and decodes:
//     {"version", "sysid", "compid", "seq", "msgid", "name", "fields": {snake_name: value}}
//     (64-bit integers as strings); exits after COUNT packets or TIMEOUT_MS.
//   node mavlink_peer.js send HOST:PORT FILE
//     FILE: JSON lines {"name", "version" (1|2), "sysid", "compid", "seq", "fields"}; each is
//     encoded by node-mavlink and sent as one datagram.
'use strict';
const dgram = require('dgram');
const fs = require('fs');
const { PassThrough } = require('stream');
const { MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV1, MavLinkProtocolV2,
  minimal, common } = require('node-mavlink');

const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY };
const BY_NAME = {};
for (const clazz of Object.values(REGISTRY)) BY_NAME[clazz.MSG_NAME] = clazz;

function toJson(value) {
  if (typeof value === 'bigint') return value.toString();
  if (Array.isArray(value)) return value.map(toJson);
  if (typeof value === 'number' && !Number.isFinite(value)) return String(value);
  return value;
}

function fromJson(value, type) {
  if (Array.isArray(value)) return value.map((v) => fromJson(v, type));
  if (type.startsWith('int64') || type.startsWith('uint64')) return BigInt(value);
  if (typeof value === 'string') return Number(value);  // "NaN", "Infinity"
  return value;
}

function listen(count, timeoutMs) {
  const socket = dgram.createSocket('udp4');
  const input = new PassThrough();
  const reader = input.pipe(new MavLinkPacketSplitter()).pipe(new MavLinkPacketParser());
  let seen = 0;
  const done = () => { socket.close(); process.exit(0); };
  reader.on('data', (packet) => {
    const clazz = REGISTRY[packet.header.msgid];
    const out = {
      version: packet.header.magic === 0xFD ? 2 : 1, sysid: packet.header.sysid, compid: packet.header.compid,
      seq: packet.header.seq, msgid: packet.header.msgid, name: clazz ? clazz.MSG_NAME : null, fields: {},
    };
    if (clazz) {
      const data = packet.protocol.data(packet.payload, clazz);
      for (const f of clazz.FIELDS) out.fields[f.source] = toJson(data[f.name]);
    }
    process.stdout.write(JSON.stringify(out) + '\n');
    if (++seen >= count) setImmediate(done);
  });
  socket.on('message', (msg) => input.write(msg));
  socket.bind(0, '127.0.0.1', () => {
    process.stdout.write('PORT ' + socket.address().port + '\n');
  });
  setTimeout(done, timeoutMs);
}

function send(target, file) {
  const [host, port] = target.split(':');
  const socket = dgram.createSocket('udp4');
  const lines = fs.readFileSync(file, 'utf8').split('\n').filter((l) => l.trim().length);
  let pending = lines.length;
  if (!pending) process.exit(0);
  for (const line of lines) {
    const spec = JSON.parse(line);
    const clazz = BY_NAME[spec.name];
    if (!clazz) throw new Error('node-mavlink has no message ' + spec.name);
    const msg = new clazz();
    for (const f of clazz.FIELDS) {
      if (f.source in spec.fields) msg[f.name] = fromJson(spec.fields[f.source], f.type);
    }
    const protocol = spec.version === 1 ? new MavLinkProtocolV1(spec.sysid, spec.compid)
      : new MavLinkProtocolV2(spec.sysid, spec.compid);
    const buffer = protocol.serialize(msg, spec.seq);
    socket.send(buffer, Number(port), host, () => { if (--pending === 0) { socket.close(); } });
  }
}

const [mode, a, b] = process.argv.slice(2);
if (mode === 'listen') listen(Number(a), Number(b));
else if (mode === 'send') send(a, b);
else {
  process.stderr.write('usage: mavlink_peer.js listen COUNT TIMEOUT_MS | send HOST:PORT FILE\n');
  process.exit(2);
}
