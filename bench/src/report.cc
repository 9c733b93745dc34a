#include "ovpc/bench/report.h"

#include <cstdio>
#include <fstream>

namespace ovpc::bench {

std::string MachineName() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) {
        std::string name = line.substr(colon + 1);
        name.erase(0, name.find_first_not_of(" \t"));
        return name;
      }
    }
  }
  return "unknown";
}

double LoadAverage1Min() {
  std::ifstream loadavg("/proc/loadavg");
  double load = -1.0;
  if (!(loadavg >> load)) return -1.0;
  return load;
}

std::string BuildType() {
#if defined(OVPC_BUILD_TYPE)
  const std::string cmake_type = OVPC_BUILD_TYPE;
#else
  const std::string cmake_type;
#endif
#if defined(__OPTIMIZE__) && defined(NDEBUG)
  const std::string flags = "optimised, NDEBUG";
#elif defined(__OPTIMIZE__)
  const std::string flags = "optimised, assertions on";
#else
  const std::string flags = "unoptimised, assertions on: timings are not meaningful";
#endif
  return cmake_type.empty() ? flags : cmake_type + " (" + flags + ")";
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string JsonEscape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\u%04x", static_cast<unsigned>(c));
      out += buffer;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace ovpc::bench
