// Shared by the project's libraries, not a stable API: the one open-addressing table from integer
// cell (voxel) keys to dense ids, behind the point cloud buffer's voxels, the per-update voxel
// accumulator and the map preparation's neighbour cells.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "ovpc/core/internal/hash.h"

namespace ovpc::internal {

/// The 32-bit hash of a cell key: its home slot (low bits) and its fingerprint.
template <typename Key>
inline std::uint32_t CellHash(const Key key[3]) {
  return static_cast<std::uint32_t>(HashCellKey(key[0], key[1], key[2]));
}

/// Maps cell keys (three integers) to ids the caller owns: linear probing in a power-of-two table
/// kept at most half full. A slot holds id + 1 and the key's 32-bit hash, so that a probe compares
/// keys only on a matching hash, and growing never reads a key. The caller stores the keys: the
/// lookups take `key_of(id)`, which returns a pointer to the three coordinates of cell `id`.
/// Erase shifts the probe run back, so the table never fills with tombstones.
class CellTable {
 public:
  /// Empties the table and sizes it for about `expected` cells (it grows when needed).
  void Reset(std::size_t expected) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    slots_.assign(capacity, Slot{0, 0});
    mask_ = capacity - 1;
    size_ = 0;
  }

  std::size_t size() const { return size_; }

  /// Brings the home slot of `hash` towards the cache (to overlap the misses of a batch).
  void Prefetch(std::uint32_t hash) const { __builtin_prefetch(&slots_[hash & mask_]); }

  /// The id of the cell `key` (hash `hash`), if it is in the table.
  template <typename Key, typename KeyOf>
  std::optional<std::uint32_t> Find(const Key key[3], std::uint32_t hash, KeyOf key_of) const {
    for (std::size_t slot = hash & mask_; slots_[slot].id_plus_1 != 0; slot = (slot + 1) & mask_) {
      const Slot& s = slots_[slot];
      if (s.hash == hash && SameKey(key_of(s.id_plus_1 - 1), key)) return s.id_plus_1 - 1;
    }
    return std::nullopt;
  }

  /// The id of the cell `key`; if it is not in the table, `new_id()` gives the id it gets, and
  /// `*inserted` (when given) is set.
  template <typename Key, typename KeyOf, typename NewId>
  std::uint32_t FindOrInsert(const Key key[3], std::uint32_t hash, KeyOf key_of, NewId new_id, bool* inserted = nullptr) {
    std::size_t slot = hash & mask_;
    for (; slots_[slot].id_plus_1 != 0; slot = (slot + 1) & mask_) {
      const Slot& s = slots_[slot];
      if (s.hash == hash && SameKey(key_of(s.id_plus_1 - 1), key)) {
        if (inserted != nullptr) *inserted = false;
        return s.id_plus_1 - 1;
      }
    }
    const std::uint32_t id = new_id();
    slots_[slot] = Slot{id + 1, hash};
    if (2 * ++size_ > slots_.size()) Grow();
    if (inserted != nullptr) *inserted = true;
    return id;
  }

  /// Removes the cell with id `id` and hash `hash` (it must be in the table).
  void Erase(std::uint32_t id, std::uint32_t hash) {
    std::size_t hole = hash & mask_;
    while (slots_[hole].id_plus_1 != id + 1) hole = (hole + 1) & mask_;
    // Backward shift: move up every later slot of the run that may live in the hole.
    for (std::size_t j = (hole + 1) & mask_; slots_[j].id_plus_1 != 0; j = (j + 1) & mask_) {
      const std::size_t home = slots_[j].hash & mask_;
      if (((j - home) & mask_) >= ((j - hole) & mask_)) {
        slots_[hole] = slots_[j];
        hole = j;
      }
    }
    slots_[hole] = Slot{0, 0};
    --size_;
  }

 private:
  struct Slot {
    std::uint32_t id_plus_1;  // 0: empty
    std::uint32_t hash;
  };

  template <typename A, typename B>
  static bool SameKey(const A* a, const B* b) {
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
  }

  void Grow() {
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(2 * old.size(), Slot{0, 0});
    mask_ = slots_.size() - 1;
    for (const Slot& s : old) {
      if (s.id_plus_1 == 0) continue;
      std::size_t slot = s.hash & mask_;
      while (slots_[slot].id_plus_1 != 0) slot = (slot + 1) & mask_;
      slots_[slot] = s;
    }
  }

  std::vector<Slot> slots_ = std::vector<Slot>(16, Slot{0, 0});
  std::size_t mask_ = 15;
  std::size_t size_ = 0;
};

}  // namespace ovpc::internal
