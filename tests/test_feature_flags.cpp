// The feature flags (issue 21): one table (kernels/shared/feature_flags.h)
// that the kernels, the host's #ifndef defaults, the runtime's option
// completion and cache key, SceneFeatures' options and --verbose line, and
// DESIGN.md's table all agree with.

// First, before anything names a flag: the header's #ifndef defaults (what
// host code compiling the kernel library gets) must be the table's.
#include "kernels/shared/feature_flags.h"
#define CS_CHECK_DEFAULT(name, def, word, description) \
  static_assert((name) == (def), "the #ifndef default of " #name " disagrees with its row in the table");
CS_FEATURE_FLAGS(CS_CHECK_DEFAULT)
#undef CS_CHECK_DEFAULT

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "host/cl/embedded_kernels.h"
#include "host/cl/runtime.h"
#include "host/error.h"
#include "host/scene/features.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::set<std::string> table_names() {
  std::set<std::string> names;
  for (const auto& f : kFeatureFlags) names.insert(f.name);
  return names;
}

// HAS_* names in text, also in -DHAS_X; not inside longer identifiers
// (kHAS_X, CS_HAS_X). HAS_X is the docs' placeholder.
std::vector<std::string> flag_names_in(const std::string& text) {
  static const std::regex name(R"re((?:^|[^A-Za-z0-9_]|-D)(HAS_[A-Z0-9_]*[A-Z0-9]))re");
  std::vector<std::string> out;
  for (std::sregex_iterator it(text.begin(), text.end(), name), end; it != end; ++it)
    if ((*it)[1].str() != "HAS_X") out.push_back((*it)[1].str());
  return out;
}

TEST(FeatureFlags, TableRowsAreWellFormed) {
  std::set<std::string> names, words;
  for (const auto& f : kFeatureFlags) {
    EXPECT_EQ(std::string(f.name).rfind("HAS_", 0), 0u) << f.name;
    EXPECT_TRUE(f.default_value == 0 || f.default_value == 1) << f.name;
    EXPECT_TRUE(names.insert(f.name).second) << "twice: " << f.name;
    EXPECT_TRUE(words.insert(f.word).second) << "word twice: " << f.word;
    EXPECT_NE(std::string(f.description), "") << f.name;
    EXPECT_EQ(std::string(f.description).find('|'), std::string::npos) << f.name << ": '|' breaks the docs' table";
  }
}

// DESIGN.md's table (between the feature-flags markers) lists exactly the
// table's rows, in its order.
TEST(FeatureFlags, DesignMdTableIsTheTable) {
  const std::string doc = read_text(std::filesystem::path(CAUSTICA_SOURCE_DIR) / "DESIGN.md");
  const size_t begin = doc.find("<!-- feature-flags:");
  const size_t end = doc.find("<!-- /feature-flags -->");
  ASSERT_NE(begin, std::string::npos) << "DESIGN.md has no feature-flags table";
  ASSERT_NE(end, std::string::npos);
  std::istringstream in(doc.substr(begin, end - begin));
  static const std::regex row(R"re(^\| `(HAS_[A-Z0-9_]+)` \| ([01]) \| `([^`]*)` \| (.*) \|\s*$)re");
  std::vector<std::string> got, want;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_match(line, m, row)) got.push_back(line);
    else if (line.rfind("| `", 0) == 0) ADD_FAILURE() << "DESIGN.md: unparsed feature-flag row: " << line;
  }
  std::string expected;
  for (const auto& f : kFeatureFlags) {
    want.push_back(std::string("| `") + f.name + "` | " + std::to_string(f.default_value) + " | `" + f.word + "` | " +
                   f.description + " |");
    expected += want.back() + "\n";
  }
  EXPECT_EQ(got, want) << "DESIGN.md's feature-flag rows should be, from kernels/shared/feature_flags.h:\n" << expected;
}

// Every HAS_* the kernels name is in the table and every row is tested by
// some kernel; flags are tested with #if, never #ifdef / #ifndef /
// defined() (except an #ifndef default that agrees with the table); none of
// the old names (X_WITH_Y, PATH_CHECK_NUMERICS) is left.
TEST(FeatureFlags, KernelsUseExactlyTheTableWithIf) {
  const std::set<std::string> table = table_names();
  std::map<std::string, int> defaults;
  for (const auto& f : kFeatureFlags) defaults[f.name] = f.default_value;
  std::set<std::string> tested;
  static const std::regex old_name(R"re(\b[A-Z]+_WITH_[A-Z0-9_]+|PATH_CHECK_NUMERICS)re");
  static const std::regex if_test(R"re(^\s*#\s*(if|elif)\b(.*)$)re");
  static const std::regex presence(R"re(^\s*#\s*(ifdef|ifndef)\s+(HAS_\w+)|defined\s*\(?\s*(HAS_\w+))re");
  static const std::regex default_block(R"re(#\s*ifndef\s+(HAS_\w+)\s*\n\s*#\s*define\s+(HAS_\w+)\s+([01])\s*\n\s*#\s*endif)re");
  for (const auto& file : embedded_kernel_files()) {
    for (const auto& n : flag_names_in(file.text)) EXPECT_TRUE(table.count(n)) << "kernels/" << file.path << ": " << n;
    std::smatch m;
    EXPECT_FALSE(std::regex_search(file.text, m, old_name)) << "kernels/" << file.path << ": old flag name " << m.str();
    // #ifndef defaults must agree with the table; they are then no presence test.
    std::string text = file.text;
    for (std::sregex_iterator it(file.text.begin(), file.text.end(), default_block), end; it != end; ++it) {
      const auto& d = *it;
      EXPECT_EQ(d[1].str(), d[2].str()) << "kernels/" << file.path;
      EXPECT_TRUE(defaults.count(d[1].str()) && defaults[d[1].str()] == std::stoi(d[3].str()))
          << "kernels/" << file.path << ": #ifndef default " << d[1] << " " << d[3] << " disagrees with the table";
    }
    text = std::regex_replace(text, default_block, "");
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
      if (std::regex_search(line, m, presence)) ADD_FAILURE() << "kernels/" << file.path << ": tests a flag's presence: " << line;
      if (std::regex_match(line, m, if_test) && file.path != "shared/feature_flags.h")
        for (const auto& n : flag_names_in(m[2])) tested.insert(n);
    }
  }
  for (const auto& n : table) EXPECT_TRUE(tested.count(n)) << n << " is in the table but no kernel tests it with #if";
}

// The host, tests, bench, tools and docs name no HAS_* outside the table and
// none of the old names.
TEST(FeatureFlags, SourcesAndDocsNameOnlyTableFlags) {
  namespace fs = std::filesystem;
  const fs::path root(CAUSTICA_SOURCE_DIR);
  const std::set<std::string> table = table_names();
  const std::set<std::string> extensions{".h", ".cl", ".cpp", ".hpp", ".py", ".md", ".sh", ".cmake", ".txt", ".json"};
  static const std::regex old_name(R"re((?:^|[^A-Za-z0-9_]|-D)((BSDF|PATH|PHONG)_WITH_[A-Z0-9_]+|PATH_CHECK_NUMERICS))re");
  std::vector<fs::path> files;
  for (const char* dir : {"kernels", "host", "tests", "bench", "tools", "docs", "fuzz", "cmake"}) {
    if (!fs::exists(root / dir)) continue;
    // Not the project's own: Python environments and caches that benchmark
    // scripts make in place (bench/cycles/venv, bench/*/cache).
    for (auto it = fs::recursive_directory_iterator(root / dir); it != fs::recursive_directory_iterator(); ++it) {
      const fs::directory_entry& e = *it;
      if (e.is_directory() && (fs::exists(e.path() / "pyvenv.cfg") || e.path().filename() == "__pycache__" ||
                               e.path().filename() == "cache")) {
        it.disable_recursion_pending();
        continue;
      }
      if (e.is_regular_file() && extensions.count(e.path().extension().string()) && e.file_size() < 4000000)
        files.push_back(e.path());
    }
  }
  for (const auto& e : fs::directory_iterator(root))
    if (e.is_regular_file() && e.path().extension() == ".md") files.push_back(e.path());
  ASSERT_GT(files.size(), 50u);
  for (const auto& p : files) {
    if (p.filename() == "test_feature_flags.cpp") continue;  // names wrong flags on purpose
    const std::string text = read_text(p);
    for (const auto& n : flag_names_in(text)) EXPECT_TRUE(table.count(n)) << fs::relative(p, root).string() << ": " << n;
    std::smatch m;
    EXPECT_FALSE(std::regex_search(text, m, old_name)) << fs::relative(p, root).string() << ": old flag name " << m[1].str();
  }
}

TEST(FeatureFlags, OptionsAreCompletedInTableOrder) {
  std::string all_defaults;
  for (const auto& f : kFeatureFlags)
    all_defaults += std::string(all_defaults.empty() ? "" : " ") + "-D" + f.name + "=" + std::to_string(f.default_value);
  EXPECT_EQ(complete_feature_flags(""), all_defaults);
  // The same flags spelled differently: the same options (and cache key).
  const std::string a = complete_feature_flags("-DHAS_SPHERES -DHAS_TRIANGLES -cl-fast-relaxed-math -DOTHER=3");
  const std::string b =
      complete_feature_flags("-DHAS_TRIANGLES=1 -cl-fast-relaxed-math  -D HAS_SPHERES=1 -DOTHER=3 -DHAS_CAUSTICS=0");
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.rfind("-cl-fast-relaxed-math -DOTHER=3 -DHAS_SPHERES=1 -DHAS_CYLINDERS=0 -DHAS_TRIANGLES=1", 0), 0u) << a;
  EXPECT_NE(a.find("-DHAS_DIELECTRIC=1"), std::string::npos) << a;
  // The last definition counts; a completed string completes to itself.
  EXPECT_NE(complete_feature_flags("-DHAS_DIELECTRIC=1 -DHAS_DIELECTRIC=0").find("-DHAS_DIELECTRIC=0"), std::string::npos);
  EXPECT_EQ(complete_feature_flags(a), a);
  const std::string unknown = test::error_of([] { complete_feature_flags("-DHAS_NOPE"); });
  EXPECT_NE(unknown.find("HAS_NOPE is not a feature flag"), std::string::npos) << unknown;
  const std::string two = test::error_of([] { complete_feature_flags("-DHAS_SPHERES=2"); });
  EXPECT_NE(two.find("0 or 1"), std::string::npos) << two;
}

TEST(FeatureFlags, SceneFeaturesWriteEveryFlagFromTheTable) {
  SceneFeatures f;
  f.mode = RenderMode::Path;
  f.spheres = f.lights = f.caustics = true;
  f.caustics_reason = "why";
  const std::string options = f.build_options();
  std::string want;
  for (int i = 0; i < kFeatureFlagCount; ++i)
    want += std::string(" -D") + kFeatureFlags[i].name + "=" + std::to_string(f.flag_value(FeatureFlag(i)));
  EXPECT_EQ(options, want);
  EXPECT_EQ(complete_feature_flags(options), options.substr(1)) << "build_options names every flag in table order";
  EXPECT_NE(options.find("-DHAS_SPHERES=1"), std::string::npos);
  EXPECT_NE(options.find("-DHAS_CAUSTICS=1"), std::string::npos);
  EXPECT_NE(options.find("-DHAS_DIELECTRIC=0"), std::string::npos) << "path mode without glass";
  EXPECT_NE(options.find("-DHAS_AREA_LIGHTS=0"), std::string::npos);
  const std::string line = f.describe();
  EXPECT_EQ(line.rfind("mode=path ", 0), 0u) << line;
  for (const auto& row : kFeatureFlags) EXPECT_NE(line.find(std::string(" ") + row.word + "="), std::string::npos) << line;
  EXPECT_NE(line.find("spheres=yes"), std::string::npos) << line;
  EXPECT_NE(line.find("photon-pass=yes (why)"), std::string::npos) << line;
  EXPECT_NE(line.find("cylinders=no"), std::string::npos) << line;
  // Phong keeps the dielectric BSDF and area-light code for its photon pass.
  f.mode = RenderMode::Phong;
  EXPECT_EQ(f.flag_value(FeatureFlag::kHAS_DIELECTRIC), 1);
  EXPECT_EQ(f.flag_value(FeatureFlag::kHAS_AREA_LIGHTS), 1);
  EXPECT_EQ(f.flag_value(FeatureFlag::kHAS_REFRACTION), 0);
}

}  // namespace
}  // namespace caustica
