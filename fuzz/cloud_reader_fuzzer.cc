// libFuzzer harness for one point-cloud reader (io/): the input is the bytes of a file in the format
// this harness is built for (OVPC_FUZZ_FORMAT: ply, pcd, bin or xyz). For bin, the first byte picks
// the record layout (even: KITTI's 4 fields, odd: nuScenes' 5) and the rest is the file.
// A reader may refuse the input with CloudIoError, one line naming the file; anything else (another
// exception, a crash, a sanitizer report, a hang or a huge allocation) is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <string>

#include "ovpc/io/cloud_io.h"

namespace {

#define OVPC_STR2(x) #x
#define OVPC_STR(x) OVPC_STR2(x)
constexpr const char* kName = "fuzz." OVPC_STR(OVPC_FUZZ_FORMAT);

[[noreturn]] void Finding(const std::string& what) {
  std::fprintf(stderr, "cloud_reader_fuzzer: %s\n", what.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  int bin_fields = 4;
  const ovpc::CloudFormat format = ovpc::FormatFromExtension(kName);
  if (format == ovpc::CloudFormat::kKittiBin) {
    if (bytes.empty()) return 0;
    bin_fields = (static_cast<unsigned char>(bytes[0]) & 1) != 0 ? 5 : 4;
    bytes.erase(0, 1);
  }
  try {
    const ovpc::Points points = ovpc::ParseCloud(bytes, format, kName, bin_fields);
    // A cloud is never larger than its file could hold: at least one byte per coordinate for text,
    // the record size for binary data.
    if (points.size() > bytes.size()) Finding("more points than bytes: " + std::to_string(points.size()));
  } catch (const ovpc::CloudIoError& e) {
    const std::string what = e.what();
    if (what.rfind(std::string(kName) + ": ", 0) != 0) Finding("error does not name the file: " + what);
    if (what.find('\n') != std::string::npos) Finding("error is not one line: " + what);
  }
  return 0;
}
