// Reads a short run's run.mcap with MCAP's reference reader (@mcap/core, zstd from @mcap/support)
// and validates every message against Foxglove's JSON schemas (@foxglove/schemas) with ajv.
// Run by CTest (mcap.reader) as `node --test`, with OVPC_BIN naming the ovpc program.
import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { existsSync, mkdtempSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const repo = join(here, "..", "..");
if (!existsSync(join(here, "node_modules", "@mcap", "core"))) {
  throw new Error(`${join(here, "node_modules")} is missing: run scripts/install-deps (it runs npm ci there)`);
}
const ovpc = process.env.OVPC_BIN;
if (!ovpc || !existsSync(ovpc)) throw new Error("OVPC_BIN must name the ovpc program (CTest sets it)");

const { McapIndexedReader, McapStreamReader } = await import("@mcap/core");
const { loadDecompressHandlers } = await import("@mcap/support");
const { crc32 } = await import("@foxglove/crc");
const foxglove = await import("@foxglove/schemas/jsonschema.js");
const Ajv = (await import("ajv")).default;

const TOPICS = ["/tf", "/pose/true", "/pose/odometry", "/command", "/lidar/points", "/map/mesh", "/map/points",
                "/plan", "/world", "/log"];
const work = mkdtempSync(join(tmpdir(), "ovpc-mcap-"));
let decompressHandlers;

// One short run of the carport scenario (6 simulated seconds).
function run(out, ...extra) {
  const args = ["run", join(repo, "scenarios", "carport_2p5.yaml"), "--set", "time_limit_s=6", "--out", join(work, out),
                "-q", ...extra];
  try {
    execFileSync(ovpc, args, { stdio: ["ignore", "ignore", "inherit"] });
  } catch (e) {
    if (e.status !== 1) throw e;  // 1: a criterion failed (the goal is not reached in 6 s)
  }
  return join(work, out);
}

function readable(bytes) {
  return {
    size: async () => BigInt(bytes.byteLength),
    read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
  };
}
async function indexedReader(bytes) {
  return McapIndexedReader.Initialize({ readable: readable(bytes), decompressHandlers });
}

let file;
before(async () => {
  decompressHandlers = await loadDecompressHandlers();
  run("two_threads", "--mcap", "--threads", "2");
  run("one_thread", "--mcap", "--threads", "1");
  run("no_log", "--threads", "2");
  file = new Uint8Array(readFileSync(join(work, "two_threads", "run.mcap")));
});
after(() => rmSync(work, { recursive: true, force: true }));

test("the same scenario and seed give the same run.mcap with one or two threads, and the log changes no trajectory", () => {
  const one = readFileSync(join(work, "one_thread", "run.mcap"));
  assert.ok(Buffer.from(file).equals(one), "run.mcap differs between --threads 1 and 2");
  const trajectory = readFileSync(join(work, "no_log", "trajectory.csv"));
  for (const dir of ["two_threads", "one_thread"]) {
    assert.ok(readFileSync(join(work, dir, "trajectory.csv")).equals(trajectory), `${dir}: trajectory.csv differs`);
  }
  assert.ok(!existsSync(join(work, "no_log", "run.mcap")), "a run without --mcap wrote run.mcap");
  assert.ok(!existsSync(join(work, "two_threads", "run.mcap.part")), "run.mcap.part left behind");
});

test("summary: statistics, channel counts and the CRCs agree with what the reader reads", async () => {
  const reader = await indexedReader(file);  // checks the summary CRC
  const stats = reader.statistics;
  assert.ok(stats, "no Statistics record");
  assert.equal(reader.chunkIndexes.length, stats.chunkCount);
  assert.ok(reader.chunkIndexes.every((c) => c.compression === "zstd"));
  assert.equal(reader.channelsById.size, stats.channelCount);
  assert.equal(reader.schemasById.size, stats.schemaCount);
  const counts = new Map();
  let n = 0;
  for await (const m of reader.readMessages({ validateCrcs: true })) {
    counts.set(m.channelId, (counts.get(m.channelId) ?? 0) + 1);
    ++n;
  }
  assert.equal(BigInt(n), stats.messageCount);
  for (const [id, count] of stats.channelMessageCounts) assert.equal(BigInt(counts.get(id) ?? 0), count);
  // The data section's CRC (Data End): every byte before the Data End record.
  const dataEnd = Number(reader.footer.summaryStart) - 13;
  assert.equal(file[dataEnd], 0x0f, "no Data End record before the summary");
  assert.equal(crc32(file.subarray(0, dataEnd)), reader.dataSectionCrc);
  // The streaming reader (chunk CRCs checked) reads the same messages.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(file);
  let streamed = 0;
  for (let r; (r = stream.nextRecord()); ) if (r.type === "Message") ++streamed;
  assert.ok(stream.done());
  assert.equal(streamed, n);
});

test("every topic is there and every message is valid under Foxglove's JSON schema", async () => {
  const reader = await indexedReader(file);
  const ajv = new Ajv({ strict: false, allErrors: false });
  const validators = new Map();
  for (const [id, schema] of reader.schemasById) {
    assert.equal(schema.encoding, "jsonschema");
    const name = schema.name;
    const official = name.startsWith("foxglove.") ? foxglove[name.slice("foxglove.".length)] : undefined;
    if (name.startsWith("foxglove.")) assert.ok(official, `${name} is not one of Foxglove's schemas`);
    validators.set(id, ajv.compile(official ?? JSON.parse(new TextDecoder().decode(schema.data))));
  }
  const seen = new Map(), frames = new Set(), logNames = new Set();
  const decoder = new TextDecoder();
  for await (const m of reader.readMessages()) {
    const channel = reader.channelsById.get(m.channelId);
    assert.equal(channel.messageEncoding, "json");
    const message = JSON.parse(decoder.decode(m.data));
    const validate = validators.get(channel.schemaId);
    assert.ok(validate(message), `${channel.topic}: ${ajv.errorsText(validate.errors)}`);
    seen.set(channel.topic, (seen.get(channel.topic) ?? 0) + 1);
    if (channel.topic === "/tf") frames.add(`${message.parent_frame_id}->${message.child_frame_id}`);
    if (channel.topic === "/log") logNames.add(message.name);
    if (message.point_stride) {
      const bytes = Buffer.from(message.data, "base64").length;
      assert.equal(bytes % message.point_stride, 0, `${channel.topic}: data is not whole points`);
    }
  }
  for (const topic of TOPICS) assert.ok(seen.get(topic) > 0, `no message on ${topic}`);
  assert.deepEqual([...frames].sort(), ["base->lidar", "odom->base", "world->odom"]);
  for (const name of ["planner", "criteria", "diagnosis"]) assert.ok(logNames.has(name), `no ${name} log line`);
});

test("a flipped byte in a chunk or in the summary is caught", async () => {
  const reader = await indexedReader(file);
  const chunk = reader.chunkIndexes.reduce((a, b) => (b.compressedSize > a.compressedSize ? b : a));
  const inChunk = file.slice();
  inChunk[Number(chunk.chunkStartOffset + chunk.chunkLength / 2n)] ^= 0x10;
  await assert.rejects(async () => {
    const r = await indexedReader(inChunk);
    for await (const _ of r.readMessages({ validateCrcs: true })) { /* read all */ }
  }, "a flipped byte in a chunk was not caught");
  const inSummary = file.slice();
  inSummary[Number(reader.footer.summaryStart) + 20] ^= 0x01;
  await assert.rejects(() => indexedReader(inSummary), /CRC/, "a flipped byte in the summary was not caught");
});
