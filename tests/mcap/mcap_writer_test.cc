// The MCAP writer on tiny files, read back by hand: records framed right, the CRCs, the summary's
// offsets and counts. (tests/mcap/check_run_mcap.test.mjs reads a whole run with MCAP's own reader.)
#include "ovpc/mcap/mcap_writer.h"

#include <zstd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ovpc::mcap {
namespace {

std::uint64_t U64(const std::string& s, std::size_t at) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(s.at(at + i));
  return v;
}
std::uint32_t U32(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(s.at(at + i));
  return v;
}
std::uint16_t U16(const std::string& s, std::size_t at) {
  return static_cast<std::uint16_t>(static_cast<unsigned char>(s.at(at)) | static_cast<unsigned char>(s.at(at + 1)) << 8);
}

struct RecordAt {
  std::uint8_t op;
  std::size_t at;      ///< the opcode's offset
  std::string content;
};

// The records of bytes [from, to), which must frame exactly.
std::vector<RecordAt> Records(const std::string& bytes, std::size_t from, std::size_t to) {
  std::vector<RecordAt> out;
  std::size_t at = from;
  while (at < to) {
    const std::uint64_t length = U64(bytes, at + 1);
    EXPECT_LE(at + 9 + length, to);
    out.push_back({static_cast<std::uint8_t>(bytes.at(at)), at, bytes.substr(at + 9, length)});
    at += 9 + length;
  }
  EXPECT_EQ(at, to);
  return out;
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class McapWriterTest : public ::testing::Test {
 protected:
  std::string path_ = (std::filesystem::temp_directory_path() /
                       ("ovpc_mcap_writer_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".mcap"))
                          .string();
  void TearDown() override { std::filesystem::remove(path_); }

  // Two channels on two schemas, 40 messages, chunks of at most ~200 bytes.
  std::string WriteSmallFile() {
    McapWriter::Options options;
    options.chunk_size = 200;
    McapWriter w(path_, options);
    const std::uint16_t s1 = w.AddSchema("test.A", "jsonschema", R"({"type":"object"})");
    const std::uint16_t s2 = w.AddSchema("test.B", "jsonschema", R"({"type":"object"})");
    const std::uint16_t a = w.AddChannel(s1, "/a", "json");
    const std::uint16_t b = w.AddChannel(s2, "/b", "json", {{"k", "v"}});
    for (int i = 0; i < 40; ++i) w.Write(i % 3 == 0 ? b : a, 1000u * i, R"({"i":)" + std::to_string(i) + "}");
    EXPECT_EQ(w.message_count(), 40u);
    w.Close();
    return ReadAll(path_);
  }
};

TEST(Crc32Test, KnownString) { EXPECT_EQ(Crc32("123456789"), 0xCBF43926u); }

TEST_F(McapWriterTest, FramesRecordsBetweenMagicsAndChecksCrcs) {
  const std::string f = WriteSmallFile();
  const std::string magic(kMagic, kMagicSize);
  ASSERT_GT(f.size(), 2 * kMagicSize + 29);
  EXPECT_EQ(f.substr(0, kMagicSize), magic);
  EXPECT_EQ(f.substr(f.size() - kMagicSize), magic);
  // Footer: the last record, 20 bytes of content.
  const std::size_t footer_at = f.size() - kMagicSize - 29;
  ASSERT_EQ(f[footer_at], static_cast<char>(Opcode::kFooter));
  const std::uint64_t summary_start = U64(f, footer_at + 9), offsets_start = U64(f, footer_at + 17);
  EXPECT_EQ(U32(f, footer_at + 25), Crc32(f.substr(summary_start, footer_at + 25 - summary_start)));
  // Data section: Header first, Data End last, with the CRC of every byte before it.
  const std::vector<RecordAt> data = Records(f, kMagicSize, summary_start);
  ASSERT_GE(data.size(), 3u);
  EXPECT_EQ(data.front().op, static_cast<std::uint8_t>(Opcode::kHeader));
  EXPECT_EQ(data.back().op, static_cast<std::uint8_t>(Opcode::kDataEnd));
  EXPECT_EQ(U32(data.back().content, 0), Crc32(f.substr(0, data.back().at)));
  // Summary and summary offsets frame exactly; each offset points at a group of its opcode.
  const std::vector<RecordAt> summary = Records(f, summary_start, offsets_start);
  for (const RecordAt& o : Records(f, offsets_start, footer_at)) {
    ASSERT_EQ(o.op, static_cast<std::uint8_t>(Opcode::kSummaryOffset));
    const std::uint64_t start = U64(o.content, 1), length = U64(o.content, 9);
    for (const RecordAt& r : Records(f, start, start + length)) EXPECT_EQ(r.op, static_cast<std::uint8_t>(o.content[0]));
  }
  std::map<std::uint8_t, int> ops;
  for (const RecordAt& r : summary) ++ops[r.op];
  EXPECT_EQ(ops[static_cast<std::uint8_t>(Opcode::kSchema)], 2);
  EXPECT_EQ(ops[static_cast<std::uint8_t>(Opcode::kChannel)], 2);
  EXPECT_EQ(ops[static_cast<std::uint8_t>(Opcode::kStatistics)], 1);
  EXPECT_GE(ops[static_cast<std::uint8_t>(Opcode::kChunkIndex)], 3);
}

TEST_F(McapWriterTest, ChunkIndexesPointAtChunksAndTheirMessages) {
  const std::string f = WriteSmallFile();
  const std::size_t footer_at = f.size() - kMagicSize - 29;
  const std::uint64_t summary_start = U64(f, footer_at + 9), offsets_start = U64(f, footer_at + 17);
  std::uint64_t messages = 0, stats_count = 0;
  for (const RecordAt& r : Records(f, summary_start, offsets_start)) {
    if (r.op == static_cast<std::uint8_t>(Opcode::kStatistics)) stats_count = U64(r.content, 0);
    if (r.op != static_cast<std::uint8_t>(Opcode::kChunkIndex)) continue;
    const std::uint64_t chunk_at = U64(r.content, 16), chunk_length = U64(r.content, 24);
    ASSERT_EQ(f[chunk_at], static_cast<char>(Opcode::kChunk));
    EXPECT_EQ(9 + U64(f, chunk_at + 1), chunk_length);
    // Chunk: start, end, uncompressed size, CRC, "zstd", compressed records.
    const std::string chunk = f.substr(chunk_at + 9, chunk_length - 9);
    const std::uint64_t size = U64(chunk, 16);
    ASSERT_EQ(U32(chunk, 28), 4u);
    ASSERT_EQ(chunk.substr(32, 4), "zstd");
    const std::string compressed = chunk.substr(44, U64(chunk, 36));
    std::string records(size, '\0');
    ASSERT_EQ(ZSTD_decompress(records.data(), size, compressed.data(), compressed.size()), size);
    EXPECT_EQ(U32(chunk, 24), Crc32(records));
    // Each channel's Message Index points at Message records of that channel in the chunk.
    const std::uint32_t map_bytes = U32(r.content, 32);
    for (std::size_t e = 36; e < 36 + map_bytes; e += 10) {
      const std::uint16_t channel = U16(r.content, e);
      const std::uint64_t index_at = U64(r.content, e + 2);
      ASSERT_EQ(f[index_at], static_cast<char>(Opcode::kMessageIndex));
      EXPECT_EQ(U16(f, index_at + 9), channel);
      const std::uint32_t pairs = U32(f, index_at + 11);
      for (std::size_t p = 0; p < pairs; p += 16) {
        const std::uint64_t offset = U64(f, index_at + 15 + p + 8);
        ASSERT_EQ(records.at(offset), static_cast<char>(Opcode::kMessage));
        EXPECT_EQ(U16(records, offset + 9), channel);
        EXPECT_EQ(U64(records, offset + 15), U64(f, index_at + 15 + p));  // log time
        ++messages;
      }
    }
  }
  EXPECT_EQ(messages, 40u);
  EXPECT_EQ(stats_count, 40u);
}

TEST_F(McapWriterTest, SameCallsGiveTheSameBytes) {
  const std::string first = WriteSmallFile();
  EXPECT_EQ(WriteSmallFile(), first);
}

TEST_F(McapWriterTest, RefusesUnknownChannelsAndUnwritableFiles) {
  McapWriter w(path_, {});
  EXPECT_THROW(w.Write(0, 0, "{}"), McapError);
  EXPECT_THROW(w.AddChannel(3, "/x", "json"), McapError);
  w.Close();
  EXPECT_THROW(w.AddSchema("a", "jsonschema", "{}"), McapError);
  EXPECT_THROW(McapWriter("/nonexistent-folder/x.mcap", {}), McapError);
}

}  // namespace
}  // namespace ovpc::mcap
