#include "ovpc/suite/output_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "ovpc/scenarios/recorder.h"

namespace ovpc::suite {
namespace {

namespace fs = std::filesystem;

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A folder this program may clear: marked, or one that holds only what `ovpc run` writes (run
// folders written before the marker existed).
bool Owned(const fs::path& dir) {
  if (fs::exists(dir / kMarker)) return true;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file() || !IsRunFile(e.path().filename().string())) return false;
  }
  return !ec;
}

void WriteMarker(const fs::path& dir) {
  std::ofstream marker(dir / kMarker);
  marker << "Made by ovpc: a later ovpc run, suite or family may clear this folder.\n";
  marker.close();
  if (!marker) throw BadInput(dir.string() + ": cannot write in this folder");
}

// write(2) all of `text`; false on any error (errno says which).
bool WriteAll(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

bool IsSafeComponent(const std::string& name, std::string* why) {
  const auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (name.empty()) return fail("is empty");
  if (name.size() > kMaxComponentBytes) return fail("is " + std::to_string(name.size()) + " bytes (at most " + std::to_string(kMaxComponentBytes) + ")");
  if (name == "." || name == "..") return fail("is a path, not a name");
  for (char c : name) {
    if (c == '/') return fail("holds a '/' (a name is not a path)");
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return fail("holds a control character");
  }
  return true;
}

bool IsRunFile(const std::string& name) {
  static const char* const kFiles[] = {"result.json", "result.json.part", "run.log", "trajectory.csv", "plans.csv",
                                       "cycles.csv", "topdown.png", scenarios::kRunLogName, kMarker, kLockFile};
  for (const char* f : kFiles) {
    if (name == f) return true;
  }
  // The pictures by the Recorder's own rule; a write cut short leaves a .part or .partial file.
  return scenarios::IsRecorderPicture(name) || EndsWith(name, ".part") || EndsWith(name, ".partial");
}

void MakeFolder(const fs::path& dir) {
  if (dir.empty()) throw BadInput("the output folder's name is empty");
  std::error_code ec;
  const bool fresh = !fs::exists(dir, ec) || (fs::is_directory(dir, ec) && fs::is_empty(dir, ec));
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw BadInput(dir.string() + ": cannot make this folder: " + (ec ? ec.message() : "not a folder"));
  if (fresh) WriteMarker(dir);
}

void CheckClearable(const fs::path& dir) {
  std::error_code ec;
  if (fs::is_symlink(dir, ec)) throw BadInput(dir.string() + ": is a symbolic link; refusing to clear it");
  if (!fs::exists(dir, ec)) return;
  if (!fs::is_directory(dir, ec)) throw BadInput(dir.string() + ": exists and is not a folder; refusing to replace it");
  if (!fs::is_empty(dir, ec) && !Owned(dir)) {
    throw BadInput(dir.string() + ": holds files that ovpc did not write (no " + kMarker +
                   "); refusing to clear it: remove it or choose another --out");
  }
}

void MakeFresh(const fs::path& dir) {
  CheckClearable(dir);
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec)) {
    fs::remove_all(dir, ec);
    if (ec) throw BadInput(dir.string() + ": cannot clear this folder: " + ec.message());
  }
  MakeFolder(dir);
}

FolderLock::FolderLock(const fs::path& dir) {
  MakeFolder(dir);
  const fs::path path = dir / kLockFile;
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw BadInput(dir.string() + ": cannot write in this folder: " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw BadInput(dir.string() + ": another ovpc process is writing to this folder (" + path.string() +
                   " is locked); wait for it or choose another --out");
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the flock
}

void WriteFileAtomic(const fs::path& path, const std::string& text) {
  const fs::path part = path.string() + ".part";
  const int fd = ::open(part.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(path.string() + ": cannot write it: " + std::strerror(errno));
  const bool written = WriteAll(fd, text);
  const int write_errno = errno;
  const bool closed = ::close(fd) == 0;
  const int close_errno = errno;
  std::error_code ec;
  if (!written || !closed) {
    fs::remove(part, ec);
    throw std::runtime_error(path.string() + ": could not write it whole: " + std::strerror(written ? close_errno : write_errno));
  }
  fs::rename(part, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(part, ignored);
    throw std::runtime_error(path.string() + ": cannot put it in place: " + ec.message());
  }
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace ovpc::suite
