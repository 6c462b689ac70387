// Atomic file replacement: readers of `path` see either the old file or the complete new
// one, never a partial write, even if the process dies midway.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "unjam/io/packing_file.hpp"

namespace unjam {

namespace {

[[noreturn]] void Throw(const std::filesystem::path& path, const std::string& step, int error) {
  throw OutputError("cannot write '" + path.string() + "': " + step + ": " + std::strerror(error));
}

bool WriteAll(int fd, std::string_view content) {
  while (!content.empty()) {
    const ssize_t written = ::write(fd, content.data(), content.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    content.remove_prefix(static_cast<std::size_t>(written));
  }
  return true;
}

// Makes the rename itself durable. Best effort: some file systems refuse fsync on a
// directory, and the data is already safe in the renamed file.
void SyncDirectory(const std::filesystem::path& path) {
  const std::filesystem::path dir =
      path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

void WriteFileAtomically(const std::filesystem::path& path, std::string_view content) {
  // Same directory as the target, so that rename() never crosses file systems.
  std::filesystem::path temporary = path;
  temporary += ".tmp." + std::to_string(::getpid());
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) Throw(path, "cannot create temporary " + temporary.string(), errno);
  // The data must be on disk before the rename makes it visible under the final name.
  if (!WriteAll(fd, content) || ::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    ::unlink(temporary.c_str());
    Throw(path, "writing temporary " + temporary.string(), error);
  }
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    Throw(path, "closing temporary " + temporary.string(), error);
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    Throw(path, "renaming " + temporary.string() + " into place", error);
  }
  SyncDirectory(path);
}

}  // namespace unjam
