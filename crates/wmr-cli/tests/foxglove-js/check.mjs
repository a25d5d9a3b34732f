// Reads a wmr-cli MCAP file the way Foxglove does and reports what it finds.
//
//   node check.mjs FILE.mcap [SEEKS]
//
// 1. @mcap/core's indexed reader (as Foxglove/Lichtblick's McapIndexedIterableSource) and its
//    streaming reader both read every message; CRCs are checked; every channel's schema is
//    parsed with protobufjs from its FileDescriptorSet (as Lichtblick's parseProtobufSchema)
//    and every message decoded with it.
// 2. Foxglove's seek: for SEEKS times spread over the file (default 24), the latest message
//    of every topic at or before the time, read topic by topic with a reverse indexed read
//    (McapIndexedIterableSource.getBackfillMessages); the decompressed bytes are counted.
// 3. What the 3D panel then shows of each run's path (the line strips of the latest
//    /runN/scene, /runN/path and /runN/path_tip messages, with their deletions) against the
//    positions of the /runN/sample messages up to that time: the largest distance of a
//    logged position from the drawn path and of a drawn vertex from the logged path.
//
// Prints one JSON object on stdout; exits 1 (with the reason on stderr) when a check fails.

import { readFileSync } from "node:fs";
import mcapCore from "@mcap/core";
import protobufjs from "protobufjs";
import descriptor from "protobufjs/ext/descriptor/index.js";
import zstd from "@lichtblick/wasm-zstd";

const { McapIndexedReader, McapStreamReader } = mcapCore;

const [file, seeksArg] = process.argv.slice(2);
if (!file) {
  console.error("usage: node check.mjs FILE.mcap [SEEKS]");
  process.exit(2);
}
const SEEKS = Number(seeksArg ?? 24);
const TOLERANCE_M = 0.01;

function fail(msg) {
  console.error(`check.mjs: ${msg}`);
  process.exit(1);
}

await zstd.isLoaded;
let decompressedBytes = 0;
let decompressedChunks = 0;
const decompressHandlers = {
  zstd: (buffer, size) => {
    decompressedBytes += Number(size);
    decompressedChunks += 1;
    return new Uint8Array(zstd.decompress(buffer, Number(size)));
  },
};

const bytes = readFileSync(file);
const readable = {
  size: async () => BigInt(bytes.byteLength),
  read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
};
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });

// Schemas, parsed as Lichtblick's parseProtobufSchema does.
const decoders = new Map(); // channel id -> decode(bytes) -> object
const topicOf = new Map();
const schemaOf = new Map();
for (const channel of reader.channelsById.values()) {
  const schema = reader.schemasById.get(channel.schemaId);
  if (!schema) fail(`channel ${channel.topic} has no schema`);
  topicOf.set(channel.id, channel.topic);
  schemaOf.set(channel.topic, schema.name);
  if (channel.messageEncoding === "json" && schema.encoding === "jsonschema") {
    // Files written before the topics became protobuf (kept readable for comparisons).
    const text = new TextDecoder();
    decoders.set(channel.id, (data) => JSON.parse(text.decode(data)));
    continue;
  }
  if (channel.messageEncoding !== "protobuf" || schema.encoding !== "protobuf") {
    fail(`${channel.topic}: encoding ${channel.messageEncoding}/${schema.encoding}, expected protobuf`);
  }
  const set = descriptor.FileDescriptorSet.decode(schema.data);
  const root = protobufjs.Root.fromDescriptor(set);
  root.resolveAll();
  const type = root.lookupType(schema.name);
  decoders.set(channel.id, (data) => type.toObject(type.decode(data), { defaults: true, longs: Number }));
}

// 1. Every message, indexed (CRCs checked) and streamed.
const perTopic = {};
const samples = new Map(); // run -> [{t (ns), x, y}]
decompressedBytes = 0;
for await (const m of reader.readMessages({ validateCrcs: true })) {
  const topic = topicOf.get(m.channelId);
  const msg = decoders.get(m.channelId)(m.data);
  perTopic[topic] = (perTopic[topic] ?? 0) + 1;
  const match = /^\/run(\d+)\/sample$/.exec(topic);
  if (match) {
    const run = Number(match[1]);
    if (!samples.has(run)) samples.set(run, []);
    samples.get(run).push({ t: m.logTime, x: msg.x, y: msg.y });
  }
}
const fullReadBytes = decompressedBytes;
let streamed = 0;
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(bytes);
for (let rec; (rec = stream.nextRecord()); ) {
  if (rec.type === "Message") {
    decoders.get(rec.channelId)(rec.data);
    streamed += 1;
  }
}
if (!stream.done()) fail("the streaming reader did not reach the end of the file");
const indexed = Object.values(perTopic).reduce((a, b) => a + b, 0);
if (streamed !== indexed) fail(`streaming reader read ${streamed} messages, indexed reader ${indexed}`);
const stats = reader.statistics;
if (stats && Number(stats.messageCount) !== indexed) {
  fail(`statistics say ${stats.messageCount} messages, the reader read ${indexed}`);
}

// 2. Seeks, as Foxglove's getBackfillMessages: one reverse read per topic.
const topics = [...new Set(topicOf.values())].sort();
let start, end;
for (const c of reader.chunkIndexes) {
  if (start === undefined || c.messageStartTime < start) start = c.messageStartTime;
  if (end === undefined || c.messageEndTime > end) end = c.messageEndTime;
}
async function backfill(time) {
  const latest = new Map();
  for (const topic of topics) {
    for await (const m of reader.readMessages({ endTime: time, topics: [topic], reverse: true, validateCrcs: false })) {
      latest.set(topic, { logTime: m.logTime, msg: decoders.get(m.channelId)(m.data) });
      break;
    }
  }
  return latest;
}

function segDist(px, py, ax, ay, bx, by) {
  const dx = bx - ax, dy = by - ay;
  const l2 = dx * dx + dy * dy;
  let t = l2 === 0 ? 0 : ((px - ax) * dx + (py - ay) * dy) / l2;
  t = Math.max(0, Math.min(1, t));
  return Math.hypot(px - (ax + t * dx), py - (ay + t * dy));
}
function distToPolylines(px, py, lines) {
  let best = Infinity;
  for (const pts of lines) {
    if (pts.length === 1) best = Math.min(best, Math.hypot(px - pts[0].x, py - pts[0].y));
    for (let i = 1; i < pts.length; i++) {
      best = Math.min(best, segDist(px, py, pts[i - 1].x, pts[i - 1].y, pts[i].x, pts[i].y));
    }
  }
  return best;
}

// 3. The drawn path of run `run` from the backfilled scene updates.
function drawnPath(latest, run) {
  const lines = [];
  for (const name of ["scene", "path", "path_tip"]) {
    const m = latest.get(`/run${run}/${name}`);
    if (!m) continue;
    const entities = new Map();
    for (const d of m.msg.deletions) {
      if (d.type === 1) entities.clear();
      else entities.delete(d.id);
    }
    for (const e of m.msg.entities) entities.set(e.id, e);
    for (const e of entities.values()) {
      if (e.frame_id !== "world" && e.lines.length > 0) fail(`path entity in frame ${e.frame_id}`);
      for (const l of e.lines) lines.push(l.points);
    }
  }
  return lines;
}

const seekTimes = [];
for (let i = 1; i <= SEEKS; i++) seekTimes.push(start + ((end - start) * BigInt(i)) / BigInt(SEEKS));
let worstSeekBytes = 0, totalSeekBytes = 0, worstSeekChunks = 0, worstMissing = 0, worstExtra = 0;
for (const time of seekTimes) {
  decompressedBytes = 0;
  decompressedChunks = 0;
  const latest = await backfill(time);
  worstSeekBytes = Math.max(worstSeekBytes, decompressedBytes);
  worstSeekChunks = Math.max(worstSeekChunks, decompressedChunks);
  totalSeekBytes += decompressedBytes;
  for (const [run, all] of samples) {
    const truth = all.filter((s) => s.t <= time);
    if (truth.length < 2) continue;
    const lines = drawnPath(latest, run);
    if (lines.length === 0) {
      const moved = truth.some((s) => Math.hypot(s.x - truth[0].x, s.y - truth[0].y) > TOLERANCE_M);
      if (moved) fail(`run ${run}: nothing drawn after a seek to ${time} ns, but C moved`);
      continue;
    }
    for (const s of truth) worstMissing = Math.max(worstMissing, distToPolylines(s.x, s.y, lines));
    const truthLine = [truth];
    for (const pts of lines) for (const p of pts) worstExtra = Math.max(worstExtra, distToPolylines(p.x, p.y, truthLine));
  }
}

const summary = {
  file,
  bytes: bytes.byteLength,
  chunks: reader.chunkIndexes.length,
  messages: indexed,
  messagesPerTopic: perTopic,
  schemas: Object.fromEntries(topics.map((t) => [t, schemaOf.get(t)])),
  decompressedBytesFullRead: fullReadBytes,
  seeks: SEEKS,
  seekDecompressedBytesMax: worstSeekBytes,
  seekDecompressedBytesMean: Math.round(totalSeekBytes / SEEKS),
  seekDecompressedChunksMax: worstSeekChunks,
  pathAfterSeekMaxMissingM: worstMissing,
  pathAfterSeekMaxExtraM: worstExtra,
};
console.log(JSON.stringify(summary, null, 1));
if (worstMissing > TOLERANCE_M || worstExtra > TOLERANCE_M) {
  fail(`the path after a seek is off by ${Math.max(worstMissing, worstExtra)} m (> ${TOLERANCE_M} m)`);
}
