#include "host/render/pass_set.h"

#include <algorithm>

#include "host/error.h"

namespace caustica {

PassSet PassSet::range(int begin, int end) {
  PassSet s;
  if (end > begin) s.ranges_.emplace_back(begin, end);
  return s;
}

PassSet PassSet::from_ranges(std::vector<Range> ranges, const std::string& what) {
  for (size_t i = 0; i < ranges.size(); ++i) {
    const auto [b, e] = ranges[i];
    if (b < 0 || e <= b || (i > 0 && b <= ranges[i - 1].second))
      throw Error(what + ": pass range " + std::to_string(i) + " [" + std::to_string(b) + ", " + std::to_string(e) +
                  ") is not a sorted, disjoint, non-adjacent, non-empty range of pass indices");
  }
  PassSet s;
  s.ranges_ = std::move(ranges);
  return s;
}

int PassSet::count() const {
  int n = 0;
  for (const auto& [b, e] : ranges_) n += e - b;
  return n;
}

int PassSet::first_common(const PassSet& other) const {
  int first = -1;
  for (const auto& [b, e] : ranges_)
    for (const auto& [ob, oe] : other.ranges_) {
      const int lo = std::max(b, ob), hi = std::min(e, oe);
      if (lo < hi && (first < 0 || lo < first)) first = lo;
    }
  return first;
}

bool PassSet::overlaps(const PassSet& other) const { return first_common(other) >= 0; }

void PassSet::add(int begin, int end) {
  if (end <= begin) return;
  const PassSet added = range(begin, end);
  if (overlaps(added))
    throw Error("pass set: passes [" + std::to_string(begin) + ", " + std::to_string(end) + ") added to " +
                describe() + ", which holds pass " + std::to_string(first_common(added)));
  ranges_.emplace_back(begin, end);
  std::sort(ranges_.begin(), ranges_.end());
  std::vector<Range> joined;
  for (const Range& r : ranges_) {
    if (!joined.empty() && joined.back().second == r.first) joined.back().second = r.second;
    else joined.push_back(r);
  }
  ranges_ = std::move(joined);
}

void PassSet::add(const PassSet& other) {
  if (overlaps(other))
    throw Error("pass set: " + other.describe() + " added to " + describe() + ": both hold pass " +
                std::to_string(first_common(other)));
  for (const auto& [b, e] : other.ranges_) add(b, e);
}

int PassSet::count_from(int first) const {
  int n = 0;
  for (const auto& [b, e] : ranges_) n += std::max(0, e - std::max(b, first));
  return n;
}

int PassSet::half_start(int last) {
  if (last < 1) return 0;
  int p = 1;
  while (p <= last / 2) p *= 2;
  return p;
}

std::string PassSet::describe() const {
  if (ranges_.empty()) return "no passes";
  std::string s;
  for (const auto& [b, e] : ranges_)
    s += (s.empty() ? "" : " ") + std::string("[") + std::to_string(b) + ", " + std::to_string(e) + ")";
  return "passes " + s;
}

}  // namespace caustica
