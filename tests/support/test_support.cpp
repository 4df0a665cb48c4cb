#include "tests/support/test_support.h"

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <unistd.h>

namespace caustica::test {

Runtime& runtime() {
  static std::unique_ptr<Runtime> rt = [] {
    const char* env = std::getenv("CAUSTICA_TEST_DEVICE");
    return std::make_unique<Runtime>(select_device(env ? env : "cpu"));
  }();
  return *rt;
}

std::string source_dir() { return CAUSTICA_SOURCE_DIR; }

std::string shared_dir() {
  std::filesystem::path p;
  if (const char* env = std::getenv("CAUSTICA_SHARED_DIR"))
    p = env;
  else
    p = std::filesystem::path(CAUSTICA_SOURCE_DIR) / ".." / "shared";
  std::error_code ec;
  if (!std::filesystem::is_directory(p, ec)) return {};
  return std::filesystem::weakly_canonical(p, ec).string();
}

std::string binary_path() { return CAUSTICA_BINARY; }

std::string temp_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : "caustica";
  for (auto& c : name)
    if (c == '/') c = '_';
  auto dir = std::filesystem::temp_directory_path() / ("caustica_test_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace caustica::test
