// The output folders of `ovpc run`, `ovpc suite` and `ovpc family`: made and cleared only inside
// `--out`, only when this program made them, with one writer at a time, and report files that are
// either whole or not there.
#pragma once

#include <filesystem>
#include <string>

#include "ovpc/suite/errors.h"

namespace ovpc::suite {

/// The file that marks a folder as made by this program (it may be cleared by a later run).
inline constexpr const char* kMarker = ".ovpc-output";
/// The lock file of a folder being written (flock; released when the process ends).
inline constexpr const char* kLockFile = ".ovpc-lock";
/// Longest folder name made from a name (a file system allows 255 bytes).
inline constexpr std::size_t kMaxComponentBytes = 200;

/// Whether `name` can be one folder name under --out: 1-200 bytes, no separator, no control
/// character, not "." or "..". `why` gets the reason when it cannot.
bool IsSafeComponent(const std::string& name, std::string* why = nullptr);

/// Makes `dir` (and its parents); marks it as this program's when this call made it or it was
/// empty (a folder that holds a user's files is never marked).
/// @throws BadInput when it cannot be made or written (before any run starts).
void MakeFolder(const std::filesystem::path& dir);

/// Leaves `dir` empty and marked: made when missing; cleared when it is this program's (it has the
/// marker, or holds only the files an `ovpc run` writes); refused otherwise, removing nothing.
/// @throws BadInput naming the folder when it refuses.
void MakeFresh(const std::filesystem::path& dir);

/// Refuses (BadInput) a `dir` that MakeFresh would refuse, without changing anything.
void CheckClearable(const std::filesystem::path& dir);

/// Whether `name` is a file an `ovpc run` writes in its folder (result, logs, picture, snapshots).
bool IsRunFile(const std::string& name);

/// Makes `dir` (MakeFolder) and holds its lock for its lifetime: a second writer of the same folder is refused.
class FolderLock {
 public:
  /// @throws BadInput when another process holds it, or the folder cannot be written.
  explicit FolderLock(const std::filesystem::path& dir);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

/// Writes `text` to `path` through a temporary file in the same folder, checked and renamed: the
/// file is whole, or an earlier file at `path` is left as it was.
/// @throws std::runtime_error naming `path` when it cannot be written whole.
void WriteFileAtomic(const std::filesystem::path& path, const std::string& text);

/// `text` as one CSV field (RFC 4180: quoted when it holds a comma, a quote or a line break).
std::string CsvField(const std::string& text);

}  // namespace ovpc::suite
