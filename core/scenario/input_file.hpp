// Reading a user's input file (a scenario, a catalog) without surprises: only a regular file is read
// (a FIFO would block, /dev/zero never ends, a directory has no text), at most a cap of bytes, and it
// must be text (UTF-8 without NUL bytes), so a binary file is refused with a clear reason instead of a
// parser's.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace kessler {

// The largest input file read: above any request the daemon takes (--max-message-mb at most 2000).
inline constexpr std::uint64_t kMaxInputFileBytes = 2000ull << 20;

// The file's text, or nullopt with *error set ("cannot be read (No such file or directory)", "is a
// directory", "is not a regular file (a FIFO)", "is 3.1 GB, above the 2000 MB limit", "is not a text file: a
// NUL byte at offset 12", ...).
std::optional<std::string> read_input_file(const std::string& path, std::string* error,
                                           std::uint64_t max_bytes = kMaxInputFileBytes);

}  // namespace kessler
