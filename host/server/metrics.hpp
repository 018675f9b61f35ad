// Counters and histograms the server exports at GET /metrics in the Prometheus text format
// (version 0.0.4): bake time by kind, requests by status, fast-path tables. Jobs by state, queue
// lengths and device busy time are read from the job store and the scheduler when rendered.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace brdfbake::server {

class Metrics {
 public:
  // One finished bake of a table kind, in seconds of wall time.
  void observe_bake(const std::string& kind, double seconds);
  void count_request(int status);
  void count_table(bool cache_hit);

  // The exposition text of what this object holds (each family with # HELP and # TYPE lines).
  std::string render() const;

  // Bucket bounds of the bake time histogram, in seconds.
  static const std::vector<double>& bake_buckets();

 private:
  struct Histogram {
    std::vector<std::uint64_t> counts;  // per bucket, not cumulative
    std::uint64_t count = 0;
    double sum = 0;
  };
  mutable std::mutex mutex_;
  std::map<std::string, Histogram> bakes_;
  std::map<int, std::uint64_t> requests_;
  std::uint64_t table_hits_ = 0, table_misses_ = 0;
};

// A label value escaped for the exposition format (backslash, quote, newline).
std::string prometheus_label(const std::string& value);

}  // namespace brdfbake::server
