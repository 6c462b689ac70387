// Advisory output locks (io/output_lock.hpp).
#include "unjam/io/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>

#include "unjam/io/packing_file.hpp"

namespace unjam {

namespace {

// Who holds the lock, as the holder wrote it in the file ("process PID on HOST"); empty if
// it cannot be read.
std::string Holder(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

// Tells a later run who holds the lock (best effort: the lock itself is what counts).
void WriteHolder(int fd) {
  char host[256] = "?";
  ::gethostname(host, sizeof host - 1);
  const std::string text = "process " + std::to_string(::getpid()) + " on " + host + "\n";
  if (::ftruncate(fd, 0) == 0) (void)!::write(fd, text.data(), text.size());
}

// True if `fd` is still the file at `path`: a holder removes the file as it releases it, so
// a lock taken on a file opened just before that removal guards nothing.
bool StillTheFile(int fd, const std::filesystem::path& path) {
  struct stat opened {};
  struct stat named {};
  return ::fstat(fd, &opened) == 0 && ::stat(path.c_str(), &named) == 0 &&
         opened.st_dev == named.st_dev && opened.st_ino == named.st_ino;
}

}  // namespace

OutputLock::OutputLock(const std::filesystem::path& lock_file, const std::string& output)
    : path_(lock_file) {
  for (;;) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd_ < 0)
      throw OutputError("cannot create the lock file '" + path_.string() + "' of " + output + ": " +
                        std::strerror(errno));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      ::close(fd_);
      if (error != EWOULDBLOCK)
        throw OutputError("cannot lock '" + path_.string() + "': " + std::strerror(error));
      const std::string holder = Holder(path_);
      throw OutputError(output + " is being written by another run (" +
                        (holder.empty() ? "a process" : holder) + " holds " + path_.string() +
                        "): two runs on one output would mix their results; wait for it to end, or "
                        "choose another output");
    }
    if (StillTheFile(fd_, path_)) break;
    ::close(fd_);
  }
  WriteHolder(fd_);
}

OutputLock::~OutputLock() {
  // Removed while still held, so that no one can lock the old file after us (StillTheFile).
  ::unlink(path_.c_str());
  ::close(fd_);
}

}  // namespace unjam
