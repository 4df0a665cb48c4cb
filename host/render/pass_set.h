// The passes a film holds, by absolute pass index (issue 23: renders of a
// subset of passes, `caustica merge`, MPI ranks).
//
// Rules. A pass's samples are a pure function of (pixel, absolute pass
// index, seed): Sobol-Burley's sample index is the pass index, and the film
// sums passes as 128-bit integers, so films holding disjoint pass sets add
// to the bits of one film holding their union. A set is a list of disjoint,
// non-adjacent half-open ranges [begin, end), in increasing order (adjacent
// ranges are joined), so equal sets have equal lists. The half buffer's
// passes are the set's passes from P on, P the largest power of two at most
// the set's last pass (the same [P, N) as a film of passes [0, N)); pass 0
// is in no half.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace caustica {

class PassSet {
 public:
  using Range = std::pair<int, int>;  // [begin, end)
  PassSet() = default;
  static PassSet range(int begin, int end);  // empty when end <= begin
  // From ranges as stored (a state file's): throws caustica::Error, naming
  // `what`, unless they are sorted, disjoint, non-adjacent, non-empty and
  // within [0, 2^31).
  static PassSet from_ranges(std::vector<Range> ranges, const std::string& what);

  const std::vector<Range>& ranges() const { return ranges_; }
  bool empty() const { return ranges_.empty(); }
  int count() const;
  int first() const { return ranges_.empty() ? -1 : ranges_.front().first; }
  int last() const { return ranges_.empty() ? -1 : ranges_.back().second - 1; }
  int end() const { return ranges_.empty() ? 0 : ranges_.back().second; }  // one past the last pass
  bool is_prefix() const { return ranges_.empty() || (ranges_.size() == 1 && ranges_[0].first == 0); }
  // Adds [begin, end); throws caustica::Error if it overlaps the set.
  void add(int begin, int end);
  bool overlaps(const PassSet& other) const;
  // The first pass both hold (-1: none).
  int first_common(const PassSet& other) const;
  void add(const PassSet& other);  // throws caustica::Error when they overlap
  // Passes held at or after `first`.
  int count_from(int first) const;
  // The half buffer's first pass for a set whose last pass is `last`: the
  // largest power of two <= last (0 when last < 1: no half).
  static int half_start(int last);
  int half_count() const { return last() < 1 ? 0 : count_from(half_start(last())); }
  // "[0, 8) [16, 24)", for messages.
  std::string describe() const;
  bool operator==(const PassSet& o) const { return ranges_ == o.ranges_; }

 private:
  std::vector<Range> ranges_;
};

}  // namespace caustica
