// Bounded reads (read_file.h). open + fstat on the same descriptor, so the
// file checked is the file read; O_NONBLOCK keeps open() from waiting on a
// FIFO that has no writer. The read itself stops one byte past the limit, so
// a file that grows after fstat is still bounded.
#include "host/read_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "host/error.h"

namespace caustica {

bool is_file(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

std::string format_bytes(uint64_t bytes) {
  if (bytes >= (uint64_t(1) << 30) && bytes % (uint64_t(1) << 30) == 0)
    return std::to_string(bytes >> 30) + " GiB";
  if (bytes >= (uint64_t(1) << 20) && bytes % (uint64_t(1) << 20) == 0)
    return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

namespace {

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a pipe (FIFO)";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string read_input_file(const std::string& path, const std::string& what, uint64_t limit_bytes) {
  Fd f{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY)};
  if (f.fd < 0) {
    const int e = errno;
    if (e == ENOENT) throw Error(path + ": " + what + " not found");
    throw Error(path + ": cannot open " + what + ": " + std::strerror(e));
  }
  struct stat st{};
  if (::fstat(f.fd, &st) != 0) throw Error(path + ": cannot examine " + what + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    throw Error(path + ": is " + kind_of(st.st_mode) + ", expected a regular file (" + what + ")");
  if (st.st_size < 0 || uint64_t(st.st_size) > limit_bytes)
    throw Error(path + ": " + what + " is " + std::to_string(uint64_t(st.st_size)) + " bytes, over the limit of " +
                format_bytes(limit_bytes));
  std::string data;
  data.resize(size_t(st.st_size));
  size_t have = 0;
  for (;;) {
    if (have == data.size()) {
      if (have > limit_bytes) break;
      data.resize(std::min<uint64_t>(uint64_t(have) + (uint64_t(1) << 16), limit_bytes + 1));
    }
    const ssize_t n = ::read(f.fd, &data[have], data.size() - have);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw Error(path + ": error while reading " + what + ": " + std::strerror(errno));
    }
    if (n == 0) break;
    have += size_t(n);
  }
  if (have > limit_bytes)
    throw Error(path + ": " + what + " grew past the limit of " + format_bytes(limit_bytes) + " while being read");
  data.resize(have);
  return data;
}

}  // namespace caustica
