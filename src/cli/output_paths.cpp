#include "output_paths.hpp"

#include <stdexcept>
#include <system_error>

namespace unjam::cli {

namespace {

// The path with `.`, `..` and the links of its existing part resolved; if even that fails
// (a component that cannot be searched), the absolute path, normalised.
// Absolute first: weakly_canonical leaves a relative path none of whose parts exists
// relative, so that `P` and `./P` would differ until P is written.
std::filesystem::path Resolved(const std::filesystem::path& p) {
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::absolute(p, error).lexically_normal();
  std::filesystem::path resolved = std::filesystem::weakly_canonical(absolute, error);
  return error ? absolute : resolved;
}

}  // namespace

bool SameFile(const std::filesystem::path& a, const std::filesystem::path& b) {
  if (Resolved(a) == Resolved(b)) return true;
  std::error_code error;  // either missing: not one file
  return std::filesystem::equivalent(a, b, error) && !error;
}

void RefuseOutputOverInput(const std::string& option, const std::filesystem::path& output,
                           const std::vector<std::filesystem::path>& inputs) {
  if (output.empty()) return;
  for (const std::filesystem::path& input : inputs) {
    if (!SameFile(output, input)) continue;
    throw std::invalid_argument(option + " " + output.string() + " is the input file " +
                                input.string() + ", which it would overwrite: choose another " +
                                option);
  }
}

void RefuseOutputDirectoryOverInput(const std::string& option, const std::filesystem::path& dir,
                                    const std::vector<std::string>& files,
                                    const std::vector<std::filesystem::path>& inputs) {
  if (dir.empty()) return;
  RefuseOutputOverInput(option, dir, inputs);
  for (const std::string& name : files) {
    for (const std::filesystem::path& input : inputs) {
      if (!SameFile(dir / name, input)) continue;
      throw std::invalid_argument(option + " " + dir.string() + " would overwrite the input file " +
                                  input.string() + " (with its " + name + "): choose another " +
                                  option);
    }
  }
}

}  // namespace unjam::cli
