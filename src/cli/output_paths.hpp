// Outputs that would overwrite an input: refused before any work, so that a mistyped
// command line never destroys the file it reads (docs/cli.md, "Exit codes").
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace unjam::cli {

// True if `a` and `b` name one file: the same path once `.`, `..` and symbolic links are
// resolved (std::filesystem::weakly_canonical, so `./P` is `P`), or two links to one file.
bool SameFile(const std::filesystem::path& a, const std::filesystem::path& b);

// Throws std::invalid_argument (a usage error) naming `option` if `output` is one of the
// `inputs`. An empty output (option not given) is never refused.
void RefuseOutputOverInput(const std::string& option, const std::filesystem::path& output,
                           const std::vector<std::filesystem::path>& inputs);

// The same for an output directory: refused if it is an input, or if `files` (the names
// the command writes in it) would overwrite one.
void RefuseOutputDirectoryOverInput(const std::string& option, const std::filesystem::path& dir,
                                    const std::vector<std::string>& files,
                                    const std::vector<std::filesystem::path>& inputs);

}  // namespace unjam::cli
