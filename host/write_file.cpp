#include "host/write_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "host/error.h"

namespace caustica {
namespace fs = std::filesystem;

namespace {

// Writes every byte to fd: false (errno set) on the first failure.
bool write_fully(int fd, std::string_view bytes) {
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = ENOSPC;
      return false;
    }
    written += size_t(n);
  }
  return true;
}

}  // namespace

void write_output_file(const std::string& path, std::string_view bytes, const std::string& what) {
  auto fail = [&](const std::string& why) { return Error("cannot write " + what + " '" + path + "': " + why); };
  std::error_code ec;
  // Through a link to the file it names (which may not exist yet).
  fs::path target = path;
  for (int links = 0; fs::is_symlink(fs::symlink_status(target, ec)); ++links) {
    if (links == 40) throw fail("too many levels of symbolic links");
    const fs::path next = fs::read_symlink(target, ec);
    if (ec) throw fail("cannot follow the link: " + ec.message());
    target = next.is_absolute() ? next : target.parent_path() / next;
  }
  const fs::file_status status = fs::status(target, ec);
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    if (fs::is_directory(status)) throw fail("it is a directory");
    const int fd = ::open(target.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) throw fail(std::string("cannot open it: ") + std::strerror(errno));
    const bool ok = write_fully(fd, bytes);
    const int error = errno;
    if (::close(fd) != 0 || !ok) throw fail(std::string("write failed: ") + std::strerror(ok ? errno : error));
    return;
  }
  const std::string temporary = target.string() + ".tmp";
  // Every failure from here on leaves the previous file and no temporary.
  auto fail_temporary = [&](const std::string& step, int error) {
    ::unlink(temporary.c_str());
    return fail(step + " " + temporary + " failed: " + std::strerror(error));
  };
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw fail("cannot create " + temporary + ": " + std::strerror(errno));
  if (!write_fully(fd, bytes)) {
    const int error = errno;
    ::close(fd);
    throw fail_temporary("writing", error);
  }
  // On disk before it replaces the previous file: a crash after the rename
  // must not leave a file whose bytes never arrived.
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    throw fail_temporary("flushing", error);
  }
  if (::close(fd) != 0) throw fail_temporary("closing", errno);
  if (std::rename(temporary.c_str(), target.c_str()) != 0) throw fail_temporary("renaming", errno);
  // The rename itself on disk: the directory flushed. Best effort: some file
  // systems refuse fsync on a directory, and the file is complete either way.
  const fs::path dir = target.parent_path();
  const int dir_fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

}  // namespace caustica
