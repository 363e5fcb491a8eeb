//! @file LineNumbers.cpp
//! @brief W411: an N number written twice.
#include "frontend/checks/FileChecker.h"

#include <algorithm>
#include <string_view>
#include <unordered_map>

namespace iso::frontend::checks {

using diag::Msg;

void FileChecker::checkLineNumbers() {
  // SPEC §2: compared as written, so N132,5 and N132.5 (or N10 and N010) are different numbers.
  // File::numbers holds them in statement order. Equal texts have equal values: numbers that
  // strictly increase, as CAM output's do, hold no two alike.
  const auto& nums = f_.numbers;
  if (std::adjacent_find(nums.begin(), nums.end(),
                         [](const LineNumber& a, const LineNumber& b) { return !(a.value < b.value); }) == nums.end())
    return;
  std::unordered_map<std::string_view, uint32_t> seen;
  seen.reserve(nums.size());
  for (uint32_t k = 0; k < nums.size(); ++k) {
    const LineNumber& n = nums[k];
    auto [it, ins] = seen.emplace(n.text, k);
    if (!ins) {
      auto& d = diags_.report(Msg::LineNumberTwice, n.loc, n.len, n.text);
      d.note(Msg::LineNumberTwiceNote, nums[it->second].loc);
      // z32: a GO naming this number finds the first line, never this one
      for (const GoJump& g : f_.gos)
        for (std::string_view t : {g.from, g.to})
          if (t.size() == n.text.size() + 1 && t[0] == 'N' && t.substr(1) == n.text) {
            d.note(Msg::LineNumberTwiceGoNote, g.range && t.data() == g.to.data() ? g.toLoc : g.fromLoc, t,
                   nums[it->second].loc.line);
            break;
          }
    }
  }
}

} // namespace iso::frontend::checks
