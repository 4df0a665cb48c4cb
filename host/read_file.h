// Bounded whole-file reads for every file caustica parses (scenes, meshes,
// material libraries, textures, images). Only regular files are read: a
// device such as /dev/zero or /dev/urandom, a FIFO, a socket or a directory
// is refused by what it is before a byte is read, because its length is
// unknown and a read could run until memory is exhausted. A regular file
// larger than the caller's limit is refused with the limit named. Errors are
// caustica::Error reading "<path>: <what> ...".
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace caustica {

// `what` names the file's role in messages ("scene file", "PLY file"...).
std::string read_input_file(const std::string& path, const std::string& what, uint64_t limit_bytes);

// Whether `path` is a regular file (false, never an exception, where it
// cannot be inspected): what a search for a file may open.
bool is_file(const std::filesystem::path& path);

// "1 GiB", "64 MiB", "512 bytes": limits as the messages name them.
std::string format_bytes(uint64_t bytes);

}  // namespace caustica
