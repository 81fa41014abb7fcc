// Test-time only (make test): converts a ROS 1 bag into a ROS 2 bag with libraries independent of the project's
// reader: @foxglove/rosbag reads the ROS 1 bag, @foxglove/cdr writes CDR, @mcap/core writes MCAP, sql.js writes
// the SQLite .db3 file rosbag2's sqlite3 storage writes (Humble's schema), optionally in a rosbag2 folder with
// metadata.yaml.
//
//   node convert.js IN.bag OUT {mcap|db3|folder} [--compression none|lz4|zstd] [--endian le|be]
//
// Messages keep their topics and the bag's receive times; ROS 1's header.seq is dropped (ROS 2 has none).
"use strict";
const fs = require("fs");
const path = require("path");
const { Bag } = require("@foxglove/rosbag");
const { FileReader } = require("@foxglove/rosbag/node");
const Bzip2 = require("@foxglove/wasm-bz2");
const lz4 = require("@foxglove/wasm-lz4");
const zstd = require("@foxglove/wasm-zstd");
const { CdrWriter, EncapsulationKind } = require("@foxglove/cdr");
const { McapWriter } = require("@mcap/core");
const initSqlJs = require("sql.js");

const TYPES = {
  "sensor_msgs/LaserScan": "sensor_msgs/msg/LaserScan",
  "nav_msgs/Odometry": "nav_msgs/msg/Odometry",
  "tf2_msgs/TFMessage": "tf2_msgs/msg/TFMessage",
};
// Enough of each definition to name its fields; the project's reader decodes by type name.
const DEFINITIONS = {
  "sensor_msgs/msg/LaserScan":
    "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\nfloat32 time_increment\n" +
    "float32 scan_time\nfloat32 range_min\nfloat32 range_max\nfloat32[] ranges\nfloat32[] intensities\n",
  "nav_msgs/msg/Odometry":
    "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n" +
    "geometry_msgs/TwistWithCovariance twist\n",
  "tf2_msgs/msg/TFMessage": "geometry_msgs/TransformStamped[] transforms\n",
};

function header(w, h) {
  w.int32(h.stamp.sec).uint32(h.stamp.nsec).string(h.frame_id);
}
function vector3(w, v) {
  w.float64(v.x).float64(v.y).float64(v.z);
}
function quaternion(w, q) {
  w.float64(q.x).float64(q.y).float64(q.z).float64(q.w);
}
function float32s(w, a) {
  w.uint32(a.length);
  for (const v of a) w.float32(v);
}
function covariance(w, c) {
  for (let i = 0; i < 36; ++i) w.float64(c[i] ?? 0);
}

function encode(type, m, kind) {
  const w = new CdrWriter({ kind });
  if (type === "sensor_msgs/msg/LaserScan") {
    header(w, m.header);
    for (const f of ["angle_min", "angle_max", "angle_increment", "time_increment", "scan_time", "range_min", "range_max"])
      w.float32(m[f]);
    float32s(w, m.ranges);
    float32s(w, m.intensities);
  } else if (type === "nav_msgs/msg/Odometry") {
    header(w, m.header);
    w.string(m.child_frame_id);
    vector3(w, m.pose.pose.position);
    quaternion(w, m.pose.pose.orientation);
    covariance(w, m.pose.covariance);
    vector3(w, m.twist.twist.linear);
    vector3(w, m.twist.twist.angular);
    covariance(w, m.twist.covariance);
  } else {
    w.uint32(m.transforms.length);
    for (const t of m.transforms) {
      header(w, t.header);
      w.string(t.child_frame_id);
      vector3(w, t.transform.translation);
      quaternion(w, t.transform.rotation);
    }
  }
  return w.data;
}

const QOS = "- history: 3\n  depth: 0\n  reliability: 1\n  durability: 2\n  avoid_ros_namespace_conventions: false";

async function readBag(file) {
  const bz2 = await Bzip2.init();
  const bag = new Bag(new FileReader(file), {
    parse: true,
    decompress: { bz2: (b, size) => bz2.decompress(b, size, { small: false }), lz4: (b, size) => lz4(b, size) },
  });
  await bag.open();
  const topics = new Map();  // topic -> ROS 2 type
  for (const c of bag.connections.values()) if (TYPES[c.type]) topics.set(c.topic, TYPES[c.type]);
  const messages = [];
  for await (const e of bag.messageIterator({ topics: [...topics.keys()] })) {
    const ns = BigInt(e.timestamp.sec) * 1000000000n + BigInt(e.timestamp.nsec);
    messages.push({ topic: e.topic, type: topics.get(e.topic), time: ns, message: e.message });
  }
  return { topics, messages };
}

async function writeMcap(out, bag, kind, compression) {
  await lz4.isLoaded;
  await zstd.isLoaded;
  const fd = fs.openSync(out, "w");
  let position = 0n;
  const writable = {
    write: async (buffer) => {
      fs.writeSync(fd, buffer);
      position += BigInt(buffer.byteLength);
    },
    position: () => position,
  };
  const compressChunk =
    compression === "zstd" ? (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) })
    : compression === "lz4" ? undefined  // wasm-lz4 only decompresses; lz4 files come from elsewhere
    : (data) => ({ compression: "", compressedData: data });
  if (compression === "lz4") throw new Error("lz4 writing is not available in @foxglove/wasm-lz4");
  const writer = new McapWriter({ writable, compressChunk, chunkSize: 256 * 1024 });
  await writer.start({ profile: "ros2", library: "partslam tests/ros2/convert.js (@mcap/core)" });
  const channels = new Map();
  for (const [topic, type] of bag.topics) {
    const schemaId = await writer.registerSchema({
      name: type, encoding: "ros2msg", data: new TextEncoder().encode(DEFINITIONS[type]),
    });
    channels.set(topic, await writer.registerChannel({
      topic, schemaId, messageEncoding: "cdr", metadata: new Map([["offered_qos_profiles", QOS]]),
    }));
  }
  let sequence = 0;
  for (const m of bag.messages) {
    await writer.addMessage({
      channelId: channels.get(m.topic), sequence: sequence++, logTime: m.time, publishTime: m.time,
      data: encode(m.type, m.message, kind),
    });
  }
  await writer.end();
  fs.closeSync(fd);
}

async function writeDb3(out, bag, kind) {
  const SQL = await initSqlJs();
  const db = new SQL.Database();
  db.run(`CREATE TABLE schema(schema_version INTEGER PRIMARY KEY,ros_distro TEXT NOT NULL);
    INSERT INTO schema VALUES (3, 'humble');
    CREATE TABLE metadata(id INTEGER PRIMARY KEY,metadata_version INTEGER NOT NULL,metadata TEXT NOT NULL);
    CREATE TABLE topics(id INTEGER PRIMARY KEY,name TEXT NOT NULL,type TEXT NOT NULL,
      serialization_format TEXT NOT NULL,offered_qos_profiles TEXT NOT NULL);
    CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT NULL,timestamp INTEGER NOT NULL,
      data BLOB NOT NULL);
    CREATE INDEX timestamp_idx ON messages (timestamp ASC);`);
  const ids = new Map();
  for (const [topic, type] of bag.topics) {
    ids.set(topic, ids.size + 1);
    db.run("INSERT INTO topics VALUES (?, ?, ?, 'cdr', ?)", [ids.get(topic), topic, type, QOS]);
  }
  db.run("BEGIN");
  const insert = db.prepare("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)");
  for (const m of bag.messages) insert.run([ids.get(m.topic), m.time.toString(), encode(m.type, m.message, kind)]);
  insert.free();
  db.run("COMMIT");
  fs.writeFileSync(out, db.export());
  db.close();
}

function writeMetadata(folder, file, bag) {
  const counts = new Map();
  for (const m of bag.messages) counts.set(m.topic, (counts.get(m.topic) ?? 0) + 1);
  const times = bag.messages.map((m) => m.time);
  const start = times.reduce((a, b) => (b < a ? b : a));
  const end = times.reduce((a, b) => (b > a ? b : a));
  let yaml = "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n";
  yaml += `  duration:\n    nanoseconds: ${end - start}\n  starting_time:\n    nanoseconds_since_epoch: ${start}\n`;
  yaml += `  message_count: ${bag.messages.length}\n  topics_with_message_count:\n`;
  for (const [topic, type] of bag.topics) {
    yaml += `    - topic_metadata:\n        name: ${topic}\n        type: ${type}\n        serialization_format: cdr\n`;
    yaml += `        offered_qos_profiles: ""\n      message_count: ${counts.get(topic) ?? 0}\n`;
  }
  yaml += `  compression_format: ""\n  compression_mode: ""\n  relative_file_paths:\n    - ${file}\n`;
  yaml += "  files:\n    - path: " + file + `\n      starting_time:\n        nanoseconds_since_epoch: ${start}\n`;
  yaml += `      duration:\n        nanoseconds: ${end - start}\n      message_count: ${bag.messages.length}\n`;
  fs.writeFileSync(path.join(folder, "metadata.yaml"), yaml);
}

async function main() {
  const args = process.argv.slice(2);
  const option = (name, fallback) => {
    const i = args.indexOf(name);
    return i >= 0 ? args.splice(i, 2)[1] : fallback;
  };
  const compression = option("--compression", "zstd");
  const endian = option("--endian", "le");
  const [input, out, format] = args;
  if (!input || !out || !["mcap", "db3", "folder"].includes(format) || !["le", "be"].includes(endian))
    throw new Error("usage: node convert.js IN.bag OUT {mcap|db3|folder} [--compression none|zstd] [--endian le|be]");
  const kind = endian === "le" ? EncapsulationKind.CDR_LE : EncapsulationKind.CDR_BE;
  const bag = await readBag(input);
  if (format === "mcap") await writeMcap(out, bag, kind, compression);
  else if (format === "db3") await writeDb3(out, bag, kind);
  else {
    fs.mkdirSync(out, { recursive: true });
    const file = "bag_0.db3";  // as rosbag2 names its first file, less the folder name
    await writeDb3(path.join(out, file), bag, kind);
    writeMetadata(out, file, bag);
  }
  console.log(`${out}: ${bag.messages.length} messages on ${bag.topics.size} topics`);
}

main().catch((e) => {
  console.error(`convert.js: ${e.message}`);
  process.exit(1);
});
