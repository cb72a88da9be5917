// An independent client of keylo's live view: npm's @foxglove/ws-protocol (the protocol
// Foxglove and Lichtblick speak) over npm's `ws`, protobuf decoded by protobufjs from the
// schemas the server advertises. Subscribes to every channel and writes what it received.
//
//   node ws-client.mjs URL OUT.json [all|stall|drop]
//
// all:   read everything until the server closes;
// stall: after the first message stop reading the socket (a viewer that hangs);
// drop:  close the connection after the first message (a viewer that goes away).
import fs from "node:fs";
import wsProtocol from "@foxglove/ws-protocol";
import WebSocket from "ws";
const { FoxgloveClient } = wsProtocol;
import protobuf from "protobufjs";
import descriptor from "protobufjs/ext/descriptor/index.js";

const [url, out, mode = "all"] = process.argv.slice(2);
const ws = new WebSocket(url, ["foxglove.sdk.v1"]);
const client = new FoxgloveClient({ ws });
const channels = new Map(); // subscription id -> channel
const decoders = new Map(); // channel id -> protobuf type
const result = { mode, topics: {}, schemas: {}, stats: [], poses: [], images: {}, scan: null };
let first = true;

function protobufType(channel) {
  const bytes = Buffer.from(channel.schema, "base64");
  const set = descriptor.FileDescriptorSet.decode(bytes);
  return protobuf.Root.fromDescriptor(set).lookupType(channel.schemaName);
}

function finish() {
  fs.writeFileSync(out, JSON.stringify(result, null, 1));
  process.exit(0);
}

client.on("advertise", (list) => {
  for (const ch of list) {
    result.schemas[ch.topic] = `${ch.schemaName} [${ch.encoding}]`;
    if (ch.encoding === "protobuf") decoders.set(ch.id, protobufType(ch));
    channels.set(client.subscribe(ch.id), ch);
  }
});

client.on("message", ({ subscriptionId, timestamp, data }) => {
  const ch = channels.get(subscriptionId);
  if (!ch) return;
  result.topics[ch.topic] = (result.topics[ch.topic] ?? 0) + 1;
  const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  if (ch.topic === "/keylo/stats") {
    result.stats.push(JSON.parse(Buffer.from(bytes).toString("utf8")));
  } else if (ch.topic === "/keylo/pose") {
    const type = decoders.get(ch.id);
    const m = type.toObject(type.decode(bytes), { defaults: true, longs: String });
    // google.protobuf.Timestamp: seconds, nanos.
    const ns = BigInt(m.timestamp.seconds) * 1000000000n + BigInt(m.timestamp.nanos);
    result.poses.push({ stamp_ns: ns.toString(), log_time_ns: timestamp.toString(), frame_id: m.frameId ?? m.frame_id,
      position: m.pose.position, orientation: m.pose.orientation });
  } else if (ch.topic === "/keylo/trajectory" || ch.topic === "/keylo/reference") {
    const type = decoders.get(ch.id);
    const m = type.toObject(type.decode(bytes), { defaults: true });
    const last = m.poses[m.poses.length - 1];
    result[ch.topic.slice(7)] = { poses: m.poses.length, frame_id: m.frameId ?? m.frame_id, last: last.position };
  } else if (ch.topic === "/keylo/map") {
    const m = decoders.get(ch.id).decode(bytes);
    const stride = m.pointStride ?? m.point_stride;
    result.map = { frame_id: m.frameId ?? m.frame_id, points: m.data.length / stride };
  } else if (ch.topic.startsWith("/keylo/image/") && !ch.topic.endsWith("/keypoints")) {
    const m = decoders.get(ch.id).decode(bytes);
    result.images[ch.topic] = { width: m.width, height: m.height, encoding: m.encoding, bytes: m.data.length };
  } else if (ch.topic === "/keylo/scan") {
    result.scan = { bytes: bytes.length, encoding: ch.encoding, schema: ch.schemaName };
  }
  if (first) {
    first = false;
    if (mode === "stall") {
      // Never read again: the server's queue for this client fills up.
      ws._socket.pause();
      fs.writeFileSync(out, JSON.stringify(result, null, 1));
    } else if (mode === "drop") {
      fs.writeFileSync(out, JSON.stringify(result, null, 1));
      client.close();
      process.exit(0);
    }
  }
});

client.on("close", finish);
client.on("error", (e) => {
  console.error(`ws-client: ${e.message ?? e}`);
});
