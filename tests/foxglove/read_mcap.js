// Reads an MCAP written by ucon-mcap with the official readers (@mcap/core: the streaming
// reader, which checks chunk CRCs, and the indexed reader, which goes through the summary and
// the chunk and message indexes) and checks it against the LCM log it came from:
//   - every LCM channel is a topic, with as many messages as the log has events on it;
//   - every schema is valid JSON Schema (ajv) and of the form Foxglove's jsonschema parser
//     takes; every message is JSON that validates against its channel's schema;
//   - log time = the message's utime; statistics and indexes agree with the messages;
//   - the point clouds' packed bytes hold the log's points at the fields' offsets;
//   - the Foxglove views (transforms, poses, scene updates, trajectory, map) are there;
//   - the data section and summary CRCs are right.
//   - with --layout: every topic the shipped Foxglove layout shows is in the file, and every
//     value its plots pick by name is there.
// usage: node read_mcap.js --log run.lcm --mcap run.mcap [--events N] [--no-views] [--layout L]
//   --events N: the MCAP should hold the first N events of the log (a damaged log's export).
"use strict";
const fs = require("fs");
const path = require("path");
const { createRequire } = require("module");

const modules = process.env.UCON_NODE_MODULES;
if (!modules) throw new Error("UCON_NODE_MODULES is not set");
const req = createRequire(path.join(modules, "index.js"));
const { McapIndexedReader, McapStreamReader } = req("@mcap/core");
const { loadDecompressHandlers } = req("@mcap/support");
const { FileHandleReadable } = req("@mcap/nodejs");
const { crc32 } = req("@foxglove/crc");
const Ajv = req("ajv");

const args = {};
for (let i = 2; i < process.argv.length; i++) {
  const a = process.argv[i];
  if (a === "--no-views") args.noViews = true;
  else args[a.replace(/^--/, "")] = process.argv[++i];
}

let failures = 0;
let passes = 0;
function check(what, ok, detail) {
  if (ok) {
    passes++;
  } else {
    failures++;
    console.log(`FAIL: ${what}${detail !== undefined ? ": " + detail : ""}`);
  }
}

// LCM log events (big-endian: sync, event number, timestamp, channel length, data length).
function readLcmLog(file, limit) {
  const b = fs.readFileSync(file);
  const events = [];
  let at = 0;
  while (at + 28 <= b.length && (limit === undefined || events.length < limit)) {
    if (b.readUInt32BE(at) !== 0xeda1da01) break;
    const chLen = b.readInt32BE(at + 20);
    const dataLen = b.readInt32BE(at + 24);
    if (at + 28 + chLen + dataLen > b.length) break;
    const channel = b.toString("latin1", at + 28, at + 28 + chLen);
    events.push({ channel, data: b.subarray(at + 28 + chLen, at + 28 + chLen + dataLen), offset: at });
    at += 28 + chLen + dataLen;
  }
  return events;
}

// The form Foxglove's jsonschema support takes: an object with properties, each of one type
// among boolean/string/number/integer/object/array (base64 strings allowed), or an
// enumeration (oneOf of numeric consts); array items likewise.
function foxgloveCompatible(schema, where) {
  if (schema.type !== "object" || typeof schema.properties !== "object") return `${where}: not an object with properties`;
  for (const [name, p] of Object.entries(schema.properties)) {
    const at = `${where}.${name}`;
    if (Array.isArray(p.oneOf)) {
      if (!p.oneOf.every((alt) => typeof alt.const === "number")) return `${at}: oneOf needs numeric consts`;
      continue;
    }
    if (p.type === "object") {
      const e = foxgloveCompatible(p, at);
      if (e) return e;
    } else if (p.type === "array") {
      const it = p.items || {};
      if (it.type === "object") {
        const e = foxgloveCompatible(it, at + "[]");
        if (e) return e;
      } else if (!["boolean", "string", "number", "integer"].includes(it.type) || it.contentEncoding !== undefined) {
        return `${at}: array items of unsupported type ${JSON.stringify(it.type)}`;
      }
    } else if (p.type === "string") {
      if (p.contentEncoding !== undefined && p.contentEncoding !== "base64") return `${at}: contentEncoding`;
    } else if (!["boolean", "number", "integer"].includes(p.type)) {
      return `${at}: unsupported type ${JSON.stringify(p.type)}`;
    }
  }
  return undefined;
}

// JSON has no NaN: the exporters write null for non-finite numbers (documented). Validate with
// that allowed, and nothing else relaxed.
function allowNullNumbers(schema) {
  if (Array.isArray(schema)) return schema.map(allowNullNumbers);
  if (schema === null || typeof schema !== "object") return schema;
  const out = {};
  for (const [k, v] of Object.entries(schema)) out[k] = allowNullNumbers(v);
  if (out.type === "number") out.type = ["number", "null"];
  return out;
}

function base64(s) {
  return Buffer.from(s, "base64");
}

async function main() {
  const limit = args.events !== undefined ? Number(args.events) : undefined;
  const events = readLcmLog(args.log, limit);
  if (limit !== undefined) check(`the log has at least ${limit} readable events`, events.length === limit, events.length);
  const perChannel = new Map();
  for (const e of events) perChannel.set(e.channel, (perChannel.get(e.channel) || 0) + 1);

  const bytes = fs.readFileSync(args.mcap);
  const decompressHandlers = await loadDecompressHandlers();

  // 1. Streaming reader over the whole file: every record, chunk CRCs checked.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(bytes);
  const channels = new Map();
  const schemas = new Map();
  const streamed = [];
  let header, dataEnd, footer, statistics;
  const summaryOffsets = [];
  for (let r; (r = stream.nextRecord()); ) {
    if (r.type === "Header") header = r;
    else if (r.type === "Schema") schemas.set(r.id, r);
    else if (r.type === "Channel") channels.set(r.id, r);
    else if (r.type === "Message") streamed.push(r);
    else if (r.type === "DataEnd") dataEnd = r;
    else if (r.type === "Statistics") statistics = r;
    else if (r.type === "SummaryOffset") summaryOffsets.push(r);
    else if (r.type === "Footer") footer = r;
  }
  check("the streaming reader read to the end", stream.done());
  check("header names the writer", header && header.library === "ucon-mcap", header && header.library);
  check("a Data End record", dataEnd !== undefined);
  check("a Statistics record", statistics !== undefined);
  check("summary offsets", summaryOffsets.length >= 3, summaryOffsets.length);
  check("a footer", footer !== undefined);

  // 2. CRCs of the data section and of the summary.
  if (dataEnd && footer) {
    const summaryStart = Number(footer.summaryStart);
    const dataEndAt = summaryStart - (1 + 8 + 4);
    check("data section CRC", dataEnd.dataSectionCrc === crc32(bytes.subarray(0, dataEndAt)),
          dataEnd.dataSectionCrc);
    const footerAt = bytes.length - 8 - (1 + 8 + 20);
    check("summary CRC", footer.summaryCrc === crc32(bytes.subarray(summaryStart, footerAt + 1 + 8 + 16)),
          footer.summaryCrc);
  }

  // 3. Indexed reader: summary, chunk indexes, message indexes.
  const handle = await fs.promises.open(args.mcap, "r");
  const indexed = await McapIndexedReader.Initialize({ readable: new FileHandleReadable(handle), decompressHandlers });
  const viaIndex = [];
  for await (const m of indexed.readMessages({ validateCrcs: true })) viaIndex.push(m);
  check("indexed reader finds every message", viaIndex.length === streamed.length, `${viaIndex.length} vs ${streamed.length}`);
  check("statistics count every message", indexed.statistics && Number(indexed.statistics.messageCount) === streamed.length);
  check("one chunk index per chunk", indexed.chunkIndexes.length === Number(indexed.statistics.chunkCount));
  const topicOf = (m) => channels.get(m.channelId).topic;
  const count = new Map();
  for (const m of streamed) count.set(topicOf(m), (count.get(topicOf(m)) || 0) + 1);
  for (const [id, n] of indexed.statistics.channelMessageCounts) {
    check(`statistics count of ${indexed.channelsById.get(id).topic}`, Number(n) === count.get(indexed.channelsById.get(id).topic));
  }
  // A time window read through the index gives exactly the messages of that window.
  const times = streamed.map((m) => m.logTime).sort((a, b) => (a < b ? -1 : a > b ? 1 : 0));
  if (times.length > 10) {
    const t0 = times[Math.floor(times.length / 3)];
    const t1 = t0 + 1000000000n;
    let windowed = 0;
    for await (const m of indexed.readMessages({ startTime: t0, endTime: t1, topics: ["ROBOT_POSE", "/tf"] })) {
      check("windowed message in its window", m.logTime >= t0 && m.logTime <= t1);
      windowed++;
    }
    const expected = streamed.filter(
      (m) => m.logTime >= t0 && m.logTime <= t1 && ["ROBOT_POSE", "/tf"].includes(topicOf(m))).length;
    check("a 1 s window read through the index", windowed === expected && expected > 0, `${windowed} vs ${expected}`);
  }
  await handle.close();

  // 4. Every LCM channel is a topic with the log's number of messages.
  for (const [ch, n] of perChannel) {
    if (ch === "LCM_SELF_TEST") continue;  // LCM's own start-up check, not a ucon message
    check(`topic ${ch} has the log's ${n} messages`, count.get(ch) === n, count.get(ch));
  }

  // 5. Schemas: valid JSON Schema, of Foxglove's form; messages validate against them.
  const ajv = new Ajv({ strict: false, allErrors: false });
  const validators = new Map();
  for (const [id, s] of schemas) {
    check(`schema ${s.name} is jsonschema`, s.encoding === "jsonschema");
    let parsed;
    try {
      parsed = JSON.parse(new TextDecoder().decode(s.data));
    } catch (e) {
      check(`schema ${s.name} is JSON`, false, e.message);
      continue;
    }
    check(`schema ${s.name} titled by its name`, parsed.title === s.name, parsed.title);
    try {
      ajv.compile(parsed);  // throws on an invalid schema
      validators.set(id, ajv.compile(allowNullNumbers(parsed)));
      passes++;
    } catch (e) {
      check(`schema ${s.name} is valid JSON Schema`, false, e.message);
    }
    const err = foxgloveCompatible(parsed, s.name);
    check(`schema ${s.name} is of the form Foxglove reads`, err === undefined, err);
  }
  const decoder = new TextDecoder();
  // The time policy (message_time.hpp): the time base (points, IMU, poses, ground truth)
  // keeps its utime; any other message keeps its utime when it lies within 10 minutes of the
  // clock, and otherwise (invalid, or wall clock in a simulated run) sits at the run's time.
  const timeBase = new Set(["ucon.point_cloud_t", "ucon.imu_t", "ucon.robot_pose_t", "ucon.sim_ground_truth_t"]);
  const windowNs = 600n * 1000000000n;
  let badJson = 0, invalid = 0, badTime = 0, baseFirst, baseLast;
  const byTopic = new Map();
  const others = [];
  for (const m of streamed) {
    const ch = channels.get(m.channelId);
    check(`channel ${ch.topic} is json`, ch.messageEncoding === "json");
    let v;
    try {
      v = JSON.parse(decoder.decode(m.data));
    } catch (e) {
      if (badJson++ < 3) check(`message on ${ch.topic} is JSON`, false, e.message);
      continue;
    }
    const validate = validators.get(ch.schemaId);
    if (validate && !validate(v) && invalid++ < 3) {
      check(`message on ${ch.topic} validates`, false, JSON.stringify(validate.errors.slice(0, 2)));
    }
    check(`log time = publish time on ${ch.topic}`, m.logTime === m.publishTime);
    const schemaName = schemas.get(ch.schemaId).name;
    if (timeBase.has(schemaName)) {
      if (m.logTime !== BigInt(v.utime) * 1000n && badTime++ < 3) {
        check(`log time of ${ch.topic} is its utime`, false, `${m.logTime} vs ${v.utime}`);
      }
      if (baseFirst === undefined || m.logTime < baseFirst) baseFirst = m.logTime;
      if (baseLast === undefined || m.logTime > baseLast) baseLast = m.logTime;
    } else if (schemaName.startsWith("ucon.") && typeof v.utime === "number") {
      others.push({ topic: ch.topic, logTime: m.logTime, utime: BigInt(v.utime) * 1000n });
    }
    if (!byTopic.has(ch.topic)) byTopic.set(ch.topic, []);
    byTopic.get(ch.topic).push({ v, m });
  }
  check("every message is JSON", badJson === 0, badJson);
  check("every message validates against its schema", invalid === 0, invalid);
  check("log time = utime for every time-base message", badTime === 0, badTime);
  let misplaced = 0;
  for (const o of others) {
    const kept = o.logTime === o.utime;
    const replaced = o.utime <= 0n || o.utime < o.logTime - windowNs || o.utime > o.logTime + windowNs;
    const inRun = baseFirst === undefined || (o.logTime >= baseFirst && o.logTime <= baseLast + windowNs);
    if (!(kept || (replaced && inRun)) && misplaced++ < 3) {
      check(`${o.topic} at its utime or, without a usable one, within the run`, false, `${o.logTime} vs ${o.utime}`);
    }
  }
  check("other messages sit at their utime or, without a usable one, within the run", misplaced === 0, misplaced);

  if (!args.noViews) {
    // 6. Point clouds: the packed bytes hold the log's points.
    const raw = byTopic.get("LIDAR_POINTS") || [];
    const clouds = byTopic.get("/lidar_points") || [];
    check("a point cloud per LIDAR_POINTS message", raw.length > 0 && clouds.length === raw.length, `${clouds.length} vs ${raw.length}`);
    let layoutBad = 0;
    for (let i = 0; i < Math.min(raw.length, clouds.length); i++) {
      const r = raw[i].v;
      const c = clouds[i].v;
      const fields = new Map(c.fields.map((f) => [f.name, f]));
      const size = { 1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 4, 8: 8 };
      const spans = c.fields.map((f) => [f.offset, f.offset + size[f.type]]).sort((a, b) => a[0] - b[0]);
      for (let k = 0; k < spans.length; k++) {
        if (spans[k][1] > c.point_stride || (k > 0 && spans[k][0] < spans[k - 1][1])) layoutBad++;
      }
      const data = base64(c.data);
      const finite = r.x.filter((x, k) => x !== null && r.y[k] !== null && r.z[k] !== null).length;
      if (data.length !== finite * c.point_stride || ["x", "y", "z"].some((n) => fields.get(n)?.type !== 7)) {
        layoutBad++;
        continue;
      }
      if (i % 50 === 0) {
        // Every point of every 50th cloud, field by field.
        const refl = base64(r.reflectivity);
        const tag = base64(r.tag);
        for (let k = 0, p = 0; k < r.x.length; k++) {
          if (r.x[k] === null || r.y[k] === null || r.z[k] === null) continue;
          const at = p++ * c.point_stride;
          if (data.readFloatLE(at + fields.get("x").offset) !== Math.fround(r.x[k]) ||
              data.readFloatLE(at + fields.get("y").offset) !== Math.fround(r.y[k]) ||
              data.readFloatLE(at + fields.get("z").offset) !== Math.fround(r.z[k]) ||
              data[at + fields.get("reflectivity").offset] !== refl[k] ||
              data[at + fields.get("tag").offset] !== tag[k]) {
            layoutBad++;
            break;
          }
        }
      }
      if (clouds[i].m.logTime !== raw[i].m.logTime) layoutBad++;
    }
    check("point cloud bytes match the log's points and their fields", layoutBad === 0, layoutBad);

    // 7. The other views.
    const need = ["/tf", "/robot_pose", "/perception_objects", "/perception_static", "/planner_trajectory", "/map",
                  "/sim_ground_truth/objects", "/sim_ground_truth/pose"];
    for (const t of need) check(`view ${t} is there`, (byTopic.get(t) || []).length > 0, (byTopic.get(t) || []).length);
    const tf = (byTopic.get("/tf") || []).map((x) => x.v);
    check("transforms world -> base", tf.some((t) => t.parent_frame_id === "world" && t.child_frame_id === "base"));
    const scenes = (byTopic.get("/perception_objects") || []).map((x) => x.v);
    const tracks = scenes.flatMap((s) => s.entities);
    check("tracked objects are drawn", tracks.length > 0, tracks.length);
    check("every track has its cylinder, id and sector",
          tracks.every((e) => e.cylinders.length === 1 && e.texts.length === 1 && e.triangles.length === 1 &&
                              e.triangles[0].indices.length % 3 === 0 &&
                              e.triangles[0].indices.every((k) => k < e.triangles[0].points.length)));
    check("tracks have covariance ellipses", tracks.some((e) => e.lines.length === 1 && e.lines[0].type === 1));
    const plans = (byTopic.get("/planner_trajectory") || []).map((x) => x.v);
    check("trajectories are line strips", plans.some((p) => p.entities.length === 1 && p.entities[0].lines[0].type === 0 &&
                                                             p.entities[0].lines[0].points.length > 1));
    const maps = (byTopic.get("/map") || []).map((x) => x.v);
    const last = maps[maps.length - 1];
    check("the static map grid's bytes fill its rows",
          last && base64(last.data).length % last.row_stride === 0 && last.row_stride === last.column_count &&
          base64(last.data).some((b) => b > 0));
  }

  if (args.layout) {
    const layout = JSON.parse(fs.readFileSync(args.layout, "utf8"));
    const panels = layout.configById;
    const used = [];
    for (const [id, cfg] of Object.entries(panels)) {
      if (id.startsWith("3D!")) used.push(...Object.keys(cfg.topics));
      if (id.startsWith("RawMessages!")) used.push(cfg.topicPath);
      if (id.startsWith("Plot!")) {
        for (const p of cfg.paths) {
          const m = /^([^.]+)\.(\w+)\[:\]\{name=="([^"]+)"\}\.(\w+)$/.exec(p.value);
          check(`layout plot path ${p.value} has the expected form`, m !== null);
          if (!m) continue;
          used.push(m[1]);
          const found = (byTopic.get(m[1]) || []).some(({ v }) =>
            (v[m[2]] || []).some((e) => e.name === m[3] && m[4] in e));
          check(`layout plot ${p.value} finds its value`, found);
        }
      }
    }
    for (const t of used) check(`layout topic ${t} is in the file`, count.has(t));
    check("the layout has a 3D panel and plots", used.length > 8, used.length);
  }

  console.log(`read_mcap: ${streamed.length} messages on ${channels.size} topics, ${schemas.size} schemas, ` +
              `${indexed.chunkIndexes.length} chunks; ${events.length} log events`);
  console.log(`${passes} passed, ${failures} failed`);
  process.exit(failures === 0 ? 0 : 1);
}

main().catch((e) => {
  console.log(`FAIL: ${e.stack || e}`);
  process.exit(1);
});
