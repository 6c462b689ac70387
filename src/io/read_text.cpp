#include "unjam/io/read_text.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "unjam/io/packing_file.hpp"

namespace unjam {

std::string ReadInputText(const std::filesystem::path& path, std::size_t max_bytes) {
  const std::string name = path.string();
  std::FILE* file = std::fopen(name.c_str(), "rb");
  if (file == nullptr)
    throw InputError(name, 0, std::string("cannot open: ") + std::strerror(errno));
  std::string text;
  char buffer[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof(buffer), file)) > 0) {
    if (text.size() + got > max_bytes) {
      std::fclose(file);
      throw InputError(
          name, 0,
          "larger than " + std::to_string(max_bytes >> 20) + " MiB: not a file unjam reads");
    }
    text.append(buffer, got);
  }
  const bool failed = std::ferror(file) != 0;
  const int error = errno;
  std::fclose(file);
  if (failed) throw InputError(name, 0, std::string("cannot read: ") + std::strerror(error));
  return text;
}

}  // namespace unjam
