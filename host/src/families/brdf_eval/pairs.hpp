// Internal: the eval family's pairs, read and written as streams (pairs.cpp): the input (a file or
// standard input, CSV or raw float32) in chunks that go through an evaluator, and the results'
// bytes. The memory of a stream stays constant whatever its length.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "brdfbake/brdf.hpp"

namespace brdfbake::detail {

// Pairs go through the evaluator in chunks of this many.
inline constexpr size_t kChunkPairs = size_t(1) << 16;
// An eval held in memory (jobs, bindings) stops here; `brdfbake eval` streams any size.
inline constexpr std::uint64_t kMaxPairsInMemory = std::uint64_t(1) << 24;

// The input: standard input ("-") or a file, read through its file descriptor with a buffer of its
// own; every wait for data checks for a stop request (brdfbake/cancel.hpp).
class PairInput {
 public:
  explicit PairInput(const std::string& path);
  ~PairInput();
  PairInput(const PairInput&) = delete;
  PairInput& operator=(const PairInput&) = delete;
  const std::string& name() const;
  struct Impl;
  Impl& impl() { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// Reads every pair of `in` (CSV with the header wi_x,...,wo_z, or float32 with `binary`), evaluates
// them in chunks and hands each chunk's f (3 a pair) to `sink`; returns the number of pairs. The
// evaluator is made (its program built) with the first chunk, after its lines were checked.
std::uint64_t stream_pairs(PairInput& in, bool binary, const std::function<PairEvaluator&()>& ev,
                           double* device_seconds, const std::function<void(const double* f, size_t count)>& sink,
                           std::uint64_t max_pairs = ~std::uint64_t(0));

// The bytes of `count` results: CSV rows (the header before the first chunk) or float32.
void format_results(const double* f, size_t count, bool binary, bool first, std::string& out);

}  // namespace brdfbake::detail
