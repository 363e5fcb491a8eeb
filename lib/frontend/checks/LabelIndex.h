//! @file LabelIndex.h
//! @brief A file's labels by name, in any case, for the per-file checker (private).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "frontend/Ast.h"
#include "support/Bytes.h"
#include "support/CaseFold.h"

namespace iso::frontend::checks {

/// A file's labels by name, in any case (E203, jumps): open addressing over the indices of
/// File::labels, sized once for all of them. (A CAM program has a label every few lines: a
/// node per label and a pointer chase per lookup cost more than the checks that use them.)
class LabelIndex {
public:
  explicit LabelIndex(const std::vector<StmtLabel>& labels) : labels_(labels) {}
  /// Empties it, with room for every label of the file (at most half full: short probes).
  void clear() {
    size_t capacity = 16;
    while (capacity < 2 * labels_.size())
      capacity *= 2;
    slots_.assign(capacity, Slot{0, kNoIndex});
  }
  /// Adds label `j` (an index in File::labels), unless a label of its name is there already:
  /// then that one's index, else kNoIndex.
  uint32_t add(uint32_t j) {
    const std::string_view name = labels_[j].text;
    const uint64_t h = hash(name);
    size_t i = static_cast<size_t>(h) & (slots_.size() - 1);
    for (; slots_[i].label != kNoIndex; i = (i + 1) & (slots_.size() - 1))
      if (slots_[i].hash == h && support::iequals(labels_[slots_[i].label].text, name)) return slots_[i].label;
    slots_[i] = Slot{h, j};
    return kNoIndex;
  }
  /// The index in File::labels of the label `name`, or kNoIndex.
  uint32_t find(std::string_view name) const {
    if (slots_.empty()) return kNoIndex;
    const uint64_t h = hash(name);
    for (size_t i = static_cast<size_t>(h) & (slots_.size() - 1); slots_[i].label != kNoIndex;
         i = (i + 1) & (slots_.size() - 1))
      if (slots_[i].hash == h && support::iequals(labels_[slots_[i].label].text, name)) return slots_[i].label;
    return kNoIndex;
  }

private:
  struct Slot {
    uint64_t hash;  ///< all of it: names are compared only when the whole hash agrees
    uint32_t label; ///< kNoIndex: empty
  };
  static uint64_t hash(std::string_view s) {
    support::Fnv1a h;
    for (char c : s)
      h.byte(static_cast<uint8_t>(support::upperAscii(c)));
    return h.value() ^ (h.value() >> 29); // the low bits pick the slot: fold the high ones in
  }
  const std::vector<StmtLabel>& labels_;
  std::vector<Slot> slots_;
};

} // namespace iso::frontend::checks
