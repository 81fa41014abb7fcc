// Test-time only (make test, the ctest ResultMcap.ReadByFoxglove): reads a result.mcap that `partslam slam`
// wrote (or the MCAP of `locate --mcap`), with libraries independent of the project: @mcap/core's stream reader for the container, and for every
// message Foxglove's ROS 2 reader (@foxglove/rosmsg parses the schema the file carries, @foxglove/rosmsg2-
// serialization decodes the CDR by it), as Foxglove Studio does. A message that does not decode, or leaves bytes
// its schema does not account for, fails. Prints a JSON summary of what it read.
//
//   node read-result.js RESULT.mcap
"use strict";
const fs = require("fs");
const { McapStreamReader } = require("@mcap/core");
const { parse } = require("@foxglove/rosmsg");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");

const file = process.argv[2];
const stream = new McapStreamReader();
stream.append(fs.readFileSync(file));
const schemas = new Map(), channels = new Map(), readers = new Map();
const summary = { topics: {}, map: null, slam_path: 0, odom_path: 0, closure_points: 0, scan_points: 0, tf: 0,
                  located_path: 0, located_points: 0, located_colours: 0 };
let record;
while ((record = stream.nextRecord()) !== undefined) {
  if (record.type === "Schema") schemas.set(record.id, record);
  else if (record.type === "Channel") {
    const schema = schemas.get(record.schemaId);
    if (schema.encoding !== "ros2msg" || record.messageEncoding !== "cdr") throw new Error(`${record.topic}: not ros2msg/cdr`);
    const definitions = parse(new TextDecoder().decode(schema.data), { ros2: true });
    channels.set(record.id, { topic: record.topic, type: schema.name });
    readers.set(record.id, new MessageReader(definitions));
    summary.topics[record.topic] = { type: schema.name, messages: 0 };
  } else if (record.type === "Message") {
    const channel = channels.get(record.channelId);
    const reader = readers.get(record.channelId);
    const m = reader.readMessage(record.data);
    if (reader.lastReadHadTrailingBytes()) throw new Error(`${channel.topic}: bytes left over after the message`);
    summary.topics[channel.topic].messages += 1;
    if (channel.topic === "/map") {
      const counts = { occupied: 0, free: 0, unknown: 0 };
      for (const v of m.data) counts[v === 100 ? "occupied" : v === 0 ? "free" : "unknown"] += 1;
      summary.map = { width: m.info.width, height: m.info.height, resolution: m.info.resolution,
                      origin: [m.info.origin.position.x, m.info.origin.position.y], frame: m.header.frame_id, ...counts };
    } else if (channel.topic === "/slam/path") summary.slam_path = m.poses.length;
    else if (channel.topic === "/odom/path") summary.odom_path = m.poses.length;
    else if (channel.topic === "/loop_closures") summary.closure_points = m.markers[0].points.length;
    else if (channel.topic === "/tf") summary.tf += m.transforms.length;
    else if (channel.topic === "/scan") summary.scan_points += m.width * m.height;
    else if (channel.topic === "/located/path") summary.located_path = m.poses.length;
    else if (channel.topic === "/located") {
      summary.located_points = m.markers[0].points.length;
      summary.located_colours = m.markers[0].colors.length;
    }
  }
}
if (!stream.done()) throw new Error(`${file}: the stream did not end with its footer and magic`);
console.log(JSON.stringify(summary));
