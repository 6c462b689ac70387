// One writer per output: an advisory lock (flock(2)) on a lock file beside the output, held
// for a whole run, so that a second run on the same output is refused instead of
// interleaving its records with the first's (docs/cli.md, "One run per output"). The kernel
// releases the lock when the process ends, however it ends, so a killed run resumes at once;
// the lock file it leaves behind holds nothing.
#pragma once

#include <filesystem>
#include <string>

namespace unjam {

class OutputLock {
 public:
  // Takes the lock on `lock_file` (created if missing) without waiting. Throws OutputError if
  // another process holds it (naming `output`, the lock file and that process), or if the
  // lock file cannot be created.
  OutputLock(const std::filesystem::path& lock_file, const std::string& output);
  // Releases the lock and removes the lock file.
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

}  // namespace unjam
