// Talks to a running ucon-foxglove-bridge with @foxglove/ws-protocol's client while a
// simulation runs:
//   - serverInfo (capabilities: time only) and advertise (the ucon channels and the views);
//   - subscribe to everything; decodable messages arrive on the channels a person looks at,
//     each valid JSON, timestamps in message time, Time messages too;
//   - read-only: client advertise/publish, parameters and service calls are refused with an
//     error status, and nothing is published on the bus (the bridge's status counts them);
//   - a client that stops reading (paused socket) loses its oldest messages, counted by the
//     bridge, while another client keeps receiving at the same time: the bridge never waits
//     for a client;
//   - unsubscribe stops a channel's messages.
// usage: node bridge_client.js --url ws://127.0.0.1:PORT [--seconds S]
"use strict";
const path = require("path");
const { createRequire } = require("module");
const req = createRequire(path.join(process.env.UCON_NODE_MODULES, "index.js"));
const { FoxgloveClient } = req("@foxglove/ws-protocol");
const WebSocket = req("ws");

const args = {};
for (let i = 2; i < process.argv.length; i++) args[process.argv[i].replace(/^--/, "")] = process.argv[++i];
const seconds = Number(args.seconds || 6);

let failures = 0;
let passes = 0;
function check(what, ok, detail) {
  if (ok) passes++;
  else {
    failures++;
    console.log(`FAIL: ${what}${detail !== undefined ? ": " + detail : ""}`);
  }
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

function connect(name) {
  const ws = new WebSocket(args.url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const state = { name, ws, client, info: undefined, channels: new Map(), statuses: [], times: 0, open: false,
                  closed: false, bySub: new Map(), received: new Map(), payloads: new Map(), stamps: [] };
  client.on("open", () => (state.open = true));
  client.on("close", () => (state.closed = true));
  client.on("error", (e) => console.log(`${name}: error ${e && e.message}`));
  client.on("serverInfo", (i) => (state.info = i));
  client.on("advertise", (list) => list.forEach((c) => state.channels.set(c.id, c)));
  client.on("status", (s) => state.statuses.push(s));
  client.on("time", () => state.times++);
  client.on("message", ({ subscriptionId, timestamp, data }) => {
    const ch = state.bySub.get(subscriptionId);
    if (!ch) return;
    state.received.set(ch.topic, (state.received.get(ch.topic) || 0) + 1);
    state.payloads.set(ch.topic, new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
    state.stamps.push(timestamp);
  });
  return state;
}

function subscribe(state, topics) {
  for (const c of state.channels.values()) {
    if (topics && !topics.includes(c.topic)) continue;
    state.bySub.set(state.client.subscribe(c.id), c);
  }
}

async function waitFor(what, cond, ms) {
  const end = Date.now() + ms;
  while (!cond() && Date.now() < end) await sleep(50);
  check(what, cond());
}

async function main() {
  const a = connect("A");
  await waitFor("client A connects with subprotocol foxglove.websocket.v1", () => a.open, 10000);
  check("the server chose foxglove.websocket.v1", a.ws.protocol === "foxglove.websocket.v1", a.ws.protocol);
  await waitFor("serverInfo arrives", () => a.info !== undefined, 5000);
  check("capabilities: time only (read-only)", a.info && JSON.stringify(a.info.capabilities) === '["time"]',
        a.info && JSON.stringify(a.info.capabilities));
  // A channel is advertised when its first message reaches the bridge: the bridge's own status
  // comes once a second, the others at their rates.
  const wanted = ["LIDAR_POINTS", "ROBOT_POSE", "PERCEPTION_OBJECTS", "PLANNER_TRAJECTORY", "/lidar_points", "/tf",
                  "/perception_objects", "/planner_trajectory", "/map", "/perception_static", "FOXGLOVE_BRIDGE_STATUS"];
  const advertised = () => new Set([...a.channels.values()].map((c) => c.topic));
  await waitFor("channels are advertised", () => a.channels.size > 20 && wanted.every((t) => advertised().has(t)),
                8000);
  const topics = advertised();
  for (const t of wanted) check(`advertises ${t}`, topics.has(t));
  for (const c of a.channels.values()) {
    let ok = c.encoding === "json" && c.schemaEncoding === "jsonschema";
    try {
      ok = ok && JSON.parse(c.schema).title === c.schemaName;
    } catch (e) {
      ok = false;
    }
    check(`channel ${c.topic}: json with its jsonschema`, ok);
  }
  subscribe(a);

  // Let the simulation run; then a second client that stops reading.
  await sleep(1500);
  const b = connect("B");
  await waitFor("client B connects", () => b.open && b.channels.size > 20, 10000);
  subscribe(b, ["LIDAR_POINTS", "/lidar_points", "PERCEPTION_STATIC", "/perception_static"]);
  await sleep(300);
  b.ws.pause();  // B reads nothing from here on: its socket fills, then its queue
  const aBefore = a.received.get("LIDAR_POINTS") || 0;
  await sleep(seconds * 1000);
  const aDuring = (a.received.get("LIDAR_POINTS") || 0) - aBefore;
  check("client A keeps receiving point clouds while B is stalled", aDuring >= 5 * seconds, aDuring);

  // Every channel a person looks at carried decodable messages.
  const decoder = new TextDecoder();
  for (const t of ["LIDAR_POINTS", "/lidar_points", "ROBOT_POSE", "/tf", "/robot_pose", "PERCEPTION_OBJECTS",
                   "/perception_objects", "PERCEPTION_STATIC", "/perception_static", "/map", "SIM_GROUND_TRUTH",
                   "/sim_ground_truth/objects", "FOXGLOVE_BRIDGE_STATUS"]) {
    const payload = a.payloads.get(t);
    let ok = payload !== undefined;
    try {
      ok = ok && typeof JSON.parse(decoder.decode(payload)) === "object";
    } catch (e) {
      ok = false;
    }
    check(`received decodable messages on ${t}`, ok, a.received.get(t));
  }
  const cloud = JSON.parse(decoder.decode(a.payloads.get("/lidar_points") || new Uint8Array()) || "{}");
  check("point cloud data fills whole points",
        cloud.point_stride > 0 && Buffer.from(cloud.data || "", "base64").length % cloud.point_stride === 0);
  const raw = JSON.parse(decoder.decode(a.payloads.get("ROBOT_POSE") || new Uint8Array()) || "{}");
  check("message timestamps are message time (ns of utime, not the wall clock)",
        a.stamps.length > 0 && a.stamps.every((s) => s < 10n ** 17n) && raw.utime > 0);
  check("Time messages arrive", a.times > 0, a.times);

  // Read-only: every way of writing is refused with an error status.
  const errorsBefore = a.statuses.filter((s) => s.level === 2).length;
  const pub = a.client.advertise({ topic: "BASE_ESTOP", encoding: "json", schemaName: "ucon.estop_t" });
  a.client.sendMessage(pub, new TextEncoder().encode('{"engaged":false}'));
  a.client.setParameters([{ name: "/x", value: 1 }]);
  a.client.getParameters([]);
  a.client.sendServiceCallRequest({ serviceId: 1, callId: 1, encoding: "json", data: new DataView(new ArrayBuffer(2)) });
  a.ws.send("not json");
  await waitFor("publish, parameter, service and malformed requests get error statuses",
                () => a.statuses.filter((s) => s.level === 2).length - errorsBefore >= 6, 3000);
  const texts = a.statuses.map((s) => s.message).join(" | ");
  check("the refusals say read-only", (texts.match(/read-only/g) || []).length >= 5, texts);

  // Unsubscribing stops a channel.
  const sub = [...a.bySub.entries()].find(([, c]) => c.topic === "ROBOT_POSE");
  a.client.unsubscribe(sub[0]);
  await sleep(300);
  const after = a.received.get("ROBOT_POSE");
  await sleep(1000);
  check("no messages after unsubscribing", a.received.get("ROBOT_POSE") === after);

  // The stalled client lost its oldest messages, and the refused requests: both counted on
  // the bridge's status (published once a second).
  let status;
  const counter = (n) => status.counter_values[status.counter_names.indexOf(n)];
  await waitFor("the bridge's status counts dropped messages and refused requests", () => {
    const p = a.payloads.get("FOXGLOVE_BRIDGE_STATUS");
    if (!p) return false;
    status = JSON.parse(decoder.decode(p));
    return counter("dropped") > 0 && counter("refused_requests") >= 5;
  }, 5000);
  if (status) {
    console.log(`bridge status: dropped ${counter("dropped")}, frames_sent ${counter("frames_sent")}, ` +
                `refused_requests ${counter("refused_requests")}`);
  }
  const bBefore = b.received.get("LIDAR_POINTS") || 0;
  b.ws.resume();
  await waitFor("client B receives again once it reads", () => (b.received.get("LIDAR_POINTS") || 0) > bBefore + 3, 8000);
  check("client B was not disconnected", !b.closed);
  console.log(`client A: ${[...a.received.values()].reduce((x, y) => x + y, 0)} messages on ${a.received.size} topics, ` +
              `${a.times} time messages; A got ${aDuring} point clouds while B was stalled`);
  a.client.close();
  b.client.close();
  console.log(`${passes} passed, ${failures} failed`);
  process.exit(failures === 0 ? 0 : 1);
}

main().catch((e) => {
  console.log(`FAIL: ${e.stack || e}`);
  process.exit(1);
});
