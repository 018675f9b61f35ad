// Internal: what the device path (brdf_eval.cpp) and the reference backend
// (reference_backend/brdf.cpp) of bulk BRDF evaluation and tabulation share.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake::detail {

// "direction pair i: <which> is zero or not finite".
std::string pair_error(std::size_t i, const char* which);
// Normalises a direction in double (largest component divided out first); false when it is zero or
// not finite.
bool unit_direction(const double* v, double* out);

// Throws Error for a spec the tabulation rejects (no materials, too many for the layout, a material
// out of range, a slice angle outside [0, pi]).
void check_tabulate_spec(const TabulateSpec& spec);
// The grid, albedo or slice table of a checked spec at a resolved resolution: axes and the layout's
// metadata, data zero.
Table make_tabulate_table(const TabulateSpec& spec, const std::vector<int>& resolution);
// The metadata every table records (model, materials, layout, resolution, precision, device, lobes,
// conventions, generator); set or replaced in `meta`.
void tabulate_metadata(Metadata& meta, const TabulateSpec& spec, const std::vector<int>& resolution,
                       const std::string& device, const std::string& precision, const std::string& lobes);
// The merl layout's description.
void merl_metadata(Metadata& meta);

// Runs body(k) for k in [0, n) on every core.
template <class Body>
void parallel_for(size_t n, Body&& body) {
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    try {
      for (size_t k = next++; k < n; k = next++) body(k);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
      next = n;
    }
  };
  const unsigned threads = std::max(1u, std::min(std::thread::hardware_concurrency(), static_cast<unsigned>(std::max<size_t>(1, n))));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}


}  // namespace brdfbake::detail
