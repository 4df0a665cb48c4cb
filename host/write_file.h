// Every file caustica writes (images, state files, error reports) goes
// through here, checked to the end. A regular file (or none yet) is
// replaced atomically: the bytes go to "<file>.tmp" beside it, are written
// in full, flushed to disk (fsync) and closed, each step checked, and only
// then renamed over the file. A full disk, a failed write or a failed
// rename is a caustica::Error and leaves the previous file as it was, with
// no temporary behind. A symbolic link is followed: the file it names is
// replaced, the link stays. A path that exists and is not a regular file (a
// device such as /dev/null, a FIFO) cannot be replaced, and is written in
// place, every write checked. Errors read "cannot write <what> '<path>':
// <reason>".
#pragma once

#include <string>
#include <string_view>

namespace caustica {

void write_output_file(const std::string& path, std::string_view bytes, const std::string& what);

}  // namespace caustica
