// libFuzzer harness for the Siconos `.dat` reader (docs/format.md, "Fuzzing" and
// "Siconos problem format").
//
// Any input must either parse or raise InputError. Any other exception escapes and
// libFuzzer reports it as a crash, as do AddressSanitizer findings and timeouts. Accepted
// inputs are written back and re-read: the writer's output must be valid and stable.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "unjam/io/packing_file.hpp"
#include "unjam/io/siconos_problem.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  unjam::DelassusProblem problem;
  try {
    problem = unjam::ParseSiconosProblem(text, "fuzz.dat");
  } catch (const unjam::InputError&) {
    return 0;
  }
  const std::string written = unjam::FormatSiconosProblem(problem);
  // Throws (and so crashes the run) if the writer produced a file the reader rejects.
  const unjam::DelassusProblem again = unjam::ParseSiconosProblem(written, "fuzz-rewritten.dat");
  if (unjam::FormatSiconosProblem(again) != written) std::abort();
  return 0;
}
