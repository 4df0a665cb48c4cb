// Finding the files (meshes, textures) a scene names: see AssetFinder in
// scene_reader.h for the order, scenes/FORMAT.md for the user's view.
#include <algorithm>
#include <filesystem>
#include <tuple>

#include "host/read_file.h"
#include "host/scene/scene_reader.h"

namespace caustica::scene_detail {

namespace fs = std::filesystem;

namespace {

// Enough for a course repository checked out beside the scene; a scene saved
// in a home folder must not turn one missing texture into a disk crawl.
constexpr int kMaxDepth = 8;
constexpr size_t kMaxEntries = 100000;

// Path components, lower-case, without "", "." and ".." or a drive ("C:").
std::vector<std::string> components(const std::string& path) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i <= path.size()) {
    size_t j = path.find_first_of("/\\", i);
    if (j == std::string::npos) j = path.size();
    const std::string c = lower(path.substr(i, j - i));
    const bool drive = c.size() == 2 && c[1] == ':';
    if (!c.empty() && c != "." && c != ".." && !drive) out.push_back(c);
    i = j + 1;
  }
  return out;
}

}  // namespace

void AssetFinder::index_tree() {
  indexed_ = true;
  std::error_code ec;
  fs::recursive_directory_iterator it(dir_, fs::directory_options::skip_permission_denied, ec), end;
  size_t seen = 0;
  for (; !ec && it != end && seen < kMaxEntries; it.increment(ec), ++seen) {
    const fs::path& p = it->path();
    const std::string name = p.filename().string();
    std::error_code ec2;
    if (it->is_directory(ec2)) {
      // Hidden folders (.git) hold no scene assets and can be huge.
      if ((!name.empty() && name[0] == '.') || it.depth() >= kMaxDepth) it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file(ec2)) by_name_.emplace(lower(name), p.string());
  }
}

std::string AssetFinder::find(const std::string& written, const char* subfolder, std::string* tried) {
  if (written.empty()) return "";
  std::string slashed = written;
  std::replace(slashed.begin(), slashed.end(), '\\', '/');
  const fs::path base(dir_);
  const fs::path as_written(slashed);
  const std::string name = as_written.filename().string();
  std::vector<fs::path> direct = {as_written.is_absolute() ? as_written : base / as_written};
  if (!name.empty()) {
    direct.push_back(base / name);
    direct.push_back(base / subfolder / name);
  }
  std::string looked;
  std::vector<std::string> seen;
  for (const fs::path& p : direct) {
    const fs::path n = p.lexically_normal();
    if (is_file(n)) return n.string();
    if (std::find(seen.begin(), seen.end(), n.string()) != seen.end()) continue;
    seen.push_back(n.string());
    looked += (looked.empty() ? "" : ", ") + n.string();
  }
  if (tried) *tried = "as " + looked + ", and by name in the folders under " + base.lexically_normal().string();
  if (name.empty()) return "";

  if (!indexed_) index_tree();
  // Best: shares the most trailing path components with what was written;
  // then lies in a folder named like the start of the scene's file name
  // (assets saved per source repository); then the shortest path.
  const std::vector<std::string> want = components(slashed);
  const std::string stem = lower(stem_);
  std::tuple<size_t, bool, size_t> best_score{0, false, 0};
  std::string best;
  auto range = by_name_.equal_range(lower(name));
  for (auto it = range.first; it != range.second; ++it) {
    const std::string& candidate = it->second;
    const std::string relative = fs::path(candidate).lexically_relative(base).string();
    const std::vector<std::string> have = components(relative);
    size_t match = 0;
    while (match < want.size() && match < have.size() &&
           want[want.size() - 1 - match] == have[have.size() - 1 - match])
      ++match;
    bool named = false;
    for (size_t i = 0; i + 1 < have.size(); ++i)
      named |= have[i].size() >= 3 && stem.compare(0, have[i].size(), have[i]) == 0;
    // Shorter is better: compare its complement so that larger wins throughout.
    const std::tuple<size_t, bool, size_t> score{match, named, static_cast<size_t>(-1) - candidate.size()};
    if (best.empty() || score > best_score || (score == best_score && candidate < best)) {
      best_score = score;
      best = candidate;
    }
  }
  return best.empty() ? best : fs::path(best).lexically_normal().string();
}

}  // namespace caustica::scene_detail
