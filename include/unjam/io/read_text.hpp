// The whole text of an input file, read with a bound: every file unjam reads (packings,
// checkpoints, Siconos problems, run records) is far below it, and a file that is not one of
// them (a device such as /dev/zero, a stray binary) fails with a message instead of growing
// memory without end.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace unjam {

inline constexpr std::size_t kMaxInputBytes = std::size_t{1} << 30;  // 1 GiB

// Throws InputError (packing_file.hpp) naming the file if it cannot be opened or read, or
// if it holds more than max_bytes.
std::string ReadInputText(const std::filesystem::path& path,
                          std::size_t max_bytes = kMaxInputBytes);

}  // namespace unjam
