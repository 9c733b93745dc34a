// The shared cell-key table (ovpc/core/internal/cell_table.h) against std::map, through inserts,
// lookups, erases (backward shift) and growth, with keys that collide in the home slot.
#include "ovpc/core/internal/cell_table.h"

#include <array>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace ovpc::internal {
namespace {

using Key = std::array<std::int32_t, 3>;

// Keys stored by id as the buffer stores its voxels: a freed id is reused.
struct Cells {
  std::vector<Key> keys;
  std::vector<std::uint32_t> free;
  auto key_of() const {
    return [this](std::uint32_t id) { return keys[id].data(); };
  }
  std::uint32_t NewId(const Key& k) {
    if (free.empty()) {
      keys.push_back(k);
      return static_cast<std::uint32_t>(keys.size() - 1);
    }
    const std::uint32_t id = free.back();
    free.pop_back();
    keys[id] = k;
    return id;
  }
};

TEST(CellTableTest, AgreesWithAMapThroughInsertsErasesAndGrowth) {
  CellTable table;
  table.Reset(4);
  Cells cells;
  std::map<Key, std::uint32_t> reference;
  std::mt19937 rng(7);
  // A small key range: many keys meet again, and runs of probes form and are shifted back.
  std::uniform_int_distribution<int> coordinate(-6, 6);
  for (int step = 0; step < 20000; ++step) {
    const Key k{coordinate(rng), coordinate(rng), coordinate(rng)};
    const std::uint32_t hash = CellHash(k.data());
    const auto it = reference.find(k);
    if (rng() % 3 == 0 && it != reference.end()) {
      table.Erase(it->second, hash);
      cells.free.push_back(it->second);
      reference.erase(it);
    } else {
      bool inserted = false;
      const std::uint32_t id = table.FindOrInsert(k.data(), hash, cells.key_of(), [&] { return cells.NewId(k); }, &inserted);
      EXPECT_EQ(inserted, it == reference.end());
      if (it != reference.end()) {
        EXPECT_EQ(id, it->second);
      } else {
        reference[k] = id;
      }
    }
    ASSERT_EQ(table.size(), reference.size());
  }
  // Every key of the range is found exactly when the map has it, with its id.
  for (int x = -6; x <= 6; ++x) {
    for (int y = -6; y <= 6; ++y) {
      for (int z = -6; z <= 6; ++z) {
        const Key k{x, y, z};
        const auto found = table.Find(k.data(), CellHash(k.data()), cells.key_of());
        const auto it = reference.find(k);
        ASSERT_EQ(found.has_value(), it != reference.end());
        if (found) {
          EXPECT_EQ(*found, it->second);
        }
      }
    }
  }
}

TEST(CellTableTest, KeysWithOneHashAreToldApartByTheirCoordinates) {
  // Two keys with the same 32-bit hash cannot be found by brute force in a test, so the table is
  // given a hash of 0 for all: every key probes from slot 0 and only the key comparison separates.
  CellTable table;
  Cells cells;
  for (int i = 0; i < 100; ++i) {
    const Key k{i, -i, 2 * i};
    table.FindOrInsert(k.data(), 0u, cells.key_of(), [&] { return cells.NewId(k); });
  }
  EXPECT_EQ(table.size(), 100u);
  for (int i = 0; i < 100; i += 2) table.Erase(static_cast<std::uint32_t>(i), 0u);
  for (int i = 0; i < 100; ++i) {
    const Key k{i, -i, 2 * i};
    const auto found = table.Find(k.data(), 0u, cells.key_of());
    EXPECT_EQ(found.has_value(), i % 2 == 1) << i;
    if (found) {
      EXPECT_EQ(*found, static_cast<std::uint32_t>(i));
    }
  }
}

}  // namespace
}  // namespace ovpc::internal
