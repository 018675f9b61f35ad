// The error of one Fresnel table against another of the same shape (an approximation against the
// exact model), and the table with its signed error columns (`brdfbake fresnel --vs exact`).
#include <cmath>
#include <string>

#include "brdfbake/error.hpp"
#include "families/fresnel/model.hpp"

namespace brdfbake {

namespace {

void check_same_shape(const Table& a, const Table& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels || a.data.size() != b.data.size())
    throw Error("Fresnel tables of different shapes cannot be compared (" + std::to_string(a.width) + "x" +
                std::to_string(a.height) + "x" + std::to_string(a.channels.size()) + " against " +
                std::to_string(b.width) + "x" + std::to_string(b.height) + "x" + std::to_string(b.channels.size()) +
                ")");
}

}  // namespace

FresnelError fresnel_error(const Table& approx, const Table& exact) {
  check_same_shape(approx, exact);
  FresnelError e;
  double sum = 0.0;
  const int nc = approx.channel_count();
  for (int j = 0; j < approx.height; ++j)
    for (int i = 0; i < approx.width; ++i)
      for (int c = 0; c < nc; ++c) {
        const double d = std::fabs(static_cast<double>(approx.at(i, j, c)) - static_cast<double>(exact.at(i, j, c)));
        sum += d;
        if (d > e.max_abs) {
          e.max_abs = d;
          e.x_at_max = static_cast<size_t>(i) < approx.x.size() ? approx.x[static_cast<size_t>(i)] : 0.0;
          e.row_at_max = j;
          e.channel_at_max = c;
        }
      }
  if (!approx.data.empty()) e.mean_abs = sum / static_cast<double>(approx.data.size());
  return e;
}

Table with_error_columns(const Table& table, const Table& exact) {
  check_same_shape(table, exact);
  Table t = table;
  const int nc = table.channel_count();
  for (const std::string& c : table.channels) t.channels.push_back("err_" + c);
  t.data.assign(table.data.size() * 2, 0.f);
  for (int j = 0; j < table.height; ++j)
    for (int i = 0; i < table.width; ++i)
      for (int c = 0; c < nc; ++c) {
        t.at(i, j, c) = table.at(i, j, c);
        // The difference of two floats, formed in double and rounded once.
        t.at(i, j, nc + c) =
            static_cast<float>(static_cast<double>(table.at(i, j, c)) - static_cast<double>(exact.at(i, j, c)));
      }
  std::string channels;
  for (const auto& c : t.channels) channels += (channels.empty() ? "" : ",") + c;
  t.set_meta("channels", channels);
  t.set_meta("error_columns", "err_<c> = <c> - exact_<c>, signed, where exact is the " + exact.meta("model") +
                                  " model (" + exact.meta("parameters") +
                                  ") by the scalar double reference at the "
                                  "same cos_theta");
  const FresnelError e = fresnel_error(table, exact);
  t.set_meta("error_max_abs", detail::fresnel_number(e.max_abs));
  t.set_meta("error_mean_abs", detail::fresnel_number(e.mean_abs));
  return t;
}

}  // namespace brdfbake
