// libFuzzer harness for the `.unjam` reader (docs/format.md, "Fuzzing").
//
// Any input must either parse or raise InputError. Any other exception escapes and
// libFuzzer reports it as a crash (uncaught exception → abort), as do AddressSanitizer
// findings and timeouts. Accepted inputs are written back and re-read: what the writer
// produces from a valid scene must itself be valid and stable.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "unjam/io/packing_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  unjam::Scene scene;
  try {
    scene = unjam::ParsePacking(text, "fuzz.unjam");
  } catch (const unjam::InputError&) {
    return 0;
  }
  const std::string written = unjam::FormatPacking(scene);
  // Throws (and so crashes the run) if the writer produced a file the reader rejects.
  const unjam::Scene again = unjam::ParsePacking(written, "fuzz-rewritten.unjam");
  if (unjam::FormatPacking(again) != written) std::abort();
  return 0;
}
