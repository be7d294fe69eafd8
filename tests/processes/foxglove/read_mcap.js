// Reads an MCAP file with @mcap/core (an independent implementation of the
// format), twice: through the summary and chunk indexes (McapIndexedReader)
// and as a stream with CRC validation (McapStreamReader). Compiles every
// schema with ajv (valid JSON Schema), validates every message against its
// schema and, for Foxglove's well-known schemas, against Foxglove's published
// one (@foxglove/schemas). Prints a JSON summary on stdout.
// Usage: node read_mcap.js FILE.mcap
"use strict";
const fs = require("fs");
const { McapIndexedReader, McapStreamReader } = require("@mcap/core");
const Ajv = require("ajv");
const foxgloveSchemas = require("@foxglove/schemas/jsonschema");

async function main() {
  const path = process.argv[2];
  const fd = fs.openSync(path, "r");
  const size = fs.fstatSync(fd).size;
  const readable = {
    size: async () => BigInt(size),
    read: async (offset, length) => {
      const buf = Buffer.alloc(Number(length));
      fs.readSync(fd, buf, 0, Number(length), Number(offset));
      return new Uint8Array(buf.buffer, buf.byteOffset, buf.length);
    },
  };
  const errors = [];
  const ajv = new Ajv({ strict: false, allErrors: false });
  const reader = await McapIndexedReader.Initialize({ readable });
  const validators = new Map();  // schema id -> [own, foxglove's or null]
  const schemas = {};
  for (const [id, schema] of reader.schemasById) {
    let own = null, official = null;
    try {
      own = ajv.compile(JSON.parse(new TextDecoder().decode(schema.data)));
    } catch (e) {
      errors.push(`schema ${schema.name}: not a valid JSON Schema: ${e.message}`);
    }
    const short = schema.name.startsWith("foxglove.") ? schema.name.slice(9) : null;
    if (short && foxgloveSchemas[short]) official = ajv.compile(foxgloveSchemas[short]);
    validators.set(id, [own, official]);
    schemas[schema.name] = { encoding: schema.encoding, checked_against_foxglove: official !== null };
  }
  const topics = {};
  for (const [, channel] of reader.channelsById) {
    topics[channel.topic] = { count: 0, schema: reader.schemasById.get(channel.schemaId).name,
                              lcm_channel: channel.metadata.get("lcm_channel"), first_log_ns: null, last_log_ns: null,
                              invalid: 0 };
  }
  let previous = -1n, outOfOrder = 0;
  for await (const m of reader.readMessages()) {
    const channel = reader.channelsById.get(m.channelId);
    const t = topics[channel.topic];
    t.count++;
    if (t.first_log_ns === null) t.first_log_ns = m.logTime.toString();
    t.last_log_ns = m.logTime.toString();
    if (m.logTime < previous) outOfOrder++;
    previous = m.logTime;
    let value;
    try {
      value = JSON.parse(new TextDecoder().decode(m.data));
    } catch (e) {
      t.invalid++;
      if (errors.length < 20) errors.push(`${channel.topic}: message is not JSON`);
      continue;
    }
    for (const v of validators.get(channel.schemaId)) {
      if (v && !v(value)) {
        t.invalid++;
        if (errors.length < 20) errors.push(`${channel.topic}: ${ajv.errorsText(v.errors)}`);
        break;
      }
    }
  }
  // The stream, with every CRC checked.
  const stream = new McapStreamReader({ validateCrcs: true });
  const streamCounts = {};
  const streamChannels = new Map();
  const chunk = Buffer.alloc(8 << 20);
  let pos = 0, records = 0;
  for (;;) {
    const n = fs.readSync(fd, chunk, 0, chunk.length, pos);
    if (n === 0) break;
    pos += n;
    stream.append(new Uint8Array(chunk.buffer, 0, n).slice());
    let r;
    while ((r = stream.nextRecord())) {
      records++;
      if (r.type === "Channel") streamChannels.set(r.id, r.topic);
      if (r.type === "Message") {
        // File order: first and last sensor time (publish time) and log time per topic.
        const topic = streamChannels.get(r.channelId);
        const c = streamCounts[topic] || (streamCounts[topic] = { count: 0, first_publish_ns: r.publishTime.toString(),
                                                                  first_log_ns: r.logTime.toString() });
        c.count++;
        c.last_publish_ns = r.publishTime.toString();
        c.last_log_ns = r.logTime.toString();
      }
    }
  }
  if (!stream.done()) errors.push("stream reader: file ended before the footer and magic");
  const s = reader.statistics;
  console.log(JSON.stringify({
    file: path,
    bytes: size,
    chunks: reader.chunkIndexes.length,
    statistics: s ? { message_count: s.messageCount.toString(), channel_count: s.channelCount,
                      schema_count: s.schemaCount, chunk_count: s.chunkCount,
                      message_start_ns: s.messageStartTime.toString(), message_end_ns: s.messageEndTime.toString() }
                  : null,
    out_of_order: outOfOrder,
    schemas, topics, stream_records: records, stream_counts: streamCounts, errors,
  }, null, 1));
}

main().catch((e) => { console.error(`read_mcap: error: ${e.stack || e}`); process.exit(1); });
