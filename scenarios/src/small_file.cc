// Reading scenario, family and preset files: regular files of a bounded size only, checked before
// a byte is read; and the rule for scenario and family names.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <string>

#include "format.h"
#include "ovpc/scenarios/scenario_yaml.h"

namespace ovpc::scenarios {
namespace {

// What a file that is not a regular one is, for messages.
std::string KindOf(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  return "neither a file nor a directory";
}

class FileChecks {
 public:
  FileChecks(const std::string& path, const std::string& what, std::uintmax_t max_bytes)
      : path_(path), what_(what), max_bytes_(max_bytes) {}

  [[noreturn]] void Fail(const std::string& problem) const { throw ScenarioError(path_ + ": " + problem); }
  [[noreturn]] void FailErrno(const std::string& doing) const {
    Fail("cannot " + doing + " the " + what_ + " (" + std::strerror(errno) + ")");
  }
  void Check(const struct stat& st) const {
    if (S_ISDIR(st.st_mode)) Fail("is a directory, not a " + what_);
    if (!S_ISREG(st.st_mode)) Fail("is not a regular file (" + KindOf(st.st_mode) + ")");
    if (static_cast<std::uintmax_t>(st.st_size) > max_bytes_) FailSize(static_cast<std::uintmax_t>(st.st_size));
  }
  [[noreturn]] void FailSize(std::uintmax_t bytes) const {
    Fail("is " + std::to_string(bytes) + " bytes; a " + what_ + " is at most " + std::to_string(max_bytes_) + " bytes" +
         (max_bytes_ == kMaxScenarioFileBytes ? " (1 MiB)" : ""));
  }

 private:
  const std::string& path_;
  const std::string& what_;
  std::uintmax_t max_bytes_;
};

struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string ReadSmallRegularFile(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  const FileChecks checks(path, what, max_bytes);
  struct stat st {};
  // Checked before opening (opening a FIFO would wait for a writer, a socket cannot be opened), and
  // again on what was opened (the path may have changed in between); O_NONBLOCK: never wait.
  if (::stat(path.c_str(), &st) != 0) checks.FailErrno("open");
  checks.Check(st);
  const Descriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC)};
  if (file.fd < 0) checks.FailErrno("open");
  if (::fstat(file.fd, &st) != 0) checks.FailErrno("read");
  checks.Check(st);
  std::string text;
  char chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(file.fd, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) checks.FailErrno("read");
    if (n == 0) break;
    text.append(chunk, static_cast<std::size_t>(n));
    if (text.size() > max_bytes) checks.FailSize(text.size());  // it grew while read
  }
  return text;
}

std::string NameProblem(const std::string& name, std::size_t max_bytes) {
  if (name.empty()) return "is empty";
  if (name.size() > max_bytes) return "is " + std::to_string(name.size()) + " bytes long (at most " + std::to_string(max_bytes) + ")";
  if (name[0] == '.') return "starts with '.'";
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x80 && (std::isalnum(u) || c == '_' || c == '-' || c == '.')) continue;
    if (c == '/') return "holds '/' (a name is not a path)";
    constexpr char kHex[] = "0123456789abcdef";
    const std::string shown = u > 0x20 && u < 0x7f ? std::string(1, c) : std::string("\\x") + kHex[u >> 4] + kHex[u & 15];
    return "holds '" + shown + "'";
  }
  return "";
}

void ValidateName(const std::string& file, int line, const std::string& name, std::size_t max_bytes) {
  const std::string problem = NameProblem(name, max_bytes);
  if (problem.empty()) return;
  throw ScenarioError(file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": name '" + internal::Abbreviated(name) +
                      "' " + problem +
                      "; a name is 1 to " + std::to_string(max_bytes) +
                      " ASCII letters, digits, '_', '-' and '.', not starting with '.'");
}

}  // namespace ovpc::scenarios
