#include "server/metrics.hpp"

#include <cstdio>

#include "text.hpp"

namespace brdfbake::server {

namespace {}  // namespace

std::string prometheus_label(const std::string& v) {
  std::string out;
  for (char c : v) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '"')
      out += "\\\"";
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out;
}

const std::vector<double>& Metrics::bake_buckets() {
  static const std::vector<double> b = {0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60, 120, 300};
  return b;
}

void Metrics::observe_bake(const std::string& kind, double seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  Histogram& h = bakes_[kind];
  if (h.counts.empty()) h.counts.assign(bake_buckets().size(), 0);
  for (size_t i = 0; i < bake_buckets().size(); ++i)
    if (seconds <= bake_buckets()[i]) {
      ++h.counts[i];
      break;
    }
  ++h.count;
  h.sum += seconds;
}

void Metrics::count_request(int status) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++requests_[status];
}

void Metrics::count_table(bool hit) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++(hit ? table_hits_ : table_misses_);
}

std::string Metrics::render() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::string s;
  s += "# HELP brdfbake_bake_seconds Wall time of each table bake, by table kind.\n";
  s += "# TYPE brdfbake_bake_seconds histogram\n";
  for (const auto& [kind, h] : bakes_) {
    std::uint64_t cumulative = 0;
    const std::string k = prometheus_label(kind);
    for (size_t i = 0; i < bake_buckets().size(); ++i) {
      cumulative += h.counts[i];
      s += "brdfbake_bake_seconds_bucket{kind=\"" + k + "\",le=\"" + detail::fmt_number(bake_buckets()[i]) + "\"} " +
           std::to_string(cumulative) + "\n";
    }
    s += "brdfbake_bake_seconds_bucket{kind=\"" + k + "\",le=\"+Inf\"} " + std::to_string(h.count) + "\n";
    s += "brdfbake_bake_seconds_sum{kind=\"" + k + "\"} " + detail::fmt_number(h.sum) + "\n";
    s += "brdfbake_bake_seconds_count{kind=\"" + k + "\"} " + std::to_string(h.count) + "\n";
  }
  s += "# HELP brdfbake_http_requests_total HTTP requests answered, by status code.\n";
  s += "# TYPE brdfbake_http_requests_total counter\n";
  for (const auto& [code, n] : requests_)
    s += "brdfbake_http_requests_total{code=\"" + std::to_string(code) + "\"} " + std::to_string(n) + "\n";
  s += "# HELP brdfbake_tables_total Tables served by POST /v1/tables, by whether the result cache had them.\n";
  s += "# TYPE brdfbake_tables_total counter\n";
  s += "brdfbake_tables_total{cache=\"hit\"} " + std::to_string(table_hits_) + "\n";
  s += "brdfbake_tables_total{cache=\"miss\"} " + std::to_string(table_misses_) + "\n";
  return s;
}

}  // namespace brdfbake::server
