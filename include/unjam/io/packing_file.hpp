// Saved packings: the versioned, human-readable `.unjam` format (docs/format.md).
//
// Reading never crashes or hangs on bad input: every problem raises InputError naming the
// file and the line. Writing uses round-trip (shortest exact) decimal doubles, so that
// write → read gives back the same doubles bit for bit, and goes through a temporary file
// renamed into place (an interrupted run never leaves a half-written file).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "unjam/scene/scene.hpp"

namespace unjam {

// Bad user input. what() reads "FILE:LINE: message" (LINE omitted when not applicable).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, int line, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_;
  std::string message_;
};

// An output file could not be written. what() names the path and the failing step.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ReadOptions {
  // Overlap of two disks (−gap) above which the file is rejected, in length units.
  double overlap_tolerance = 1e-6;
};

Scene ReadPacking(const std::filesystem::path& path, const ReadOptions& options = {});
// Parses text already in memory; `name` is used in error messages (the fuzz entry point).
Scene ParsePacking(std::string_view text, const std::string& name, const ReadOptions& options = {});

std::string FormatPacking(const Scene& scene);
void WritePacking(const Scene& scene, const std::filesystem::path& path);

// Writes `content` to `path` through a temporary file in the same directory and a rename.
// Throws OutputError naming the path on failure; the temporary is removed.
void WriteFileAtomically(const std::filesystem::path& path, std::string_view content);

}  // namespace unjam
