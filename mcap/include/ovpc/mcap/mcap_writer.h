// An MCAP writer (https://mcap.dev/spec, major version 0): the file a robotics viewer such as
// Foxglove opens. Messages go into chunks of about `chunk_size` uncompressed bytes, each compressed
// with zstd, followed by one Message Index per channel; the summary holds the schemas, channels,
// statistics and one Chunk Index per chunk, with a Summary Offset per group, and the Data End and
// Footer records carry the CRC-32 of the data section and of the summary. The bytes depend only on
// the calls made: the same calls give the same file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace ovpc::mcap {

/// A file that cannot be written, or a call out of order; the message names the file.
class McapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The record opcodes of the specification.
enum class Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// The eight bytes that open and close every MCAP file.
inline constexpr char kMagic[] = "\x89MCAP0\r\n";
inline constexpr std::size_t kMagicSize = 8;

/// The CRC-32 (ISO-HDLC, as zlib and the specification use) of `bytes`.
std::uint32_t Crc32(std::string_view bytes);

class McapWriter {
 public:
  struct Options {
    std::size_t chunk_size = std::size_t{1} << 20;  ///< uncompressed bytes before a chunk is closed
    int zstd_level = 3;
    std::string profile;              ///< the Header's profile ("" for none)
    std::string library = "ovpc";     ///< the Header's library
  };

  /// Opens `path` (created or truncated) and writes the magic and the Header.
  /// @throws McapError if the file cannot be opened.
  McapWriter(const std::string& path, Options options);
  /// Closes the file if Close() was not called (errors then are swallowed: call Close()).
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// A Schema record; returns its id (1, 2, ...). `encoding` e.g. "jsonschema".
  std::uint16_t AddSchema(const std::string& name, const std::string& encoding, std::string_view data);
  /// A Channel record on schema `schema_id` (0: none); returns its id (0, 1, ...).
  std::uint16_t AddChannel(std::uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                           const std::map<std::string, std::string>& metadata = {});
  /// A Message on `channel_id` at `log_time_ns` (also its publish time), numbered per channel.
  /// @throws McapError for an unknown channel or after Close().
  void Write(std::uint16_t channel_id, std::uint64_t log_time_ns, std::string_view data);
  /// Writes the last chunk, the Data End, the summary and the Footer, and closes the file.
  /// @throws McapError if the file could not be written.
  void Close();

  std::uint64_t message_count() const { return message_count_; }

 private:
  struct ChunkIndexRecord;
  void CloseChunk();
  void WriteRecordToFile(Opcode op, const std::string& content, bool in_data_section);
  std::string SummarySection(std::uint64_t summary_start, std::string* offsets);
  void Check() const;

  std::string path_;
  Options options_;
  std::ofstream file_;
  bool closed_ = false;
  std::uint64_t position_ = 0;      ///< bytes written to the file
  std::uint32_t data_crc_ = 0;      ///< running CRC-32 of the data section (from the magic on)
  std::vector<std::string> schema_records_, channel_records_;
  std::vector<std::uint32_t> sequence_;  ///< next sequence number, by channel
  // The open chunk: its records, and per channel the (log time, offset) of each message in it.
  std::string chunk_;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::uint64_t chunk_start_ns_ = 0, chunk_end_ns_ = 0;
  std::vector<std::string> chunk_index_records_;
  // Statistics.
  std::uint64_t message_count_ = 0, start_ns_ = 0, end_ns_ = 0;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint32_t chunk_count_ = 0;
};

}  // namespace ovpc::mcap
