#include "ovpc/mcap/mcap_writer.h"

#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <limits>

namespace ovpc::mcap {
namespace {

// Little-endian primitives and the specification's composite types, appended to a record's content.
void PutU8(std::string* out, std::uint8_t v) { out->push_back(static_cast<char>(v)); }
template <class T>
void PutLe(std::string* out, T v) {
  for (std::size_t i = 0; i < sizeof(T); ++i) out->push_back(static_cast<char>((static_cast<std::uint64_t>(v) >> (8 * i)) & 0xFF));
}
void PutU16(std::string* out, std::uint16_t v) { PutLe(out, v); }
void PutU32(std::string* out, std::uint32_t v) { PutLe(out, v); }
void PutU64(std::string* out, std::uint64_t v) { PutLe(out, v); }
// String and Bytes: a uint32 length, then the bytes.
void PutString(std::string* out, std::string_view s) {
  PutU32(out, static_cast<std::uint32_t>(s.size()));
  out->append(s.data(), s.size());
}
// A Map or Array: a uint32 byte length, then the entries.
void PutPrefixed32(std::string* out, const std::string& entries) { PutString(out, entries); }

std::string Record(Opcode op, const std::string& content) {
  std::string r;
  r.reserve(content.size() + 9);
  PutU8(&r, static_cast<std::uint8_t>(op));
  PutU64(&r, content.size());
  r += content;
  return r;
}

std::uint32_t CrcUpdate(std::uint32_t crc, std::string_view bytes) {
  // zlib's crc32 takes a uInt length: feed it in pieces.
  constexpr std::size_t kPiece = std::size_t{1} << 30;
  for (std::size_t i = 0; i < bytes.size(); i += kPiece) {
    const std::size_t n = std::min(kPiece, bytes.size() - i);
    crc = static_cast<std::uint32_t>(
        crc32(crc, reinterpret_cast<const Bytef*>(bytes.data() + i), static_cast<uInt>(n)));
  }
  return crc;
}

}  // namespace

std::uint32_t Crc32(std::string_view bytes) { return CrcUpdate(0, bytes); }

McapWriter::McapWriter(const std::string& path, Options options)
    : path_(path), options_(std::move(options)), file_(path, std::ios::binary | std::ios::trunc) {
  if (!file_) throw McapError(path_ + ": cannot open for writing");
  if (options_.chunk_size == 0) options_.chunk_size = 1;
  const std::string magic(kMagic, kMagicSize);
  file_.write(magic.data(), static_cast<std::streamsize>(magic.size()));
  position_ = magic.size();
  data_crc_ = CrcUpdate(0, magic);
  std::string header;
  PutString(&header, options_.profile);
  PutString(&header, options_.library);
  WriteRecordToFile(Opcode::kHeader, header, true);
}

McapWriter::~McapWriter() {
  if (closed_) return;
  try {
    Close();
  } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor may not throw; Close() reports errors
  }
}

void McapWriter::Check() const {
  if (closed_) throw McapError(path_ + ": written after Close()");
}

void McapWriter::WriteRecordToFile(Opcode op, const std::string& content, bool in_data_section) {
  const std::string r = Record(op, content);
  file_.write(r.data(), static_cast<std::streamsize>(r.size()));
  position_ += r.size();
  if (in_data_section) data_crc_ = CrcUpdate(data_crc_, r);
}

std::uint16_t McapWriter::AddSchema(const std::string& name, const std::string& encoding, std::string_view data) {
  Check();
  if (schema_records_.size() >= std::numeric_limits<std::uint16_t>::max()) throw McapError(path_ + ": too many schemas");
  const auto id = static_cast<std::uint16_t>(schema_records_.size() + 1);
  std::string content;
  PutU16(&content, id);
  PutString(&content, name);
  PutString(&content, encoding);
  PutString(&content, data);
  WriteRecordToFile(Opcode::kSchema, content, true);
  schema_records_.push_back(Record(Opcode::kSchema, content));
  return id;
}

std::uint16_t McapWriter::AddChannel(std::uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                                     const std::map<std::string, std::string>& metadata) {
  Check();
  if (schema_id > schema_records_.size()) throw McapError(path_ + ": channel '" + topic + "' on an unknown schema");
  if (channel_records_.size() > std::numeric_limits<std::uint16_t>::max()) throw McapError(path_ + ": too many channels");
  const auto id = static_cast<std::uint16_t>(channel_records_.size());
  std::string content, entries;
  PutU16(&content, id);
  PutU16(&content, schema_id);
  PutString(&content, topic);
  PutString(&content, message_encoding);
  for (const auto& [key, value] : metadata) {
    PutString(&entries, key);
    PutString(&entries, value);
  }
  PutPrefixed32(&content, entries);
  WriteRecordToFile(Opcode::kChannel, content, true);
  channel_records_.push_back(Record(Opcode::kChannel, content));
  sequence_.push_back(0);
  return id;
}

void McapWriter::Write(std::uint16_t channel_id, std::uint64_t log_time_ns, std::string_view data) {
  Check();
  if (channel_id >= channel_records_.size()) throw McapError(path_ + ": message on an unknown channel");
  std::string content;
  content.reserve(data.size() + 22);
  PutU16(&content, channel_id);
  PutU32(&content, sequence_[channel_id]++);
  PutU64(&content, log_time_ns);  // log time
  PutU64(&content, log_time_ns);  // publish time
  content.append(data.data(), data.size());
  if (chunk_index_.empty()) chunk_start_ns_ = chunk_end_ns_ = log_time_ns;
  chunk_start_ns_ = std::min(chunk_start_ns_, log_time_ns);
  chunk_end_ns_ = std::max(chunk_end_ns_, log_time_ns);
  chunk_index_[channel_id].emplace_back(log_time_ns, chunk_.size());
  chunk_ += Record(Opcode::kMessage, content);
  start_ns_ = message_count_ == 0 ? log_time_ns : std::min(start_ns_, log_time_ns);
  end_ns_ = message_count_ == 0 ? log_time_ns : std::max(end_ns_, log_time_ns);
  ++message_count_;
  ++channel_counts_[channel_id];
  if (chunk_.size() >= options_.chunk_size) CloseChunk();
}

void McapWriter::CloseChunk() {
  if (chunk_index_.empty()) return;
  std::string compressed(ZSTD_compressBound(chunk_.size()), '\0');
  const std::size_t n = ZSTD_compress(compressed.data(), compressed.size(), chunk_.data(), chunk_.size(), options_.zstd_level);
  if (ZSTD_isError(n)) throw McapError(path_ + ": zstd: " + ZSTD_getErrorName(n));
  compressed.resize(n);
  std::string content;
  PutU64(&content, chunk_start_ns_);
  PutU64(&content, chunk_end_ns_);
  PutU64(&content, chunk_.size());
  PutU32(&content, Crc32(chunk_));
  PutString(&content, "zstd");
  PutU64(&content, compressed.size());
  content += compressed;
  const std::uint64_t chunk_start = position_;
  WriteRecordToFile(Opcode::kChunk, content, true);
  const std::uint64_t chunk_length = position_ - chunk_start;
  // One Message Index per channel in the chunk, in channel order; offsets into the uncompressed records.
  std::string index_offsets;
  const std::uint64_t indexes_start = position_;
  for (const auto& [channel, entries] : chunk_index_) {
    PutU16(&index_offsets, channel);
    PutU64(&index_offsets, position_);
    std::string index, pairs;
    PutU16(&index, channel);
    for (const auto& [time_ns, offset] : entries) {
      PutU64(&pairs, time_ns);
      PutU64(&pairs, offset);
    }
    PutPrefixed32(&index, pairs);
    WriteRecordToFile(Opcode::kMessageIndex, index, true);
  }
  std::string ci;
  PutU64(&ci, chunk_start_ns_);
  PutU64(&ci, chunk_end_ns_);
  PutU64(&ci, chunk_start);
  PutU64(&ci, chunk_length);
  PutPrefixed32(&ci, index_offsets);
  PutU64(&ci, position_ - indexes_start);
  PutString(&ci, "zstd");
  PutU64(&ci, compressed.size());
  PutU64(&ci, chunk_.size());
  chunk_index_records_.push_back(Record(Opcode::kChunkIndex, ci));
  ++chunk_count_;
  chunk_.clear();
  chunk_index_.clear();
}

// The summary section: schemas, channels, statistics and chunk indexes, each group's place in
// `offsets` (Summary Offset records).
std::string McapWriter::SummarySection(std::uint64_t summary_start, std::string* offsets) {
  std::string summary;
  const auto group = [&](Opcode op, const std::vector<std::string>& records) {
    if (records.empty()) return;
    std::string o;
    PutU8(&o, static_cast<std::uint8_t>(op));
    PutU64(&o, summary_start + summary.size());
    std::uint64_t length = 0;
    for (const std::string& r : records) length += r.size();
    PutU64(&o, length);
    for (const std::string& r : records) summary += r;
    *offsets += Record(Opcode::kSummaryOffset, o);
  };
  std::string stats, counts;
  PutU64(&stats, message_count_);
  PutU16(&stats, static_cast<std::uint16_t>(schema_records_.size()));
  PutU32(&stats, static_cast<std::uint32_t>(channel_records_.size()));
  PutU32(&stats, 0);  // attachments
  PutU32(&stats, 0);  // metadata
  PutU32(&stats, chunk_count_);
  PutU64(&stats, start_ns_);
  PutU64(&stats, end_ns_);
  for (const auto& [channel, count] : channel_counts_) {
    PutU16(&counts, channel);
    PutU64(&counts, count);
  }
  PutPrefixed32(&stats, counts);
  group(Opcode::kSchema, schema_records_);
  group(Opcode::kChannel, channel_records_);
  group(Opcode::kStatistics, {Record(Opcode::kStatistics, stats)});
  group(Opcode::kChunkIndex, chunk_index_records_);
  return summary;
}

void McapWriter::Close() {
  if (closed_) return;
  CloseChunk();
  std::string data_end;
  PutU32(&data_end, data_crc_);
  WriteRecordToFile(Opcode::kDataEnd, data_end, false);
  const std::uint64_t summary_start = position_;
  std::string offsets;
  const std::string summary = SummarySection(summary_start, &offsets);
  const std::uint64_t offsets_start = summary_start + summary.size();
  // The Footer's CRC covers the summary, the summary offsets and the Footer up to its CRC field.
  std::string footer_prefix;
  PutU8(&footer_prefix, static_cast<std::uint8_t>(Opcode::kFooter));
  PutU64(&footer_prefix, 8 + 8 + 4);
  PutU64(&footer_prefix, summary_start);
  PutU64(&footer_prefix, offsets_start);
  const std::uint32_t summary_crc = CrcUpdate(CrcUpdate(CrcUpdate(0, summary), offsets), footer_prefix);
  std::string tail = summary + offsets + footer_prefix;
  PutU32(&tail, summary_crc);
  tail.append(kMagic, kMagicSize);
  file_.write(tail.data(), static_cast<std::streamsize>(tail.size()));
  position_ += tail.size();
  closed_ = true;
  file_.close();
  if (!file_) throw McapError(path_ + ": write failed (disk full?)");
}

}  // namespace ovpc::mcap
