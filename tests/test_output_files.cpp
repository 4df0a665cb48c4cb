// Every file caustica writes is checked through to the rename (issue 38,
// host/write_file.h): a write that fails is an error, and the previous
// file stays whole, with no temporary left behind.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <fstream>

#include "host/error.h"
#include "host/image/image_io.h"
#include "host/render/render_state.h"
#include "host/write_file.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {
namespace fs = std::filesystem;

// Files may grow to `bytes` at most while it lives: a longer write fails
// with EFBIG, as a full disk fails with ENOSPC (SIGXFSZ ignored, so the
// write returns the error instead of ending the process).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_handler_);
  }

 private:
  rlimit saved_{};
  void (*previous_handler_)(int) = nullptr;
};

std::vector<std::string> files_in(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

ImageF gradient(int w, int h) {
  ImageF image(w, h);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = float(i % 97) / 97.0f;
  return image;
}

TEST(OutputFiles, AFailedWriteKeepsThePreviousFileAndLeavesNoTemporary) {
  const std::string dir = test::temp_dir();
  for (const char* name : {"image.pfm", "image.png", "image.exr", "image.ppm", "state.cst", "report.csv"}) {
    SCOPED_TRACE(name);
    const std::string path = dir + "/" + name;
    { std::ofstream(path) << "previous"; }
    std::string message;
    {
      const FileSizeLimit limit(64);  // every format below writes more
      message = test::error_of([&] {
        const std::string ext = fs::path(path).extension().string();
        if (ext == ".cst") {
          RenderState state;
          state.identity = {{"scene hash", "0"}};
          state.film.accumulated.assign(1000, 7);
          write_render_state(path, state);
        } else if (ext == ".csv") {
          write_output_file(path, std::string(1000, 'x'), "error report");
        } else {
          write_image(path, gradient(64, 32), DisplaySettings{});
        }
      });
    }
    EXPECT_TRUE(test::Contains(message, {"cannot write", path})) << message;
    EXPECT_EQ(test::slurp(path), "previous");
    for (const std::string& f : files_in(dir)) EXPECT_EQ(f.find(".tmp"), std::string::npos) << f;
  }
}

TEST(OutputFiles, AFullDeviceIsAnError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string link = test::temp_dir() + "/full.pfm";
  fs::create_symlink("/dev/full", link);
  const std::string message = test::error_of([&] { write_image(link, gradient(8, 8), DisplaySettings{}); });
  EXPECT_TRUE(test::Contains(message, {"cannot write image", "full.pfm", "No space left on device"})) << message;
  EXPECT_TRUE(fs::is_symlink(link));  // a device is written in place, never replaced
}

TEST(OutputFiles, ALinkIsFollowedAndStays) {
  const std::string dir = test::temp_dir();
  fs::create_directory(dir + "/real");
  fs::create_symlink("real/target.pfm", dir + "/link.pfm");  // relative, to a file not there yet
  write_image(dir + "/link.pfm", gradient(8, 8), DisplaySettings{});
  EXPECT_TRUE(fs::is_symlink(dir + "/link.pfm"));
  EXPECT_TRUE(fs::is_regular_file(dir + "/real/target.pfm"));
  EXPECT_EQ(read_hdr_image(dir + "/link.pfm").rgb, gradient(8, 8).rgb);
  const std::string message =
      test::error_of([&] { write_output_file(dir + "/real", "x", "error report"); });  // a directory
  EXPECT_TRUE(test::Contains(message, {"cannot write error report", "is a directory"})) << message;
}

}  // namespace
}  // namespace caustica
