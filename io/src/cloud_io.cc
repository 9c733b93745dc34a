// Point cloud and mesh files. Every reader loads the whole file into memory and checks each
// count against the bytes that are really there before it allocates anything, so a corrupt
// header gives an error message instead of a crash or a huge allocation.
#include "ovpc/io/cloud_io.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string_view>
#include <system_error>
#include <utility>

#include "ovpc/core/vertex_cloud.h"

namespace ovpc {
namespace {

// ---------------------------------------------------------------------------------------------
// Errors and whole-file access.

[[noreturn]] void Fail(const std::string& path, const std::string& reason) {
  throw CloudIoError(path + ": " + reason);
}

[[noreturn]] void FailAtLine(const std::string& path, int line, const std::string& reason) {
  Fail(path, "line " + std::to_string(line) + ": " + reason);
}

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// A point cloud file is a regular file of at most this many bytes (2 GiB: 130 million KITTI points).
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{2} << 30;

// The file's bytes, or its first `limit` bytes.
std::string LoadFile(const std::string& path, std::uintmax_t limit = kMaxFileBytes) {
  // A FIFO or a device would block or never end: only regular files, read up to their size.
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) Fail(path, "cannot open (No such file or directory)");
  if (!std::filesystem::is_regular_file(status)) Fail(path, "not a regular file (a folder, FIFO or device)");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) Fail(path, "cannot read its size (" + ec.message() + ")");
  if (size > kMaxFileBytes) Fail(path, "larger than 2 GiB (" + std::to_string(size) + " bytes); split the cloud");
  errno = 0;
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) Fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  const std::uintmax_t wanted = std::min(size, limit);
  std::string bytes;
  bytes.reserve(static_cast<std::size_t>(wanted));
  std::array<char, 1 << 16> chunk;
  std::size_t n = 0;
  while (bytes.size() < wanted && (n = std::fread(chunk.data(), 1, chunk.size(), file.get())) > 0) {
    bytes.append(chunk.data(), std::min<std::size_t>(n, static_cast<std::size_t>(wanted - bytes.size())));
  }
  if (std::ferror(file.get())) {
    Fail(path, std::string("cannot read (") + std::strerror(errno) + ")");
  }
  return bytes;
}

// Writes `bytes` to `file_path` as it is; "" or what failed ("cannot open for writing (...)").
std::string WriteWhole(const std::string& file_path, const std::string& bytes) {
  errno = 0;
  std::FILE* file = std::fopen(file_path.c_str(), "wb");
  if (file == nullptr) return std::string("cannot open for writing (") + std::strerror(errno) + ")";
  bool ok = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
  int error = errno;
  if (std::fclose(file) != 0 && ok) {
    ok = false;
    error = errno;
  }
  return ok ? "" : std::string("write failed (") + std::strerror(error) + ")";
}

// Writes to a temporary file beside the file (a symbolic link's target) and renames it: the file
// is never left truncated (a full disk, an interrupted run), and an earlier complete one is
// replaced only by a complete one. What is not a file to replace (a device, a FIFO) is written
// in place.
void SaveFile(const std::string& path, const std::string& bytes) {
  std::error_code ec;
  std::string target = path;
  if (std::filesystem::is_symlink(std::filesystem::symlink_status(path, ec))) {
    const std::filesystem::path resolved = std::filesystem::weakly_canonical(path, ec);
    if (!ec) target = resolved.string();
  }
  const std::filesystem::file_status status = std::filesystem::status(target, ec);
  if (!ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    const std::string failure = WriteWhole(target, bytes);
    if (!failure.empty()) Fail(path, failure);
    return;
  }
  const std::string partial = target + ".partial";
  std::string failure = WriteWhole(partial, bytes);
  if (failure.empty() && std::rename(partial.c_str(), target.c_str()) != 0) {
    failure = std::string("write failed (") + std::strerror(errno) + ")";
  }
  if (!failure.empty()) {
    std::remove(partial.c_str());
    Fail(path, failure);
  }
}

// ---------------------------------------------------------------------------------------------
// Scalars and byte order.

enum class ScalarType {
  kInt8,
  kUint8,
  kInt16,
  kUint16,
  kInt32,
  kUint32,
  kInt64,
  kUint64,
  kFloat32,
  kFloat64
};

std::size_t SizeOf(ScalarType type) {
  switch (type) {
    case ScalarType::kInt8:
    case ScalarType::kUint8: return 1;
    case ScalarType::kInt16:
    case ScalarType::kUint16: return 2;
    case ScalarType::kInt32:
    case ScalarType::kUint32:
    case ScalarType::kFloat32: return 4;
    default: return 8;
  }
}

bool HostIsLittleEndian() {
  const std::uint16_t one = 1;
  unsigned char first_byte = 0;
  std::memcpy(&first_byte, &one, 1);
  return first_byte == 1;
}

// Reads numbers of a given type and byte order at a byte offset. Callers check the bounds.
class ByteReader {
 public:
  ByteReader(const std::string& bytes, bool big_endian)
      : bytes_(bytes), swap_(big_endian == HostIsLittleEndian()) {}

  double Read(std::size_t pos, ScalarType type) const {
    switch (type) {
      case ScalarType::kInt8: return Load<std::int8_t>(pos);
      case ScalarType::kUint8: return Load<std::uint8_t>(pos);
      case ScalarType::kInt16: return Load<std::int16_t>(pos);
      case ScalarType::kUint16: return Load<std::uint16_t>(pos);
      case ScalarType::kInt32: return Load<std::int32_t>(pos);
      case ScalarType::kUint32: return Load<std::uint32_t>(pos);
      case ScalarType::kInt64: return static_cast<double>(Load<std::int64_t>(pos));
      case ScalarType::kUint64: return static_cast<double>(Load<std::uint64_t>(pos));
      case ScalarType::kFloat32: return Load<float>(pos);
      case ScalarType::kFloat64: return Load<double>(pos);
    }
    return 0.0;
  }

 private:
  template <typename T>
  T Load(std::size_t pos) const {
    std::array<char, sizeof(T)> raw;
    std::memcpy(raw.data(), bytes_.data() + pos, sizeof(T));
    if (swap_) std::reverse(raw.begin(), raw.end());
    T value;
    std::memcpy(&value, raw.data(), sizeof(T));
    return value;
  }

  const std::string& bytes_;
  bool swap_;
};

// Appends little-endian values; every file this project writes is little-endian.
template <typename T>
void AppendLe(std::string* out, T value) {
  std::array<char, sizeof(T)> raw;
  std::memcpy(raw.data(), &value, sizeof(T));
  if (!HostIsLittleEndian()) std::reverse(raw.begin(), raw.end());
  out->append(raw.data(), raw.size());
}

void AppendLe(std::string* out, const Vec3& v) {
  for (int i = 0; i < 3; ++i) AppendLe(out, static_cast<float>(v[i]));
}

// ---------------------------------------------------------------------------------------------
// Text.

// Walks a text buffer line by line (without the "\n" or "\r\n"), numbering lines from 1.
class LineReader {
 public:
  LineReader(const std::string& text, std::size_t pos, int lines_before = 0)
      : text_(text), pos_(pos), line_number_(lines_before) {}

  bool Next(std::string_view* line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string::npos) end = text_.size();
    *line = std::string_view(text_).substr(pos_, end - pos_);
    if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
    pos_ = std::min(end + 1, text_.size());
    ++line_number_;
    return true;
  }
  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return text_.size() - pos_; }
  int line_number() const { return line_number_; }

 private:
  const std::string& text_;
  std::size_t pos_;
  int line_number_;
};

void SplitTokens(std::string_view line, std::string_view separators,
                 std::vector<std::string_view>* tokens) {
  tokens->clear();
  std::size_t pos = 0;
  while (true) {
    pos = line.find_first_not_of(separators, pos);
    if (pos == std::string_view::npos) return;
    const std::size_t end = std::min(line.find_first_of(separators, pos), line.size());
    tokens->push_back(line.substr(pos, end - pos));
    pos = end;
  }
}

constexpr std::string_view kSpaces = " \t\r\v\f";

// Locale-independent; accepts "nan", "inf" and a leading '+'.
bool ParseNumber(std::string_view token, double* value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), *value);
  return ec == std::errc() && end == token.data() + token.size();
}

bool ParseCount(std::string_view token, std::uint64_t* value) {
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), *value);
  return ec == std::errc() && end == token.data() + token.size();
}

// File text quoted for an error message: bytes other than printable ASCII become '?' and long
// text is shortened, so the message stays one readable line.
std::string Quote(std::string_view text) {
  constexpr std::size_t kMaxLength = 60;
  std::string quoted = "'";
  for (char c : text.substr(0, kMaxLength)) {
    quoted += c >= ' ' && c <= '~' ? c : '?';
  }
  return quoted + (text.size() > kMaxLength ? "...'" : "'");
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// ---------------------------------------------------------------------------------------------
// Fixed-size records, shared by the PLY vertex element and PCD points.

struct RecordLayout {
  std::size_t stride = 0;                    // bytes per record (binary)
  std::size_t num_values = 0;                // numbers per record (ascii)
  std::array<std::size_t, 3> offset{};       // byte offset of x, y, z
  std::array<std::size_t, 3> value_index{};  // position of x, y, z among the numbers
  std::array<ScalarType, 3> type{};
  std::array<bool, 3> found{};
};

// Records the field `name` in `layout`; returns false if it is x, y or z with count != 1.
bool AddField(const std::string& name, ScalarType type, std::size_t count, RecordLayout* layout) {
  static constexpr std::array<const char*, 3> kAxes = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    if (name != kAxes[axis] || layout->found[axis]) continue;
    if (count != 1) return false;
    layout->found[axis] = true;
    layout->offset[axis] = layout->stride;
    layout->value_index[axis] = layout->num_values;
    layout->type[axis] = type;
  }
  layout->stride += SizeOf(type) * count;
  layout->num_values += count;
  return true;
}

void RequireXyz(const std::string& path, const RecordLayout& layout, const std::string& where) {
  static constexpr std::array<const char*, 3> kAxes = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    if (!layout.found[axis]) Fail(path, where + " has no '" + kAxes[axis] + "'");
  }
}

// Reads `count` records starting at byte `pos`; returns the points and moves `pos` past them.
Points ReadBinaryRecords(const std::string& path, const std::string& bytes, std::size_t* pos,
                         std::uint64_t count, const RecordLayout& layout, bool big_endian,
                         const char* noun) {
  const std::size_t available = bytes.size() - *pos;
  const std::uint64_t complete = layout.stride == 0 ? count : available / layout.stride;
  if (count > complete) {
    Fail(path, "truncated binary data (expected " + std::to_string(count) + " " + noun +
                   ", file ends after " + std::to_string(complete) + ")");
  }
  const ByteReader reader(bytes, big_endian);
  Points points(count);
  for (Vec3& p : points) {
    for (int axis = 0; axis < 3; ++axis) {
      p[axis] = reader.Read(*pos + layout.offset[axis], layout.type[axis]);
    }
    *pos += layout.stride;
  }
  return points;
}

// Reads `count` non-blank lines of exactly `layout.num_values` numbers each.
Points ReadAsciiRecords(const std::string& path, LineReader* lines, std::uint64_t count,
                        const RecordLayout& layout, const char* noun) {
  Points points;
  // Every record takes at least two bytes, so a header count cannot make this allocate more than
  // the file size.
  points.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(count, lines->remaining() / 2)));
  std::vector<std::string_view> tokens;
  std::vector<double> values;
  std::string_view line;
  while (points.size() < count) {
    if (!lines->Next(&line)) {
      Fail(path, "truncated ascii data (expected " + std::to_string(count) + " " + noun +
                     ", file ends after " + std::to_string(points.size()) + ")");
    }
    SplitTokens(line, kSpaces, &tokens);
    if (tokens.empty()) continue;
    if (tokens.size() != layout.num_values) {
      FailAtLine(path, lines->line_number(),
                 "expected " + std::to_string(layout.num_values) + " values, found " +
                     std::to_string(tokens.size()));
    }
    values.resize(tokens.size());
    for (std::size_t i = 0; i < tokens.size(); ++i) {
      if (!ParseNumber(tokens[i], &values[i])) {
        FailAtLine(path, lines->line_number(), "bad number " + Quote(tokens[i]));
      }
    }
    points.emplace_back(values[layout.value_index[0]], values[layout.value_index[1]],
                        values[layout.value_index[2]]);
  }
  return points;
}

// ---------------------------------------------------------------------------------------------
// PLY.

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::kFloat32;  // item type for a list
  bool is_list = false;
  ScalarType count_type = ScalarType::kUint8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  enum class Encoding { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
  Encoding encoding = Encoding::kAscii;
  std::vector<PlyElement> elements;
  std::size_t data_offset = 0;  // first byte after "end_header\n"
  int num_lines = 0;
};

bool PlyScalarType(std::string_view name, ScalarType* type) {
  static const std::pair<const char*, ScalarType> kTypes[] = {
      {"char", ScalarType::kInt8},      {"int8", ScalarType::kInt8},
      {"uchar", ScalarType::kUint8},    {"uint8", ScalarType::kUint8},
      {"short", ScalarType::kInt16},    {"int16", ScalarType::kInt16},
      {"ushort", ScalarType::kUint16},  {"uint16", ScalarType::kUint16},
      {"int", ScalarType::kInt32},      {"int32", ScalarType::kInt32},
      {"uint", ScalarType::kUint32},    {"uint32", ScalarType::kUint32},
      {"float", ScalarType::kFloat32},  {"float32", ScalarType::kFloat32},
      {"double", ScalarType::kFloat64}, {"float64", ScalarType::kFloat64}};
  for (const auto& [type_name, value] : kTypes) {
    if (name == type_name) {
      *type = value;
      return true;
    }
  }
  return false;
}

PlyHeader ParsePlyHeader(const std::string& path, const std::string& bytes) {
  LineReader lines(bytes, 0);
  std::string_view line;
  if (!lines.Next(&line) || line.substr(0, line.find_last_not_of(kSpaces) + 1) != "ply") {
    Fail(path, "not a PLY file (first line is not 'ply')");
  }
  PlyHeader header;
  bool has_format = false;
  std::vector<std::string_view> t;
  while (lines.Next(&line)) {
    const int n = lines.line_number();
    SplitTokens(line, kSpaces, &t);
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "end_header") {
      if (!has_format) Fail(path, "PLY header has no 'format' line");
      header.data_offset = lines.position();
      header.num_lines = n;
      return header;
    }
    if (t[0] == "format") {
      if (t.size() < 2) FailAtLine(path, n, "bad PLY format line");
      if (t[1] == "ascii") {
        header.encoding = PlyHeader::Encoding::kAscii;
      } else if (t[1] == "binary_little_endian") {
        header.encoding = PlyHeader::Encoding::kBinaryLittleEndian;
      } else if (t[1] == "binary_big_endian") {
        header.encoding = PlyHeader::Encoding::kBinaryBigEndian;
      } else {
        FailAtLine(path, n, "unknown PLY format " + Quote(t[1]));
      }
      has_format = true;
    } else if (t[0] == "element") {
      PlyElement element;
      if (t.size() != 3 || !ParseCount(t[2], &element.count)) {
        FailAtLine(path, n, "bad PLY element line " + Quote(line));
      }
      element.name = std::string(t[1]);
      header.elements.push_back(std::move(element));
    } else if (t[0] == "property") {
      if (header.elements.empty()) FailAtLine(path, n, "PLY property before any element");
      PlyProperty property;
      bool ok = false;
      if (t.size() == 5 && t[1] == "list") {
        property.is_list = true;
        ok = PlyScalarType(t[2], &property.count_type) && PlyScalarType(t[3], &property.type) &&
             property.count_type != ScalarType::kFloat32 &&
             property.count_type != ScalarType::kFloat64;
        property.name = std::string(t[4]);
      } else if (t.size() == 3) {
        ok = PlyScalarType(t[1], &property.type);
        property.name = std::string(t[2]);
      }
      if (!ok) FailAtLine(path, n, "bad PLY property line " + Quote(line));
      header.elements.back().properties.push_back(std::move(property));
    } else {
      FailAtLine(path, n, "unexpected PLY header keyword " + Quote(t[0]));
    }
  }
  Fail(path, "PLY header has no 'end_header' line");
}

// Moves `pos` past every record of an element that comes before the vertices.
void SkipBinaryPlyElement(const std::string& path, const std::string& bytes, bool big_endian,
                          const PlyElement& element, std::size_t* pos) {
  const auto truncated = [&]() {
    Fail(path, "truncated binary data in element " + Quote(element.name));
  };
  const bool has_list = std::any_of(element.properties.begin(), element.properties.end(),
                                    [](const PlyProperty& p) { return p.is_list; });
  if (!has_list) {
    std::size_t stride = 0;
    for (const PlyProperty& p : element.properties) stride += SizeOf(p.type);
    if (stride > 0 && element.count > (bytes.size() - *pos) / stride) truncated();
    *pos += static_cast<std::size_t>(element.count) * stride;
    return;
  }
  // Every record holds at least one list count byte, so this loop ends within the file size.
  const ByteReader reader(bytes, big_endian);
  for (std::uint64_t i = 0; i < element.count; ++i) {
    for (const PlyProperty& p : element.properties) {
      std::size_t size = SizeOf(p.type);
      if (p.is_list) {
        if (bytes.size() - *pos < SizeOf(p.count_type)) truncated();
        const double items = reader.Read(*pos, p.count_type);
        if (items < 0) Fail(path, "negative list length in element " + Quote(element.name));
        *pos += SizeOf(p.count_type);
        if (items > static_cast<double>((bytes.size() - *pos) / size)) truncated();
        size *= static_cast<std::size_t>(items);
      }
      if (bytes.size() - *pos < size) truncated();
      *pos += size;
    }
  }
}

Points ReadPly(const std::string& path, const std::string& bytes) {
  const PlyHeader header = ParsePlyHeader(path, bytes);
  const auto vertex = std::find_if(header.elements.begin(), header.elements.end(),
                                   [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex == header.elements.end()) Fail(path, "PLY header has no 'element vertex'");

  RecordLayout layout;
  for (const PlyProperty& p : vertex->properties) {
    if (p.is_list) {
      Fail(path, "list property " + Quote(p.name) + " in the vertex element is unsupported");
    }
    AddField(p.name, p.type, 1, &layout);
  }
  RequireXyz(path, layout, "PLY vertex element");

  if (header.encoding == PlyHeader::Encoding::kAscii) {
    LineReader lines(bytes, header.data_offset, header.num_lines);
    // Before the vertex element: one non-blank line per record.
    std::string_view line;
    for (auto e = header.elements.begin(); e != vertex; ++e) {
      for (std::uint64_t i = 0; i < e->count;) {
        if (!lines.Next(&line)) Fail(path, "truncated ascii data in element " + Quote(e->name));
        if (line.find_first_not_of(kSpaces) != std::string_view::npos) ++i;
      }
    }
    return ReadAsciiRecords(path, &lines, vertex->count, layout, "vertices");
  }
  const bool big_endian = header.encoding == PlyHeader::Encoding::kBinaryBigEndian;
  std::size_t pos = header.data_offset;
  for (auto e = header.elements.begin(); e != vertex; ++e) {
    SkipBinaryPlyElement(path, bytes, big_endian, *e, &pos);
  }
  return ReadBinaryRecords(path, bytes, &pos, vertex->count, layout, big_endian, "vertices");
}

// ---------------------------------------------------------------------------------------------
// PCD.

struct PcdHeader {
  RecordLayout layout;
  std::uint64_t num_points = 0;
  bool binary = false;
  std::size_t data_offset = 0;  // first byte after the DATA line
  int num_lines = 0;
};

bool PcdScalarType(char type, std::uint64_t size, ScalarType* out) {
  static const std::array<ScalarType, 4> kInts = {ScalarType::kInt8, ScalarType::kInt16,
                                                  ScalarType::kInt32, ScalarType::kInt64};
  static const std::array<ScalarType, 4> kUints = {ScalarType::kUint8, ScalarType::kUint16,
                                                   ScalarType::kUint32, ScalarType::kUint64};
  const int log2 = size == 1 ? 0 : size == 2 ? 1 : size == 4 ? 2 : size == 8 ? 3 : -1;
  if (log2 < 0) return false;
  switch (type) {
    case 'F':
      if (log2 < 2) return false;
      *out = log2 == 2 ? ScalarType::kFloat32 : ScalarType::kFloat64;
      return true;
    case 'I': *out = kInts[log2]; return true;
    case 'U': *out = kUints[log2]; return true;
    default: return false;
  }
}

PcdHeader ParsePcdHeader(const std::string& path, const std::string& bytes) {
  static constexpr std::array<std::string_view, 10> kKeywords = {
      "VERSION", "FIELDS", "COLUMNS", "SIZE",      "TYPE",
      "COUNT",   "WIDTH",  "HEIGHT",  "VIEWPOINT", "POINTS"};
  LineReader lines(bytes, 0);
  std::string_view line;
  std::vector<std::string_view> t;
  std::vector<std::string> fields;
  std::vector<std::string_view> sizes, types, counts;
  std::uint64_t width = 0, height = 1, points = 0;
  bool has_width = false, has_points = false, any_keyword = false;
  const auto parse_count = [&](std::string_view token, std::uint64_t* value) {
    if (!ParseCount(token, value)) {
      FailAtLine(path, lines.line_number(), "bad number " + Quote(token));
    }
  };
  while (lines.Next(&line)) {
    SplitTokens(line, kSpaces, &t);
    if (t.empty() || t[0][0] == '#') continue;
    const int n = lines.line_number();
    if (t[0] == "DATA") {
      if (!any_keyword) break;
      const std::string_view data = t.size() > 1 ? t[1] : "";
      if (data == "binary_compressed") {
        Fail(path,
             "binary_compressed PCD is unsupported; convert it with "
             "'pcl_convert_pcd_ascii_binary <in.pcd> <out.pcd> 1' (binary) or 0 (ascii)");
      }
      if (data != "ascii" && data != "binary") {
        FailAtLine(path, n, "unknown PCD DATA type " + Quote(data));
      }
      if (fields.empty()) Fail(path, "PCD header has no FIELDS");
      if (sizes.size() != fields.size() || types.size() != fields.size() ||
          (!counts.empty() && counts.size() != fields.size())) {
        Fail(path, "PCD header: FIELDS, SIZE, TYPE and COUNT have different lengths");
      }
      PcdHeader header;
      for (std::size_t i = 0; i < fields.size(); ++i) {
        std::uint64_t size = 0, count = 1;
        parse_count(sizes[i], &size);
        if (!counts.empty()) parse_count(counts[i], &count);
        ScalarType type;
        if (types[i].size() != 1 || !PcdScalarType(types[i][0], size, &type)) {
          Fail(path, "PCD field " + Quote(fields[i]) + " has unsupported TYPE " +
                         std::string(types[i]) + " SIZE " + std::string(sizes[i]));
        }
        if (count == 0 || count > bytes.size()) {
          Fail(path, "PCD field " + Quote(fields[i]) + " has bad COUNT " + std::to_string(count));
        }
        if (!AddField(fields[i], type, count, &header.layout)) {
          Fail(path, "PCD field " + Quote(fields[i]) + " with COUNT " + std::to_string(count) +
                         " is unsupported");
        }
      }
      RequireXyz(path, header.layout, "PCD FIELDS");
      if (!has_points && !has_width) Fail(path, "PCD header has neither POINTS nor WIDTH");
      if (has_width && height != 0 && width > UINT64_MAX / height) {
        Fail(path, "PCD WIDTH * HEIGHT overflows");
      }
      if (has_points && has_width && points != width * height) {
        Fail(path, "PCD header: POINTS " + std::to_string(points) +
                       " differs from WIDTH * HEIGHT " + std::to_string(width * height));
      }
      header.num_points = has_points ? points : width * height;
      header.binary = data == "binary";
      header.data_offset = lines.position();
      header.num_lines = n;
      return header;
    }
    if (std::find(kKeywords.begin(), kKeywords.end(), t[0]) == kKeywords.end()) {
      if (!any_keyword) break;
      FailAtLine(path, n, "unknown PCD header keyword " + Quote(t[0]));
    }
    any_keyword = true;
    const std::vector<std::string_view> args(t.begin() + 1, t.end());
    if (t[0] == "FIELDS" || t[0] == "COLUMNS") {
      fields.assign(args.begin(), args.end());
    } else if (t[0] == "SIZE") {
      sizes = args;
    } else if (t[0] == "TYPE") {
      types = args;
    } else if (t[0] == "COUNT") {
      counts = args;
    } else if (t[0] == "WIDTH" || t[0] == "HEIGHT" || t[0] == "POINTS") {
      if (args.size() != 1) FailAtLine(path, n, Quote(t[0]) + " needs one number");
      if (t[0] == "WIDTH") {
        parse_count(args[0], &width);
        has_width = true;
      } else if (t[0] == "HEIGHT") {
        parse_count(args[0], &height);
      } else {
        parse_count(args[0], &points);
        has_points = true;
      }
    }
  }
  Fail(path, any_keyword ? "PCD header has no DATA line" : "not a PCD file (no PCD header)");
}

Points ReadPcd(const std::string& path, const std::string& bytes) {
  const PcdHeader header = ParsePcdHeader(path, bytes);
  if (header.binary) {
    // PCL may pad binary files after the data, so trailing bytes are not an error.
    std::size_t pos = header.data_offset;
    return ReadBinaryRecords(path, bytes, &pos, header.num_points, header.layout,
                             /*big_endian=*/false, "points");
  }
  LineReader lines(bytes, header.data_offset, header.num_lines);
  Points points = ReadAsciiRecords(path, &lines, header.num_points, header.layout, "points");
  std::string_view line;
  while (lines.Next(&line)) {
    if (line.find_first_not_of(kSpaces) != std::string_view::npos) {
      FailAtLine(
          path, lines.line_number(),
          "more data than the " + std::to_string(header.num_points) + " POINTS in the header");
    }
  }
  return points;
}

// ---------------------------------------------------------------------------------------------
// KITTI .bin and .xyz text.

// A .bin file has no header: its record layout is the caller's word (4 float32 fields: KITTI's
// x, y, z, intensity; 5: nuScenes' x, y, z, intensity, ring). Read with the wrong layout, the
// fields slide across records and coordinates land in the intensity and ring fields, so the file
// is checked to look like a LiDAR scan: finite coordinates within 10 km, intensity >= 0, and (5
// fields) a whole ring number in [0, 1024), for at least 99 % of the records. A file of zeros (or
// of one record repeated) is not a scan either: at most half of the records may be all zero bytes,
// and two or more records must not all be the same. Both are checked on the bytes, before the
// points are allocated.
void CheckBinRecordsDiffer(const std::string& path, const std::string& bytes, std::size_t stride) {
  const std::size_t records = bytes.size() / stride;
  const std::string zero(stride, '\0');
  std::size_t zeros = 0;
  bool all_same = records >= 2;
  for (std::size_t i = 0; i < records; ++i) {
    const std::string_view record(bytes.data() + i * stride, stride);
    zeros += record == zero;
    all_same = all_same && record == std::string_view(bytes.data(), stride);
  }
  if (zeros > records / 2) {
    Fail(path, std::to_string(zeros) + " of " + std::to_string(records) + " records are all zero bytes: not a LiDAR scan");
  }
  if (all_same) Fail(path, "all " + std::to_string(records) + " records are the same: not a LiDAR scan");
}

Points ReadBin(const std::string& path, const std::string& bytes, int fields) {
  const std::size_t stride = static_cast<std::size_t>(fields) * sizeof(float);
  const std::string layout = fields == 4 ? "KITTI: float32 x, y, z, intensity" : "nuScenes: float32 x, y, z, intensity, ring";
  if (bytes.size() % stride != 0) {
    Fail(path, "size " + std::to_string(bytes.size()) + " bytes is not a multiple of " + std::to_string(stride) + " (" +
                   layout + "; --bin-fields sets the layout)");
  }
  CheckBinRecordsDiffer(path, bytes, stride);
  const ByteReader reader(bytes, /*big_endian=*/false);
  Points points(bytes.size() / stride);
  std::size_t implausible = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      points[i][axis] = reader.Read(i * stride + axis * sizeof(float), ScalarType::kFloat32);
    }
    const double intensity = reader.Read(i * stride + 3 * sizeof(float), ScalarType::kFloat32);
    bool ok = points[i].allFinite() && points[i].cwiseAbs().maxCoeff() <= 1e4 && intensity >= 0.0;
    if (fields == 5) {
      const double ring = reader.Read(i * stride + 4 * sizeof(float), ScalarType::kFloat32);
      ok = ok && ring >= 0.0 && ring < 1024.0 && ring == std::floor(ring);
    }
    // NaN points are data (the mapper drops and counts them), not a sign of the wrong layout.
    if (!ok && !points[i].hasNaN()) ++implausible;
  }
  if (implausible > points.size() / 100) {
    Fail(path, std::to_string(implausible) + " of " + std::to_string(points.size()) +
                   " records do not look like LiDAR points as " + layout + " (wrong --bin-fields?)");
  }
  return points;
}

Points ReadXyz(const std::string& path, const std::string& bytes) {
  LineReader lines(bytes, 0);
  Points points;
  std::vector<std::string_view> tokens;
  std::string_view line;
  while (lines.Next(&line)) {
    line = line.substr(0, line.find('#'));
    SplitTokens(line, " \t\r\v\f,", &tokens);
    if (tokens.empty()) continue;
    if (tokens.size() < 3) {
      FailAtLine(path, lines.line_number(),
                 "expected at least 3 numbers (x y z), found " + std::to_string(tokens.size()));
    }
    Vec3 p;
    for (int axis = 0; axis < 3; ++axis) {
      if (!ParseNumber(tokens[axis], &p[axis])) {
        FailAtLine(path, lines.line_number(), "bad number " + Quote(tokens[axis]));
      }
    }
    points.push_back(p);
  }
  return points;
}

// ---------------------------------------------------------------------------------------------
// PLY writing.

// Header of a binary little-endian PLY file; `elements` holds the element and property lines.
std::string BinaryPlyHeader(const std::string& elements) {
  return "ply\nformat binary_little_endian 1.0\ncomment generated by ovpc\n" + elements +
         "end_header\n";
}

constexpr char kXyzProperties[] = "property float x\nproperty float y\nproperty float z\n";
constexpr char kNormalProperties[] = "property float nx\nproperty float ny\nproperty float nz\n";

}  // namespace

CloudFormat FormatFromExtension(const std::string& path) {
  const std::string ext = Lower(std::filesystem::path(path).extension().string());
  if (ext == ".ply") return CloudFormat::kPly;
  if (ext == ".pcd") return CloudFormat::kPcd;
  if (ext == ".bin") return CloudFormat::kKittiBin;
  if (ext == ".xyz" || ext == ".txt") return CloudFormat::kXyz;
  return CloudFormat::kAuto;
}

namespace {

// The format to read `path` as, or a CloudIoError naming the file; bin_fields checked first.
CloudFormat ResolveFormat(const std::string& path, CloudFormat format, int bin_fields) {
  if (bin_fields != 4 && bin_fields != 5) Fail(path, "a .bin record has 4 or 5 float32 fields, not " + std::to_string(bin_fields));
  if (format == CloudFormat::kAuto) format = FormatFromExtension(path);
  if (format == CloudFormat::kAuto) {
    const std::string ext = std::filesystem::path(path).extension().string();
    const std::string expected = "expected .ply, .pcd, .bin, .xyz)";
    Fail(path, ext.empty() ? "unknown point cloud format (no extension; " + expected
                           : "unknown point cloud format " + Quote(ext) + " (" + expected);
  }
  return format;
}

Points ParseResolved(const std::string& bytes, CloudFormat format, const std::string& path, int bin_fields) {
  switch (format) {
    case CloudFormat::kPly: return ReadPly(path, bytes);
    case CloudFormat::kPcd: return ReadPcd(path, bytes);
    case CloudFormat::kKittiBin: return ReadBin(path, bytes, bin_fields);
    default: return ReadXyz(path, bytes);
  }
}

}  // namespace

Points ReadCloud(const std::string& path, CloudFormat format, int bin_fields) {
  format = ResolveFormat(path, format, bin_fields);
  if (format == CloudFormat::kKittiBin) {
    // A large file of zeros is refused on its first MiB, before the rest is read.
    const std::size_t stride = static_cast<std::size_t>(bin_fields) * sizeof(float);
    constexpr std::size_t kHead = std::size_t{1} << 20;  // a multiple of both strides
    const std::string head = LoadFile(path, kHead);
    if (head.size() == kHead) CheckBinRecordsDiffer(path, head, stride);
  }
  return ParseResolved(LoadFile(path), format, path, bin_fields);
}

Points ParseCloud(const std::string& bytes, CloudFormat format, const std::string& name, int bin_fields) {
  if (bytes.size() > kMaxFileBytes) Fail(name, "larger than 2 GiB (" + std::to_string(bytes.size()) + " bytes); split the cloud");
  format = ResolveFormat(name, format, bin_fields);
  return ParseResolved(bytes, format, name, bin_fields);
}

void WriteCloudPly(const std::string& path, const Points& points) {
  std::string out =
      BinaryPlyHeader("element vertex " + std::to_string(points.size()) + "\n" + kXyzProperties);
  out.reserve(out.size() + points.size() * 3 * sizeof(float));
  for (const Vec3& p : points) AppendLe(&out, p);
  SaveFile(path, out);
}

void WriteMeshPly(const std::string& path, const FreeSpaceMesh& mesh,
                  const std::vector<Vec3>& vertex_normals) {
  if (vertex_normals.size() < mesh.num_visible()) {
    Fail(path, "got " + std::to_string(vertex_normals.size()) + " vertex normals for " +
                   std::to_string(mesh.num_visible()) + " visible vertices");
  }
  if (mesh.face_traversable.size() != mesh.triangles.size()) {
    Fail(path, "mesh is not classified (" + std::to_string(mesh.face_traversable.size()) +
                   " traversability flags for " + std::to_string(mesh.triangles.size()) +
                   " faces)");
  }
  std::string out = BinaryPlyHeader(
      "element vertex " + std::to_string(mesh.vertices.size()) + "\n" + kXyzProperties +
      kNormalProperties + "element face " + std::to_string(mesh.triangles.size()) +
      "\nproperty list uchar int vertex_indices\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    AppendLe(&out, mesh.vertices[i]);
    AppendLe(&out, i < mesh.num_visible() ? vertex_normals[i] : Vec3::Zero().eval());
  }
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    AppendLe(&out, std::uint8_t{3});
    for (int v : mesh.triangles[f]) AppendLe(&out, static_cast<std::int32_t>(v));
    const bool traversable = mesh.face_traversable[f] != 0;
    const std::array<std::uint8_t, 3> rgb = traversable ? std::array<std::uint8_t, 3>{0, 200, 0}
                                                        : std::array<std::uint8_t, 3>{220, 0, 0};
    for (std::uint8_t c : rgb) AppendLe(&out, c);
  }
  SaveFile(path, out);
}

void WriteTraversabilityCloudPly(const std::string& path, const TraversabilityCloud& cloud) {
  const Points& points = cloud.points();
  const std::vector<Vec3>& normals = cloud.normals();
  const std::vector<std::uint8_t>& traversable = cloud.traversable();
  std::string out =
      BinaryPlyHeader("element vertex " + std::to_string(points.size()) + "\n" + kXyzProperties +
                      kNormalProperties + "property uchar traversable\n");
  out.reserve(out.size() + points.size() * (6 * sizeof(float) + 1));
  for (std::size_t i = 0; i < points.size(); ++i) {
    AppendLe(&out, points[i]);
    AppendLe(&out, normals[i]);
    AppendLe(&out, static_cast<std::uint8_t>(traversable[i] != 0 ? 1 : 0));
  }
  SaveFile(path, out);
}

}  // namespace ovpc
