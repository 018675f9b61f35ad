// The job parser: parse_job (JSON limits, every field, the registry's validation of each table)
// and, for a job it accepts, job_to_json read back again (the round trip must hold).
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "brdfbake/job.hpp"
#include "fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace brdfbake;
  static const bool in_empty_folder = [] {
    // Tables name files (eval's and tabulate's materials) that validation opens: relative names
    // resolve in an empty folder of our own.
    return ::chdir(fuzz::scratch_dir("job").c_str()) == 0;
  }();
  (void)in_empty_folder;
  const std::string text = fuzz::text(data, size);
  // Devices and pipes would block or never end; the harness is about the parser.
  if (text.find("/dev") != std::string::npos || text.find("/proc") != std::string::npos ||
      text.find("/sys") != std::string::npos)
    return 0;
  const auto job = fuzz::accepted([&] { return parse_job(text, "fuzz.json"); });
  if (!job) return 0;
  // What parse_job accepted prints, parses again, and prints the same: job_to_json is a fixed
  // point of parse_job.
  std::string again;
  fuzz::invariant("an accepted job prints as JSON", [&] { again = job_to_json(*job); });
  fuzz::invariant("job_to_json of an accepted job parses and prints the same", [&] {
    const Job back = parse_job(again, "round trip");
    fuzz::require(job_to_json(back) == again, "job_to_json(parse_job(job_to_json(job))) == job_to_json(job)");
  });
  return 0;
}
